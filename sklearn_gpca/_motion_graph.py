"""Sparse affinity between neighbouring tracks from how alike they move.

Beyond the paper: two neighbouring tracks of one rigid object are displaced
alike over any stretch of frames, while tracks on either side of a motion
boundary part at some moment. Following Brox & Malik (ECCV 2010, long-term
trajectory analysis), the distance of neighbours ``p`` and ``q`` is the largest,
over the frames ``t`` both see, of the squared difference of their
displacements ``x(t + h) - x(t)``, in units of that frame's typical spread of
displacements (the median squared deviation from the median displacement),
for the horizons ``h`` in ``horizons``; the weight is ``exp(-d^2 / median
d^2)``. Pairs that share no displacement get the median distance (weight
``1/e``). Time and memory ``O(P k F)`` for ``k`` neighbours: it is a kNN graph,
never a dense ``P x P`` matrix. The affinity does not depend on a camera
model, so it holds under perspective, and it never needs a track's whole
trajectory.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import scipy.sparse as sp

# Edges per chunk of the vectorised distance computation.
_CHUNK = 2**15


def _displacements(points, visible, horizon):
    """Displacements over ``horizon`` frames, where both ends are seen."""
    valid = visible[:, horizon:] & visible[:, :-horizon]
    moves = points[:, horizon:] - points[:, :-horizon]
    return moves, valid


def _frame_spread(moves, valid):
    """Median squared deviation from the median displacement, per frame."""
    n_frames = moves.shape[1]
    spread = np.full(n_frames, np.nan)
    for t in range(n_frames):
        seen = moves[valid[:, t], t]
        if seen.shape[0] >= 3:
            centre = np.median(seen, axis=0)
            spread[t] = np.median(np.sum((seen - centre) ** 2, axis=1))
    positive = spread[np.isfinite(spread) & (spread > 0)]
    fallback = np.median(positive) if positive.size else 1.0
    return np.where(np.isfinite(spread) & (spread > 0), spread, fallback)


def motion_affinity(X0, mask, neighbors, *, horizons=(1, 5)):
    """Symmetric kNN affinity of tracks from their displacement differences.

    Parameters
    ----------
    X0 : ndarray of shape (n_samples, 2 * n_frames)
        Tracks ``[x_1, y_1, ..., x_F, y_F]``, zero where missing.
    mask : ndarray of shape (n_samples, 2 * n_frames), dtype=bool
        Observed entries (both coordinates of a point are seen together).
    neighbors : ndarray of shape (n_samples, n_neighbors)
        Graph edges ``p -> neighbors[p]``; ``-1`` for none.
    horizons : tuple of int, default=(1, 5)
        Frame gaps of the compared displacements (clipped to ``F - 1``).

    Returns
    -------
    affinity : scipy.sparse.csr_matrix of shape (n_samples, n_samples)
        Weights in ``(0, 1]``, symmetrised with the entrywise maximum.
    """
    n_samples, n_features = X0.shape
    n_frames = n_features // 2
    points = X0.reshape(n_samples, n_frames, 2)
    visible = mask[:, 0::2] & mask[:, 1::2]
    n_neighbors = neighbors.shape[1]
    rows = np.repeat(np.arange(n_samples), n_neighbors)
    cols = neighbors.ravel()
    keep = cols >= 0
    rows, cols = rows[keep], cols[keep]
    distances = np.full(rows.size, -np.inf)
    for horizon in sorted({min(h, n_frames - 1) for h in horizons if h >= 1}):
        if horizon < 1:
            continue
        moves, valid = _displacements(points, visible, horizon)
        spread = _frame_spread(moves, valid)
        for start in range(0, rows.size, _CHUNK):
            r = rows[start : start + _CHUNK]
            c = cols[start : start + _CHUNK]
            both = valid[r] & valid[c]
            gap = np.sum((moves[r] - moves[c]) ** 2, axis=2) / spread
            gap = np.where(both, gap, -np.inf).max(axis=1)
            distances[start : start + _CHUNK] = np.maximum(
                distances[start : start + _CHUNK], gap
            )
    seen = np.isfinite(distances)
    typical = np.median(distances[seen]) if seen.any() else 1.0
    typical = typical if typical > 0 else 1.0
    distances[~seen] = typical
    weights = np.exp(-distances / typical)
    affinity = sp.csr_matrix((weights, (rows, cols)), shape=(n_samples, n_samples))
    return affinity.maximum(affinity.T).tocsr()


def edge_weights(affinity, neighbors):
    """Weight of each edge ``p -> neighbors[p, j]`` in ``affinity`` (0 for ``-1``)."""
    affinity = affinity.tocsr()
    weights = np.zeros(neighbors.shape)
    valid = neighbors >= 0
    rows = np.nonzero(valid)[0]
    weights[valid] = np.asarray(affinity[rows, neighbors[valid]]).ravel()
    return weights
