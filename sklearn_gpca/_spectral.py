"""Spectral clustering for low-rank affinities ``S = Phi Phi^T``.

The GPCA similarity of Vidal & Hartley (CVPR 2004, section 2.2.3) is
``S_ij = cos^2(theta_ij) = (n_i . n_j)^2`` for unit normals ``n_i``. Since
``(n_i . n_j)^2 = <vec(n_i n_i^T), vec(n_j n_j^T)>``, ``S = Phi Phi^T`` with
``Phi`` of shape ``(P, K(K + 1) / 2)``. The Ng-Jordan-Weiss algorithm then runs
without ever forming the ``P x P`` affinity: the degrees are ``Phi (Phi^T 1)``
and the leading eigenvectors of ``D^{-1/2} S D^{-1/2}`` are the leading left
singular vectors of ``D^{-1/2} Phi``.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
from sklearn.cluster import KMeans

_TINY = np.finfo(np.float64).tiny


def normal_subspace_features(normals):
    """Feature map ``Phi`` whose inner products are ``tr(P_i P_j)``.

    Parameters
    ----------
    normals : ndarray of shape (n_samples, n_features) or \
            (n_samples, n_features, n_normals)
        Unit normal ``n_i`` of each point, or an orthonormal basis ``N_i`` of
        each point's normal subspace (columns).

    Returns
    -------
    features : ndarray of shape (n_samples, n_features * (n_features + 1) // 2)
        Upper-triangular entries of ``P_i = N_i N_i^T``, off-diagonal entries
        multiplied by ``sqrt(2)``, so that ``features @ features.T`` equals
        ``tr(P_i P_j)``; for unit normals that is ``cos^2`` of their angle.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._spectral import normal_subspace_features
    >>> normals = np.array([[1.0, 0.0], [np.sqrt(0.5), np.sqrt(0.5)]])
    >>> phi = normal_subspace_features(normals)
    >>> np.round(phi @ phi.T, 3)
    array([[1. , 0.5],
           [0.5, 1. ]])
    """
    normals = np.asarray(normals, dtype=np.float64)
    if normals.ndim == 2:
        normals = normals[:, :, None]
    rows, cols = np.triu_indices(normals.shape[1])
    weights = np.where(rows == cols, 1.0, np.sqrt(2.0))
    products = np.einsum("pdj,pdj->pd", normals[:, rows], normals[:, cols])
    return products * weights


def _normalize_rows(vectors):
    norms = np.linalg.norm(vectors, axis=1, keepdims=True)
    return vectors / np.maximum(norms, _TINY)


def spectral_embedding_lowrank(features, n_components):
    """Ng-Jordan-Weiss embedding of the affinity ``features @ features.T``.

    Parameters
    ----------
    features : ndarray of shape (n_samples, n_dims)
        Factor ``Phi`` of the affinity ``S = Phi Phi^T``; ``S`` must be
        entrywise non-negative (true for :func:`normal_subspace_features`).
    n_components : int
        Number of leading eigenvectors kept; at most ``n_dims`` are available
        since ``rank(S) <= n_dims``.

    Returns
    -------
    embedding : ndarray of shape (n_samples, min(n_components, n_dims))
        Leading eigenvectors of ``D^{-1/2} S D^{-1/2}``, rows scaled to unit
        norm. Time and memory are ``O(n_samples * n_dims^2)``.
    """
    features = np.asarray(features, dtype=np.float64)
    degrees = features @ features.sum(axis=0)
    # A point with zero degree is isolated: its row stays zero.
    scaled = features / np.sqrt(np.maximum(degrees, _TINY))[:, None]
    left, _, _ = np.linalg.svd(scaled, full_matrices=False)
    left = left[:, :n_components]
    left[degrees <= 0] = 0.0
    return _normalize_rows(left)


def _assign_labels(embedding, n_clusters, n_init, random_state):
    if n_clusters == 1:
        return np.zeros(embedding.shape[0], dtype=np.intp)
    kmeans = KMeans(n_clusters=n_clusters, n_init=n_init, random_state=random_state)
    return kmeans.fit_predict(embedding).astype(np.intp)


def spectral_clustering_lowrank(features, n_clusters, *, n_init=10, random_state=None):
    """Spectral clustering (Ng-Jordan-Weiss) of ``S = features @ features.T``.

    Parameters
    ----------
    features : ndarray of shape (n_samples, n_dims)
        Factor ``Phi`` of a non-negative affinity.
    n_clusters : int
        Number of clusters.
    n_init : int, default=10
        Number of k-means restarts.
    random_state : int, RandomState instance or None, default=None
        Seeds k-means.

    Returns
    -------
    labels : ndarray of shape (n_samples,), dtype=intp
        Cluster labels in ``0 .. n_clusters - 1``.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._spectral import (
    ...     normal_subspace_features, spectral_clustering_lowrank)
    >>> normals = np.repeat(np.eye(3), 4, axis=0)
    >>> phi = normal_subspace_features(normals)
    >>> spectral_clustering_lowrank(phi, 3, random_state=0).reshape(3, 4).std(1)
    array([0., 0., 0.])
    """
    embedding = spectral_embedding_lowrank(features, n_clusters)
    return _assign_labels(embedding, n_clusters, n_init, random_state)
