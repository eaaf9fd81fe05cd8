"""Nearest trajectories on co-observed frames.

Two tracks of one rigid object stay close in the image and move alike, so the
distance between trajectories over the frames both are seen in is a strong
hint that they share a motion: the neighbourhoods here seed the subspace
hypotheses and carry the smoothing term of the refinement. With missing
entries the squared distance is averaged over the co-observed coordinates
(``sum_j m_pj m_qj (x_pj - x_qj)^2 / sum_j m_pj m_qj``); pairs seen together in
fewer than ``min_overlap`` coordinates are not neighbours (their distance is
infinite). Brute force in row chunks: time ``O(P Q D)``, memory ``O(chunk Q)``.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
from sklearn.neighbors import NearestNeighbors

from sklearn_gpca._chunks import row_chunks

# Query rows per chunk of the brute-force search (chunk x n_references floats).
_CHUNK = 1024


def coobserved_sq_distances(X0, mask, rows, Y0, ymask, min_overlap):
    """Mean squared difference over co-observed coordinates, ``inf`` if too few.

    Parameters
    ----------
    X0, mask : ndarray of shape (n_samples, n_features)
        Query tracks (zero where missing) and their observed entries.
    rows : slice or ndarray
        Rows of ``X0`` to query.
    Y0, ymask : ndarray of shape (n_references, n_features)
        Reference tracks and their observed entries.
    min_overlap : int or ndarray of shape (n_samples,)
        Fewest co-observed coordinates for a finite distance (per query row).

    Returns
    -------
    distances : ndarray of shape (n_rows, n_references)
    """
    m = mask[rows].astype(np.float64)
    x = X0[rows]
    ym = ymask.astype(np.float64)
    overlap = m @ ym.T
    sq = (x * x) @ ym.T + m @ (Y0 * Y0).T - 2.0 * (x @ Y0.T)
    distances = np.maximum(sq, 0.0) / np.maximum(overlap, 1.0)
    need = min_overlap if np.isscalar(min_overlap) else min_overlap[rows][:, None]
    distances[overlap < need] = np.inf
    return distances


def track_neighbors(X0, mask, n_neighbors, *, min_overlap=4):
    """Indices of each track's nearest tracks on co-observed coordinates.

    Parameters
    ----------
    X0 : ndarray of shape (n_samples, n_features)
        Tracks, zero where missing.
    mask : ndarray of shape (n_samples, n_features), dtype=bool
        Observed entries.
    n_neighbors : int
        Number of neighbours, at most ``n_samples - 1``.
    min_overlap : int, default=4
        Fewest co-observed coordinates of two neighbours; a track observing
        fewer coordinates than this needs all of its own.

    Returns
    -------
    neighbors : ndarray of shape (n_samples, n_neighbors), dtype=intp
        Nearest first; ``-1`` where a track has fewer than ``n_neighbors``
        tracks it shares enough coordinates with.
    """
    n_samples = X0.shape[0]
    if mask.all():
        tree = NearestNeighbors(n_neighbors=n_neighbors + 1).fit(X0)
        found = tree.kneighbors(X0, return_distance=False)
        # drop the track itself (ties may put it in any position)
        keep = found != np.arange(n_samples)[:, None]
        order = np.argsort(~keep, axis=1, kind="stable")
        return np.take_along_axis(found, order, axis=1)[:, :n_neighbors].astype(np.intp)
    need = np.minimum(min_overlap, np.count_nonzero(mask, axis=1))
    neighbors = np.empty((n_samples, n_neighbors), dtype=np.intp)
    for rows in row_chunks(n_samples, _CHUNK):
        distances = coobserved_sq_distances(X0, mask, rows, X0, mask, need)
        index = np.arange(rows.start, rows.stop)
        distances[index - rows.start, index] = np.inf
        nearest = np.argpartition(distances, n_neighbors - 1, axis=1)[:, :n_neighbors]
        near_d = np.take_along_axis(distances, nearest, axis=1)
        order = np.argsort(near_d, axis=1, kind="stable")
        nearest = np.take_along_axis(nearest, order, axis=1)
        near_d = np.take_along_axis(near_d, order, axis=1)
        nearest[~np.isfinite(near_d)] = -1
        neighbors[rows] = nearest
    return neighbors
