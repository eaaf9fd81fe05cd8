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
from scipy.sparse.linalg import eigsh
from sklearn.neighbors import NearestNeighbors

_TINY = np.finfo(np.float64).tiny


def sign_invariant_neighbors(points, n_neighbors):
    """Indices of the nearest neighbours of unit vectors, up to sign.

    Parameters
    ----------
    points : ndarray of shape (n_samples, n_features)
        Unit vectors.
    n_neighbors : int
        Number of neighbours, at most ``n_samples - 1``.

    Returns
    -------
    indices : ndarray of shape (n_samples, n_neighbors), dtype=intp
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
    tree = NearestNeighbors(n_neighbors=min(n_neighbors + 2, 2 * n_samples))
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
    # tr(P_i P_j) = ||N_i^T N_j||_F^2
    overlap = np.einsum("eka,ekb->eab", bases[rows], bases[cols])
    traces = np.einsum("eab,eab->e", overlap, overlap)
    weights = (traces / np.maximum(codims[rows], codims[cols])) ** power
    affinity = sp.csr_matrix((weights, (rows, cols)), shape=(n_samples, n_samples))
    return affinity.maximum(affinity.T).tocsr()


def spectral_embedding_sparse(affinity, n_components, random_state):
    """Ng-Jordan-Weiss embedding of a sparse non-negative affinity.

    Leading eigenvectors of ``D^{-1/2} A D^{-1/2}`` by ARPACK (Lanczos), rows
    scaled to unit norm. Isolated points get a zero row.

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
    n_samples = affinity.shape[0]
    degrees = np.asarray(affinity.sum(axis=1)).ravel()
    inv_sqrt = 1.0 / np.sqrt(np.maximum(degrees, _TINY))
    scaling = sp.diags(inv_sqrt)
    normalized = scaling @ affinity @ scaling
    start = random_state.uniform(-1, 1, n_samples)
    _, vectors = eigsh(normalized, k=n_components, which="LA", v0=start)
    vectors[degrees <= 0] = 0.0
    norms = np.linalg.norm(vectors, axis=1, keepdims=True)
    return vectors / np.maximum(norms, _TINY)
