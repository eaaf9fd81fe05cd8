"""Randomized voting: co-membership votes of many K-subspaces runs.

Beyond the paper (issue 16), after Jung, Ju & Kim, "Rigid Motion Segmentation
using Randomized Voting" (CVPR 2014). Each run starts from ``n`` subspaces,
each spanned by a random point and ``d - 1`` of its nearest neighbours (a
minimal local sample, most often from one subspace), and runs a few plain
K-subspaces rounds. A run votes for every pair of points it puts together.
The vote matrix ``V = B B^T``, with ``B`` the ``P x (R n)`` one-hot matrix of
the ``R`` runs' labels, is low rank: its spectral clustering, and the
normalised cut of any labelling on it, cost ``O(P R n)`` and never form the
``P x P`` matrix. All runs advance together (batched over runs): no Python
loop over runs or points.

The vote graph is only as informative as the runs agree. Its confidence
(:func:`vote_confidence`) is the mean of the eigenvalues ``2 .. n`` of the
normalised vote matrix, one minus the spectral lower bound on its smallest
``n``-way normalised cut relative to chance (``n - 1``): near 1 when the runs
reach one segmentation, small when each run splits the points its own way.
"""

# SPDX-License-Identifier: BSD-3-Clause

import math

import numpy as np
import scipy.linalg
import scipy.sparse as sp

from sklearn_gpca._chunks import row_chunks
from sklearn_gpca._threads import one_thread

# Fit/assign rounds of each voting run after its first assignment (not tuned:
# plain K-subspaces settles within a few rounds).
VOTING_ROUNDS = 5


def _batched_normals(scatter, dim):
    """Orthonormal complements (``K - dim`` columns) of the leading ``dim``
    eigenvectors of each scatter matrix, shape (..., K, K - dim)."""
    _, vectors = np.linalg.eigh(scatter)
    return vectors[..., : scatter.shape[-1] - dim]


def _nearest(unit, normals):
    """Index of the nearest subspace of each run, shape (P, R).

    The squared sine distance to subspace ``k`` of run ``r`` is
    ``||N_rk^T x||^2`` with ``N_rk`` its orthonormal complement.
    """
    n_runs, n_clusters, n_features, codim = normals.shape
    # (K, n, R, codim): each cluster's block of columns is contiguous
    flat = normals.transpose(2, 1, 0, 3).reshape(n_features, -1)
    labels = np.empty((unit.shape[0], n_runs), dtype=np.intp)
    width = n_runs * codim
    for rows in row_chunks(unit.shape[0], max(1, 2**22 // max(flat.shape[1], 1))):
        proj = unit[rows] @ flat
        proj *= proj
        best = proj[:, :width].reshape(-1, n_runs, codim).sum(axis=2)
        chunk = np.zeros(best.shape, dtype=np.intp)
        for k in range(1, n_clusters):
            dist = proj[:, k * width : (k + 1) * width]
            dist = dist.reshape(-1, n_runs, codim).sum(axis=2)
            closer = dist < best
            best[closer] = dist[closer]
            chunk[closer] = k
        labels[rows] = chunk
    return labels


def _scatters(outer, labels, n_clusters):
    """Scatter matrix and size of every cluster of every run.

    ``outer`` holds the flattened ``x_i x_i^T`` (shape (P, K^2)); the sparse
    ``P x (R n)`` indicator of the memberships (``R`` entries a row) sums
    them in ``O(P R K^2)``. Returns shapes (R, n, K, K) and (R, n).
    """
    n_samples, n_runs = labels.shape
    n_features = math.isqrt(outer.shape[1])
    columns = (labels + n_clusters * np.arange(n_runs)).ravel()
    indicator = sp.csr_matrix(
        (np.ones(columns.size), columns, np.arange(0, columns.size + 1, n_runs)),
        shape=(n_samples, n_runs * n_clusters),
    )
    counts = np.bincount(columns, minlength=n_runs * n_clusters)
    scatter = (indicator.T @ outer).reshape(n_runs, n_clusters, n_features, n_features)
    return scatter, counts.reshape(n_runs, n_clusters)


def voting_runs(unit, n_clusters, neighbors, *, n_runs, dim, n_iter, random_state):
    """Labels of ``n_runs`` K-subspaces runs from random minimal local samples.

    Parameters
    ----------
    unit : ndarray of shape (n_samples, n_features)
        Unit points.
    n_clusters : int
        Number of subspaces per run.
    neighbors : ndarray of shape (n_samples, n_local)
        Nearest neighbours of each point. A run's subspace ``k`` is first the
        span of a random point and ``min(dim, n_local + 1) - 1`` of its
        neighbours drawn at random among these.
    n_runs : int
        Number of runs ``R``.
    dim : int
        Dimension of the subspaces fitted after the first assignment,
        ``< n_features``.
    n_iter : int
        Number of fit/assign rounds after the first assignment.
    random_state : RandomState instance
        Draws the samples.

    Returns
    -------
    labels : ndarray of shape (n_samples, n_runs), dtype=intp
        Label of each point in each run.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._voting import voting_runs
    >>> from sklearn_gpca.stages import sign_invariant_neighbors, unit_rows
    >>> rng = np.random.RandomState(0)
    >>> # two planes of R^3: z = 0 and x = 0
    >>> unit = unit_rows(np.vstack([rng.randn(20, 3) * [1, 1, 0],
    ...                             rng.randn(20, 3) * [0, 1, 1]]))
    >>> neighbors = sign_invariant_neighbors(unit, 3)
    >>> labels = voting_runs(unit, 2, neighbors, n_runs=5, dim=2, n_iter=3,
    ...                      random_state=rng)
    >>> labels.shape
    (40, 5)
    """
    n_samples = unit.shape[0]
    n_local = neighbors.shape[1]
    size = min(dim, n_local + 1)
    seeds = random_state.randint(n_samples, size=(n_runs, n_clusters))
    # size - 1 distinct neighbours among the n_local nearest of each seed
    picks = np.argsort(random_state.rand(n_runs, n_clusters, n_local), axis=2)
    chosen = np.take_along_axis(neighbors[seeds], picks[..., : size - 1], axis=2)
    members = np.concatenate([seeds[..., None], chosen], axis=2)
    samples = unit[members]  # (R, n, size, K)
    normals = _batched_normals(samples.transpose(0, 1, 3, 2) @ samples, size)
    labels = _nearest(unit, normals)
    outer = (unit[:, :, None] * unit[:, None, :]).reshape(n_samples, -1)
    if size < dim:
        normals = None
    for _ in range(n_iter):
        scatter, counts = _scatters(outer, labels, n_clusters)
        new = _batched_normals(scatter, dim)
        if normals is not None:
            # a cluster with too few points keeps its previous subspace
            keep = counts < dim
            new[keep] = normals[keep]
        normals = new
        labels = _nearest(unit, normals)
    return labels


def vote_features(labels, n_clusters):
    """Factor ``B`` of the vote matrix ``V = B B^T``, shape (P, R n).

    ``V_ij`` is the number of runs (columns of ``labels``, shape (P, R))
    that put points ``i`` and ``j`` in one cluster; ``B`` is the one-hot
    indicator of every run's labels.
    """
    n_points, n_runs = labels.shape
    columns = labels + n_clusters * np.arange(n_runs)
    onehot = np.zeros((n_points, n_runs * n_clusters))
    np.put_along_axis(onehot, columns, 1.0, axis=1)
    return onehot


def vote_cut(features, labels, n_clusters):
    """Normalised cut of ``labels`` on the vote matrix ``S = B B^T``.

    ``sum_k cut(C_k, rest) / vol(C_k) = sum_k 1 - ||B^T 1_k||^2 / vol(C_k)``
    with ``vol(C_k) = 1_k^T B B^T 1``: ``O(P R n)``, between 0 and
    ``n_clusters``; ``inf`` when a cluster has zero volume.

    Parameters
    ----------
    features : ndarray of shape (n_samples, n_dims)
        Non-negative factor ``B`` (:func:`vote_features`).
    labels : ndarray of shape (n_samples,)
        Labels in ``0 .. n_clusters - 1``.
    n_clusters : int
        Number of clusters.

    Returns
    -------
    ncut : float

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._voting import vote_cut, vote_features
    >>> runs = np.array([[0, 0], [0, 0], [1, 1], [1, 0]])
    >>> B = vote_features(runs, 2)
    >>> vote_cut(B, np.array([0, 0, 1, 1]), 2) < vote_cut(B, np.array([0, 1, 0, 1]), 2)
    True
    """
    degrees = features @ features.sum(axis=0)
    indicator = np.zeros((labels.size, n_clusters))
    indicator[np.arange(labels.size), labels] = 1.0
    sums = indicator.T @ features
    volumes = indicator.T @ degrees
    if np.any(volumes <= 0):
        return np.inf
    within = np.einsum("kd,kd->k", sums, sums)
    return float(np.sum(1.0 - within / volumes))


def vote_confidence(features, n_clusters):
    """How well the vote graph separates into ``n_clusters`` groups, in [0, 1].

    With ``N = D^{-1/2} B B^T D^{-1/2}`` the normalised vote matrix and
    ``1 = l_1 >= l_2 >= ...`` its eigenvalues, every labelling into ``n``
    clusters has a normalised cut of at least ``sum_{k=2}^n (1 - l_k)``
    (the spectral relaxation of the cut), while labels independent of the
    votes cut about ``n - 1``. The confidence ``mean(l_2 .. l_n)`` is one
    minus that bound over ``n - 1``: 1 when all runs agree on one
    segmentation (the graph has ``n`` components), near 0 when they split
    the points independently of each other. Time ``O(m^2 M + m^3)`` with
    ``m = min(P, R n)`` and ``M = max(P, R n)``: the top ``n`` eigenvalues of
    the smaller Gram matrix of ``D^{-1/2} B``.

    Parameters
    ----------
    features : ndarray of shape (n_samples, n_dims)
        Non-negative factor ``B`` (:func:`vote_features`), every row non-zero.
    n_clusters : int
        Number of clusters, at least 2.

    Returns
    -------
    confidence : float

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._voting import vote_confidence, vote_features
    >>> agree = np.array([[0, 0, 0], [0, 0, 0], [1, 1, 1], [1, 1, 1]])
    >>> round(vote_confidence(vote_features(agree, 2), 2), 6)
    1.0
    >>> disagree = np.array([[0, 0, 0], [0, 1, 1], [1, 0, 1], [1, 1, 0]])
    >>> round(vote_confidence(vote_features(disagree, 2), 2), 6)
    0.333333
    """
    degrees = features @ features.sum(axis=0)
    if np.any(degrees <= 0):
        raise ValueError(
            "vote_confidence needs every point in at least one vote: "
            "features has all-zero rows."
        )
    if not 2 <= n_clusters <= min(features.shape):
        raise ValueError(
            f"n_clusters={n_clusters} must be at least 2 and at most "
            f"min(features.shape)={min(features.shape)}."
        )
    scaled = features / np.sqrt(degrees)[:, None]
    # N = S S^T with S = D^{-1/2} B shares its non-zero eigenvalues with the
    # Gram matrix on the smaller side of S; only the top n are computed
    # one BLAS thread: a small problem, run once per fit (see _threads)
    with one_thread("blas"):
        gram = (
            scaled @ scaled.T
            if scaled.shape[0] <= scaled.shape[1]
            else scaled.T @ scaled
        )
        size = gram.shape[0]
        values = scipy.linalg.eigvalsh(
            gram, subset_by_index=[size - n_clusters, size - 1]
        )
    return float(np.clip(values[:-1].mean(), 0.0, 1.0))
