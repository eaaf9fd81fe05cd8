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
from scipy.sparse.linalg import ArpackNoConvergence, eigsh, lobpcg
from sklearn.neighbors import NearestNeighbors

from sklearn_gpca._spectral import normal_subspace_features

_TINY = np.finfo(np.float64).tiny


def sign_invariant_neighbors(points, n_neighbors, *, queries=None, n_jobs=None):
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

    Returns
    -------
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
    if queries is not None:
        tree = NearestNeighbors(n_neighbors=n_neighbors, n_jobs=n_jobs)
        tree.fit(np.vstack([points, -points]))
        return tree.kneighbors(queries, return_distance=False) % n_samples
    tree = NearestNeighbors(
        n_neighbors=min(n_neighbors + 2, 2 * n_samples), n_jobs=n_jobs
    )
    tree.fit(np.vstack([points, -points]))
    _, found = tree.kneighbors(points)
    found = found % n_samples
    # drop the point itself and its antipode, keep the first n_neighbors others
    keep = found != np.arange(n_samples)[:, None]
    order = np.argsort(~keep, axis=1, kind="stable")
    return np.take_along_axis(found, order, axis=1)[:, :n_neighbors]


def local_normal_bases(points, neighbors, rank_tol):
    """Normal subspace of a hyperplane (or lower subspace) fitted at each point.

    Parameters
    ----------
    points : ndarray of shape (n_samples, n_features)
        Unit vectors.
    neighbors : ndarray of shape (n_samples, n_local)
        Neighbours of each point (from :func:`sign_invariant_neighbors`).
    rank_tol : float
        Relative threshold on singular values. With ``s_1 >= ... >= s_K`` the
        singular values of the ``(n_local + 1, K)`` matrix of the point and its
        neighbours, direction ``l >= 3`` is a normal direction when ``s_l <=
        rank_tol * s_2`` (``s_1`` is the radial direction of the patch, ``s_2``
        its widest tangent direction); the last direction always is. Zero keeps
        exactly one normal (hyperplanes).

    Returns
    -------
    bases : ndarray of shape (n_samples, n_features, n_features)
        ``bases[i][:, l]`` for ``l < codims[i]`` is an orthonormal basis of the
        estimated normal subspace at point ``i``, smallest singular value
        first; the remaining columns are zero.
    codims : ndarray of shape (n_samples,), dtype=intp
        Estimated codimension of the local subspace, ``>= 1``.
    """
    n_features = points.shape[1]
    patches = np.concatenate([points[:, None, :], points[neighbors]], axis=1)
    _, values, vt = np.linalg.svd(patches, full_matrices=True)
    # vt rows sorted by decreasing singular value; pad missing values with 0
    values = np.pad(values, ((0, 0), (0, n_features - values.shape[1])))
    reference = values[:, min(1, n_features - 1)][:, None]
    small = values <= rank_tol * reference
    small[:, : min(2, n_features - 1)] = False
    small[:, -1] = True
    codims = np.count_nonzero(small, axis=1).astype(np.intp)
    normals = vt[:, ::-1, :].transpose(0, 2, 1)  # columns: smallest first
    bases = np.where(np.arange(n_features) < codims[:, None, None], normals, 0.0)
    return bases, codims


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
        stored entries.
    """
    n_samples, n_neighbors = neighbors.shape
    rows = np.repeat(np.arange(n_samples), n_neighbors)
    cols = neighbors.ravel()
    # tr(P_i P_j) = <phi_i, phi_j> with phi the upper triangle of P_i = N_i N_i^T
    features = normal_subspace_features(bases)
    traces = np.maximum(np.einsum("ed,ed->e", features[rows], features[cols]), 0.0)
    weights = (traces / np.maximum(codims[rows], codims[cols])) ** power
    affinity = sp.csr_matrix((weights, (rows, cols)), shape=(n_samples, n_samples))
    return affinity.maximum(affinity.T).tocsr()


def spectral_embedding_sparse(affinity, n_components, random_state):
    """Ng-Jordan-Weiss embedding of a sparse non-negative affinity.

    Leading eigenvectors of ``D^{-1/2} A D^{-1/2}`` by ARPACK (Lanczos; LOBPCG
    if it does not converge), rows scaled to unit norm. Isolated points get a
    zero row. The columns are in decreasing order of eigenvalue, so the first
    ``m`` columns of an embedding with more components are the embedding with
    ``m`` components before row scaling.

    Parameters
    ----------
    affinity : scipy.sparse matrix of shape (n_samples, n_samples)
        Symmetric non-negative affinity.
    n_components : int
        Number of eigenvectors, ``< n_samples``.
    random_state : RandomState instance
        Draws the Lanczos start vector.

    Returns
    -------
    embedding : ndarray of shape (n_samples, n_components)
    """
    vectors = leading_eigenvectors(affinity, n_components, random_state)
    return _unit_rows(vectors)


def _unit_rows(vectors):
    norms = np.linalg.norm(vectors, axis=1, keepdims=True)
    return vectors / np.maximum(norms, _TINY)


def leading_eigenvectors(affinity, n_components, random_state):
    """Leading eigenvectors of ``D^{-1/2} A D^{-1/2}``, largest first.

    See :func:`spectral_embedding_sparse`, which scales their rows.
    """
    n_samples = affinity.shape[0]
    degrees = np.asarray(affinity.sum(axis=1)).ravel()
    inv_sqrt = 1.0 / np.sqrt(np.maximum(degrees, _TINY))
    scaling = sp.diags(inv_sqrt)
    normalized = scaling @ affinity @ scaling
    start = random_state.uniform(-1, 1, n_samples)
    try:
        values, vectors = eigsh(normalized, k=n_components, which="LA", v0=start)
    except ArpackNoConvergence:
        # clustered leading eigenvalues (a graph with many components): LOBPCG
        # from a random block, still O(n_samples * n_neighbors) per iteration
        block = random_state.standard_normal((n_samples, n_components))
        values, vectors = lobpcg(normalized, block, largest=True, tol=1e-8, maxiter=500)
    # leading first
    vectors = vectors[:, np.argsort(values)[::-1]]
    vectors[degrees <= 0] = 0.0
    return vectors


def _between_cluster_weights(affinity, labels, n_clusters):
    """``C[a, b] = sum of A_ij over i in cluster a, j in cluster b``."""
    n_samples = labels.shape[0]
    indicator = sp.csr_matrix(
        (np.ones(n_samples), (np.arange(n_samples), labels)),
        shape=(n_samples, n_clusters),
    )
    return (indicator.T @ affinity @ indicator).toarray()


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
            np.minimum(volumes[:, None], volumes[None, :]), _TINY
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
