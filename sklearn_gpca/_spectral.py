"""Spectral clustering for low-rank affinities ``S = Phi Phi^T``.

The GPCA similarity of Vidal & Hartley (CVPR 2004, section 2.2.3) is
``S_ij = cos^2(theta_ij) = (n_i . n_j)^2`` for unit normals ``n_i``. Since
``(n_i . n_j)^2 = <vec(n_i n_i^T), vec(n_j n_j^T)>``, ``S = Phi Phi^T`` with
``Phi`` of shape ``(P, K(K + 1) / 2)``. The Ng-Jordan-Weiss algorithm then runs
without ever forming the ``P x P`` affinity: the degrees are ``Phi (Phi^T 1)``
and the leading eigenvectors of ``D^{-1/2} S D^{-1/2}`` are the leading left
singular vectors of ``D^{-1/2} Phi``. The same embedding of a sparse
nearest-neighbour affinity comes from Lanczos iterations (shift-invert
Lanczos on a dense factorisation for a few hundred points); both are turned
into labels by k-means on the unit rows of the eigenvectors.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import scipy.sparse as sp
from scipy.linalg import blas, lapack
from scipy.sparse.linalg import ArpackNoConvergence, LinearOperator, eigsh, lobpcg

from sklearn_gpca._chunks import row_chunks
from sklearn_gpca._kmeans import kmeans_labels
from sklearn_gpca._memory import chunk_rows
from sklearn_gpca._rows import TINY, unit_rows
from sklearn_gpca._threads import one_thread

# k-means runs on a few thousand rows of a few eigenvectors, dozens of times
# per fit: one OpenMP thread is faster than the default pool, ten times so on
# a busy machine (benchmarks/results/occlusion.md, measured both ways).
LIMIT_KMEANS_THREADS = True

# Up to this many points, the leading eigenvectors of a sparse affinity come
# from shift-invert Lanczos on a dense Cholesky factorisation: its ``n^3 / 3``
# flops cost less than the hundred-odd restarted Lanczos products that the
# clustered leading eigenvalues of such graphs need (eigenvalue 1 once per
# connected component, the next ones often within 1e-3 of it). Measured with
# one BLAS thread on GPCAClustering's graphs: 2-3.5x faster at 100-500 points
# (the 120 occluded Hopkins155 sequences), 1.5-3x slower at 833 points
# (make_motions data).
DENSE_EIGEN_SAMPLES = 600
# The shift sigma = 1 + _SHIFT lies just above the spectrum of
# D^{-1/2} A D^{-1/2}, contained in [-1, 1]: sigma I - D^{-1/2} A D^{-1/2} is
# positive definite with condition number at most (2 + _SHIFT) / _SHIFT, and
# the eigenvalues closest to sigma are the leading ones.
_SHIFT = 1e-3


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
        Computed in chunks of points whose temporaries fit in scikit-learn's
        ``working_memory``.

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
    n_samples, n_features, n_columns = normals.shape
    rows, cols = np.triu_indices(n_features)
    weights = np.where(rows == cols, 1.0, np.sqrt(2.0))
    features = np.empty((n_samples, rows.size))
    # both gathered factors of a chunk of points fit in working_memory
    for chunk in row_chunks(n_samples, chunk_rows(2 * 8 * rows.size * n_columns)):
        part = normals[chunk]
        features[chunk] = np.einsum("pdj,pdj->pd", part[:, rows], part[:, cols])
    return features * weights


def lowrank_eigenvectors(features, n_components):
    """Leading eigenvectors of ``D^{-1/2} S D^{-1/2}``, ``S = features @ features.T``.

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
    vectors : ndarray of shape (n_samples, min(n_components, n_dims))
        The leading left singular vectors of ``D^{-1/2} Phi``, largest first;
        zero rows for isolated points (zero degree). Time and memory are
        ``O(n_samples * n_dims^2)``; the ``P x P`` matrix is never formed.
    """
    features = np.asarray(features, dtype=np.float64)
    degrees = features @ features.sum(axis=0)
    # A point with zero degree is isolated: its row stays zero.
    scaled = features / np.sqrt(np.maximum(degrees, TINY))[:, None]
    left, _, _ = np.linalg.svd(scaled, full_matrices=False)
    left = left[:, :n_components]
    left[degrees <= 0] = 0.0
    return left


def leading_eigenvectors(affinity, n_components, random_state):
    """Leading eigenvectors of ``D^{-1/2} A D^{-1/2}`` for a sparse affinity.

    Shift-invert Lanczos on a dense Cholesky factorisation up to
    ``DENSE_EIGEN_SAMPLES`` points, with one BLAS thread (a second one only
    waits at barriers in these small products and factorisations: 1.4x the
    wall time with the default two threads on a busy machine); beyond,
    restarted Lanczos (ARPACK) on the sparse matrix, and LOBPCG when that does
    not converge.

    Parameters
    ----------
    affinity : scipy.sparse matrix of shape (n_samples, n_samples)
        Symmetric non-negative affinity.
    n_components : int
        Number of eigenvectors, ``< n_samples``.
    random_state : RandomState instance
        Draws the Lanczos start vector (the same draws on every route).

    Returns
    -------
    vectors : ndarray of shape (n_samples, n_components)
        Largest eigenvalue first, so the first ``m`` columns span the
        ``m``-eigenvector space; zero rows for isolated points.
    """
    n_samples = affinity.shape[0]
    degrees = np.asarray(affinity.sum(axis=1)).ravel()
    inv_sqrt = 1.0 / np.sqrt(np.maximum(degrees, TINY))
    start = random_state.uniform(-1, 1, n_samples)
    found = None
    if n_samples <= DENSE_EIGEN_SAMPLES:
        normalized = affinity.toarray()
        normalized *= inv_sqrt[:, None]
        normalized *= inv_sqrt
        with one_thread("blas"):
            found = _shift_invert_eigenpairs(normalized, n_components, start)
    if found is None:
        scaling = sp.diags(inv_sqrt)
        normalized = scaling @ affinity @ scaling
        found = _lanczos_eigenpairs(normalized, n_components, start, random_state)
    values, vectors = found
    # leading first
    vectors = vectors[:, np.argsort(values)[::-1]]
    vectors[degrees <= 0] = 0.0
    return vectors


def _lanczos_eigenpairs(normalized, n_components, start, random_state):
    """Largest eigenpairs of a sparse symmetric matrix by restarted Lanczos
    (ARPACK), or LOBPCG when it does not converge."""
    try:
        return eigsh(normalized, k=n_components, which="LA", v0=start)
    except ArpackNoConvergence:
        # clustered leading eigenvalues (a graph with many components): LOBPCG
        # from a random block, still O(n_samples * n_neighbors) per iteration
        block = random_state.standard_normal((normalized.shape[0], n_components))
        return lobpcg(normalized, block, largest=True, tol=1e-8, maxiter=500)


def _shift_invert_eigenpairs(normalized, n_components, start):
    """Largest eigenpairs of a dense ``M = D^{-1/2} A D^{-1/2}`` by
    shift-invert Lanczos.

    Lanczos on ``(M - sigma I)^{-1}`` with ``sigma`` just above the spectrum
    maps the clustered leading eigenvalues ``lambda`` to well separated ones
    ``1 / (lambda - sigma)``: a few dozen products, each two triangular solves
    with the Cholesky factor of ``sigma I - M``. Overwrites ``normalized``;
    returns None when the factorisation or ARPACK fails.
    """
    sigma = 1.0 + _SHIFT
    system = np.negative(normalized, out=normalized)
    system[np.diag_indices_from(system)] += sigma
    # sigma I - M = R^T R, R upper triangular
    factor, info = lapack.dpotrf(system, lower=0, overwrite_a=1)
    if info != 0:
        return None

    def solve(x):
        # (M - sigma I)^{-1} x = -R^{-1} R^{-T} x; two BLAS triangular solves
        # cost a third of scipy.linalg.cho_solve's call overhead at this size
        y = blas.dtrsv(factor, np.asarray(x, dtype=np.float64).ravel(), trans=1)
        return -blas.dtrsv(factor, y, overwrite_x=1)

    inverse = LinearOperator(system.shape, matvec=solve, dtype=np.float64)
    try:
        # in shift-invert mode eigsh only applies OPinv; its first argument
        # gives the shape
        return eigsh(
            inverse,
            k=n_components,
            sigma=sigma,
            which="LM",
            OPinv=inverse,
            v0=start,
        )
    except ArpackNoConvergence:
        return None


def embedding_kmeans(vectors, n_clusters, *, n_init, random_state):
    """Labels from eigenvectors: k-means on their unit rows (Ng, Jordan & Weiss).

    Parameters
    ----------
    vectors : ndarray of shape (n_samples, n_components)
        Leading eigenvectors of a normalised affinity.
    n_clusters : int
        Number of clusters.
    n_init : int
        Number of k-means runs with different centroid seeds.
    random_state : int, RandomState instance or None
        Seeds k-means.

    Returns
    -------
    labels : ndarray of shape (n_samples,), dtype=intp

    Notes
    -----
    k-means runs with one OpenMP thread (``LIMIT_KMEANS_THREADS``).
    """
    if n_clusters == 1:
        return np.zeros(vectors.shape[0], dtype=np.intp)
    X = unit_rows(vectors)
    if not LIMIT_KMEANS_THREADS:
        return kmeans_labels(X, n_clusters, n_init=n_init, random_state=random_state)
    with one_thread("openmp"):
        return kmeans_labels(X, n_clusters, n_init=n_init, random_state=random_state)


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
    vectors = lowrank_eigenvectors(features, n_clusters)
    return embedding_kmeans(
        vectors, n_clusters, n_init=n_init, random_state=random_state
    )
