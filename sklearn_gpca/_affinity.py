"""Sparse nearest-neighbour affinities between points on a union of subspaces.

Beyond the paper: instead of comparing every pair of points through the
gradients of one global polynomial (a dense but low-rank ``P x P`` kernel), each
point is compared with its ``k`` nearest neighbours only, through normal
subspaces fitted to small neighbourhoods (local subspace affinity, Yan &
Pollefeys, ECCV 2006). Points are directions (linear subspaces), so distances
are sign invariant: ``x`` and ``-x`` are the same point. Everything is
``O(P k)`` in memory; the neighbour search uses a KD-tree.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import scipy.sparse as sp
from joblib import effective_n_jobs
from sklearn.neighbors import KDTree, NearestNeighbors

from sklearn_gpca._chunks import row_chunks
from sklearn_gpca._memory import chunk_rows
from sklearn_gpca._rows import TINY
from sklearn_gpca._spectral import normal_subspace_features

# NearestNeighbors' default leaf size.
_LEAF_SIZE = NearestNeighbors().leaf_size


def sign_invariant_neighbors(
    points, n_neighbors, *, queries=None, n_jobs=None, return_distance=False
):
    """Indices of the nearest neighbours of unit vectors, up to sign.

    Parameters
    ----------
    points : ndarray of shape (n_samples, n_features)
        Unit vectors.
    n_neighbors : int
        Number of neighbours, at most ``n_samples - 1``.
    queries : ndarray of shape (n_queries, n_features), default=None
        Unit vectors whose neighbours among ``points`` are wanted; None
        queries ``points`` themselves, each excluding itself.
    n_jobs : int or None, default=None
        Parallel jobs of the search (see
        :class:`sklearn.neighbors.NearestNeighbors`).
    return_distance : bool, default=False
        With ``queries``: also return the distances.

    Returns
    -------
    distances : ndarray of shape (n_queries, n_neighbors)
        With ``return_distance`` only: ``min(||q - x_j||, ||q + x_j||)``.
    indices : ndarray of shape (n_samples or n_queries, n_neighbors), dtype=intp
        Row ``i`` lists the points ``j != i`` in increasing order of
        ``min(||x_i - x_j||, ||x_i + x_j||)``, i.e. of the angle between the
        lines through ``x_i`` and ``x_j``.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._affinity import sign_invariant_neighbors
    >>> points = np.array([[1.0, 0.0], [-0.99, 0.14], [0.0, 1.0]])
    >>> points /= np.linalg.norm(points, axis=1, keepdims=True)
    >>> sign_invariant_neighbors(points, 1).ravel()
    array([1, 0, 1])
    """
    n_samples = points.shape[0]
    both = np.vstack([points, -points])
    if queries is not None:
        distances, found = _kneighbors(both, queries, n_neighbors, n_jobs)
        found %= n_samples
        return (distances, found) if return_distance else found
    _, found = _kneighbors(both, points, min(n_neighbors + 2, 2 * n_samples), n_jobs)
    found = found % n_samples
    # drop the point itself and its antipode, keep the first n_neighbors others
    keep = found != np.arange(n_samples)[:, None]
    order = np.argsort(~keep, axis=1, kind="stable")
    return np.take_along_axis(found, order, axis=1)[:, :n_neighbors]


def _kneighbors(points, queries, n_neighbors, n_jobs):
    """``NearestNeighbors(n_neighbors=n_neighbors, n_jobs=n_jobs).fit(points)
    .kneighbors(queries)``.

    Where that would query a KD-tree in one job (few features, few
    neighbours), the tree is built and queried directly, with the same leaf
    size: the same neighbours and distances without the estimator's fixed
    costs (validation, parameter checks, a joblib dispatch), which are most
    of the search on a few hundred points.
    """
    n_points, n_features = points.shape
    # NearestNeighbors(algorithm="auto") picks a KD-tree exactly then
    kd_tree = n_features <= 15 and n_neighbors < n_points // 2
    if kd_tree and effective_n_jobs(n_jobs) == 1:
        tree = KDTree(points, leaf_size=_LEAF_SIZE)
        return tree.query(queries, k=n_neighbors)
    search = NearestNeighbors(n_neighbors=n_neighbors, n_jobs=n_jobs).fit(points)
    return search.kneighbors(queries)


def normal_affinity_graph(bases, codims, neighbors, power):
    """Sparse symmetric affinity ``(tr(P_i P_j) / max(c_i, c_j))^power``.

    Parameters
    ----------
    bases : ndarray of shape (n_samples, n_features, n_features)
        Orthonormal normal bases, zero-padded (see :func:`local_normal_bases`).
    codims : ndarray of shape (n_samples,)
        Number of non-zero columns of each basis.
    neighbors : ndarray of shape (n_samples, n_neighbors)
        Graph edges ``i -> neighbors[i]``.
    power : int
        Exponent ``q``; for hyperplanes the weight is ``cos^(2q)`` of the angle
        between the normals.

    Returns
    -------
    affinity : scipy.sparse.csr_matrix of shape (n_samples, n_samples)
        Symmetrised with the entrywise maximum; ``O(n_samples * n_neighbors)``
        stored entries. The edges are weighted in chunks, so the temporaries
        stay within scikit-learn's ``working_memory``.
    """
    n_samples, n_neighbors = neighbors.shape
    rows = np.repeat(np.arange(n_samples), n_neighbors)
    cols = neighbors.ravel()
    # tr(P_i P_j) = <phi_i, phi_j> with phi the upper triangle of P_i = N_i N_i^T
    features = normal_subspace_features(bases)
    traces = np.empty(rows.size)
    # the features of both ends of a chunk of edges fit in working_memory
    for edges in row_chunks(rows.size, chunk_rows(2 * features[0].nbytes)):
        traces[edges] = np.einsum(
            "ed,ed->e", features[rows[edges]], features[cols[edges]]
        )
    traces = np.maximum(traces, 0.0)
    weights = (traces / np.maximum(codims[rows], codims[cols])) ** power
    affinity = sp.csr_matrix((weights, (rows, cols)), shape=(n_samples, n_samples))
    return affinity.maximum(affinity.T).tocsr()


def _between_cluster_weights(affinity, labels, n_clusters):
    """``C[a, b] = sum of A_ij over i in cluster a, j in cluster b``."""
    # one pass over the stored entries: O(nnz + n_clusters^2)
    graph = sp.csr_matrix(affinity) if affinity.format != "csr" else affinity
    rows = np.repeat(np.arange(graph.shape[0]), np.diff(graph.indptr))
    pairs = labels[rows] * n_clusters + labels[graph.indices]
    weights = np.bincount(pairs, weights=graph.data, minlength=n_clusters**2)
    return weights.reshape(n_clusters, n_clusters)


def normalized_cut(affinity, labels, n_clusters):
    """Normalised cut ``sum_k cut(C_k, rest) / vol(C_k)`` of a labelling.

    Parameters
    ----------
    affinity : scipy.sparse matrix of shape (n_samples, n_samples)
        Symmetric non-negative affinity.
    labels : ndarray of shape (n_samples,)
        Labels in ``0 .. n_clusters - 1``.
    n_clusters : int
        Number of clusters.

    Returns
    -------
    ncut : float
        Between 0 (no edge between clusters) and ``n_clusters``; ``inf`` if
        a cluster has zero volume. ``O(n_samples * n_neighbors)``.

    Examples
    --------
    >>> import numpy as np
    >>> import scipy.sparse as sp
    >>> from sklearn_gpca._affinity import normalized_cut
    >>> A = sp.csr_matrix(np.array([[0, 1, 0], [1, 0, 1], [0, 1, 0]], float))
    >>> float(normalized_cut(A, np.array([0, 0, 1]), 2))
    1.333...
    """
    weights = _between_cluster_weights(affinity, labels, n_clusters)
    volumes = weights.sum(axis=1)
    if np.any(volumes <= 0):
        return np.inf
    return float(np.sum((volumes - np.diag(weights)) / volumes))


def merge_clusters(affinity, labels, n_clusters):
    """Greedily merge clusters until ``n_clusters`` remain.

    At each step the pair ``(a, b)`` with the largest normalised association
    ``cut(a, b) / min(vol(a), vol(b))`` on the graph is merged: a cluster that
    is mostly connected to another one is part of it. Used to recover a small
    subspace that spectral clustering with ``n_clusters`` would have merged
    with part of a large one: over-segment into more clusters, then merge.

    Parameters
    ----------
    affinity : scipy.sparse matrix of shape (n_samples, n_samples)
        Symmetric non-negative affinity.
    labels : ndarray of shape (n_samples,)
        Labels in ``0 .. m - 1`` with ``m >= n_clusters``.
    n_clusters : int
        Number of clusters to keep.

    Returns
    -------
    labels : ndarray of shape (n_samples,), dtype=intp
        Labels in ``0 .. n_clusters - 1``.
    """
    _, labels = np.unique(labels, return_inverse=True)
    labels = labels.astype(np.intp)
    weights = _between_cluster_weights(affinity, labels, labels.max() + 1)
    groups = [[k] for k in range(weights.shape[0])]
    while len(groups) > n_clusters:
        volumes = weights.sum(axis=1)
        association = weights / np.maximum(
            np.minimum(volumes[:, None], volumes[None, :]), TINY
        )
        np.fill_diagonal(association, -np.inf)
        a, b = np.unravel_index(np.argmax(association), association.shape)
        a, b = min(a, b), max(a, b)
        weights[a] += weights[b]
        weights[:, a] += weights[:, b]
        weights = np.delete(np.delete(weights, b, axis=0), b, axis=1)
        groups[a] += groups.pop(b)
    mapping = np.empty(sum(len(g) for g in groups), dtype=np.intp)
    for new, group in enumerate(groups):
        mapping[group] = new
    return mapping[labels]
