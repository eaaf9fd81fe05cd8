"""Tracks that disagree with their neighbours: a label-free outlier test.

A track of a rigid motion moves like the tracks near it that move alike: on a
short window of frames, the tracks of a small neighbourhood of one rigid body
lie close to a linear subspace of low dimension (4 for an affine camera; a
perspective camera bends them less over a small patch and a few frames than
over the whole scene). A track that follows no motion -- a random walk, or a
tracker's drift or jump from one motion to another in that window -- does
not fit the subspace of its neighbours.

For each window of ``WINDOW`` frames (every ``WINDOW // 2`` frames) and each
track ``p`` that observes ``n_p`` coordinates there:

1. its neighbours are the ``N_NEIGHBORS`` tracks that observe every
   coordinate ``p`` observes in the window and whose displacements from
   ``p``'s first frame there are nearest to ``p``'s (plus ``BETA`` times the
   squared offset between the two tracks at that frame): tracks that *move*
   alike, so that a neighbourhood rarely mixes two motions;
2. the subspace ``V`` of dimension ``d_p = min(DIM, n_p - 2)`` best fitting
   the neighbours on ``p``'s coordinates (SVD), their residual energy ``E``
   giving the local noise ``sigma^2 = E / ((N - d_p)(n_p - d_p))`` (the
   neighbours' own spread, on the same coordinates and geometry);
3. ``p``'s residual ``r`` to ``V``: under Gaussian noise, ``r / ((n_p -
   d_p) sigma^2)`` follows ``F(n_p - d_p, (N - d_p)(n_p - d_p))``. The
   statistic of every track of the window is divided by the median, over
   the window's tracks, of its ratio to that law's median (a robust
   calibration: a fit out of sample misfits a little more than in sample,
   and most tracks are inliers);
4. an empirical null (Efron, "Large-scale simultaneous hypothesis testing:
   the choice of a null hypothesis", JASA 2004): each track's p-value is
   turned into a normal score ``z``, and where the window's scores spread
   wider than the standard normal -- real tracks' noise is not one Gaussian
   level: it differs from track to track and a camera is not exactly
   affine over a patch -- ``z`` is divided by their width, measured on the
   lower half of the tracks whose noise is measured (the median minus the
   lower quartile, over 0.6745), which outliers do not reach. It never
   narrows the law. At ``1e-3`` it lowers the outlier-free Hopkins155 tracks
   flagged from 21 % to 8 % (every third sequence; the estimator is the
   textbook one, not tuned there), and raises the precision on the
   ``make_tracks`` draws of ``bench_outliers.py`` (seeds 0-2: hand-held 0.87
   -> 0.90, driving 0.62 -> 0.72, lab 0.97 -> 0.99; recall 0.78 -> 0.77,
   0.98 -> 0.95, 0.97 -> 0.96).

The p-value of a track is the smallest over its windows times the number of
windows it is tested in (Bonferroni), so that a track whose residuals are
noise is flagged with probability at most the threshold. A track observing
fewer than 6 coordinates in every window (seen in 2 frames or fewer there),
or without ``DIM + 3`` tracks covering it, is not tested (p-value 1). A
frame counts as observed when both its coordinates are: a lone ``x`` or ``y``
is left out of the test.

Settings (``WINDOW``, ``DIM``, ``N_NEIGHBORS``, ``BETA``) were chosen on
``make_tracks`` draws with 10 % outliers (handheld, driving and lab, seeds
0-2, ``benchmarks/bench_outliers.py``'s settings), by precision and recall
at a false-alarm probability of 1e-3; see ``benchmarks/results/outliers.md``.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
from scipy import special, stats

from sklearn_gpca._chunks import row_chunks
from sklearn_gpca._outliers import frame_windows

#: Frames per window of the local test.
WINDOW = 10
#: Largest dimension of a neighbourhood's subspace.
DIM = 5
#: Neighbours per track.
N_NEIGHBORS = 24
#: Weight of the offset between two tracks in the neighbour distance (against
#: the sum over frames of their displacements' differences).
BETA = 0.1
#: Fewest tracks tested in a window for its calibration.
MIN_TESTED = 10
# log-p-values are floored here: the F law's logsf underflows far in the tail.
_LOG_FLOOR = -700.0
# Query rows per chunk (chunk x n_samples floats per array).
_CHUNK = 512


def _neighbours(x, m, rows, n_neighbors, beta, pool):
    """Nearest tracks in motion of ``rows`` among the ``pool`` tracks covering them.

    Returns ``(neighbors, valid)`` of shape (n_rows, n_neighbors).
    """
    n = x.shape[0]
    mr, xr = m[rows], x[rows]
    index = np.arange(rows.start, rows.stop)
    cover = ((mr @ (1.0 - m).T) == 0) & pool
    cover[index - rows.start, index] = False
    # sum_t ||e_t - o||^2 + beta ||o||^2 with e_t = x_p(t) - x_q(t) and
    # o = e_{t0} at p's first observed frame t0 (q covers p: q is seen there)
    sq = (mr * xr * xr).sum(axis=1)[:, None] + mr @ (x * x).T - 2.0 * (mr * xr) @ x.T
    first = np.argmax(mr[:, ::2] > 0, axis=1)
    local = np.arange(xr.shape[0])
    ox = xr[local, 2 * first][:, None] - x[:, 2 * first].T
    oy = xr[local, 2 * first + 1][:, None] - x[:, 2 * first + 1].T
    sx = (mr[:, ::2] * xr[:, ::2]).sum(axis=1)[:, None] - mr[:, ::2] @ x[:, ::2].T
    sy = (mr[:, 1::2] * xr[:, 1::2]).sum(axis=1)[:, None] - mr[:, 1::2] @ x[:, 1::2].T
    n_t = mr[:, ::2].sum(axis=1)[:, None]
    offset = ox**2 + oy**2
    distance = sq - 2.0 * (ox * sx + oy * sy) + (n_t + beta) * offset
    distance = np.where(cover, distance, np.inf)
    k = min(n_neighbors, n - 1)
    nearest = np.argpartition(distance, k - 1, axis=1)[:, :k]
    valid = np.isfinite(np.take_along_axis(distance, nearest, axis=1))
    return nearest, valid


def _window_statistics(x, m, rows, dim, n_neighbors, beta, pool):
    """F statistic, its degrees of freedom, testability of ``rows`` and whether
    their neighbours' spread measures a noise above rounding."""
    counts = m[rows].sum(axis=1).astype(np.intp)
    nearest, valid = _neighbours(x, m, rows, n_neighbors, beta, pool)
    n_valid = valid.sum(axis=1)
    dims = np.minimum(dim, counts - 2)
    tested = (counts >= 6) & (n_valid >= dims + 3)
    stacked = x[nearest] * m[rows][:, None, :] * valid[:, :, None]
    _, values, vt = np.linalg.svd(stacked, full_matrices=False)
    width = min(dim, vt.shape[1])
    keep = np.arange(width) < dims[:, None]
    basis = vt[:, :width] * keep[:, :, None]
    xr = x[rows]
    projection = np.einsum("rkd,rd->rk", basis, xr)
    residual = np.maximum((xr * xr).sum(axis=1) - (projection**2).sum(axis=1), 0.0)
    beyond = np.arange(values.shape[1]) >= dims[:, None]
    energy = np.sum(np.where(beyond, values**2, 0.0), axis=1)
    dof1 = np.maximum(counts - dims, 1)
    dof2 = np.maximum((n_valid - dims) * (counts - dims), 1)
    # |x|^2 - |P x|^2 cancels: a residual below a few eps |x|^2 is rounding, so
    # a neighbourhood spread below that is no noise estimate (noise-free tracks)
    rounding = 16 * np.finfo(np.float64).eps * (xr * xr).sum(axis=1) / dof1
    spread = energy / dof2
    measured = spread > rounding
    sigma2 = np.maximum(np.where(measured, spread, rounding), np.finfo(np.float64).tiny)
    return residual / (dof1 * sigma2), dof1, dof2, tested, measured


def normal_scores(log_p):
    """Normal scores ``z`` with ``P(N(0, 1) >= z) = p`` of log p-values."""
    return -special.ndtri_exp(np.minimum(log_p, -1e-300))


def null_width(scores):
    """Width of an empirical null from its lower half (step 4), at least 1."""
    lower_quartile, median = np.percentile(scores, [25, 50])
    return max((median - lower_quartile) / 0.6744897501960817, 1.0)


def _empirical_null(log_p, tested):
    """Log-p-values under the empirical null of the ``tested`` tracks (step 4)."""
    z = normal_scores(log_p)
    return np.maximum(stats.norm.logsf(z / null_width(z[tested])), _LOG_FLOOR)


def local_outlier_pvalues(
    X0,
    mask,
    *,
    exclude=None,
    window=WINDOW,
    dim=DIM,
    n_neighbors=N_NEIGHBORS,
    beta=BETA,
    empirical_null=True,
):
    """Probability that each track fits its neighbours as well as noise would.

    Parameters
    ----------
    X0 : ndarray of shape (n_samples, 2 * n_frames)
        Tracks, zero where missing.
    mask : ndarray of shape (n_samples, 2 * n_frames), dtype=bool
        Observed entries.
    exclude : ndarray of shape (n_samples,), dtype=bool, default=None
        Tracks that serve as no one's neighbour (they are still tested).
        ``segment_motions`` excludes none: a second pass without the tracks
        flagged by a first one flags more of the outliers that are each
        other's neighbours, but also, under strong perspective, the near
        background tracks whose like-moving neighbours were flagged (on the
        driving draws of ``benchmarks/bench_outliers.py``, seeds 0-2,
        precision 0.62 -> 0.41).
    window : int, default=WINDOW
        Frames per window.
    dim : int, default=DIM
        Largest dimension of a neighbourhood's subspace.
    n_neighbors : int, default=N_NEIGHBORS
        Neighbours per track.
    beta : float, default=BETA
        Weight of the offset between two tracks in the neighbour distance.
    empirical_null : bool, default=True
        Widen each window's null law to the spread of its tracks' scores
        (step 4 of the module doc); False tests against the F law alone.

    Returns
    -------
    pvalues : ndarray of shape (n_samples,)
        Bonferroni-corrected p-value in ``[0, 1]`` (see module doc); 1 for a
        track that cannot be tested.

    Raises
    ------
    ValueError
        If ``mask`` is not shaped like ``X0``, ``exclude`` does not hold one
        value per track, or ``window`` is not an integer of 3 frames or more.
    """
    n_samples, n_features = X0.shape
    if mask.shape != X0.shape:
        raise ValueError(
            f"mask must have the shape of X0 {X0.shape}, got {mask.shape}."
        )
    if isinstance(window, bool) or int(window) != window or window < 3:
        raise ValueError(f"window must be an integer >= 3 frames, got {window!r}.")
    if exclude is not None and np.shape(exclude) != (n_samples,):
        raise ValueError(
            f"exclude must hold one bool per track ({n_samples}), got shape "
            f"{np.shape(exclude)}."
        )
    # the neighbour distance pairs x and y per frame: a coordinate whose
    # partner is missing is left out of the test
    seen = np.repeat(mask[:, 0::2] & mask[:, 1::2], 2, axis=1)
    X0 = np.where(seen, X0, 0.0)
    mask = seen
    starts, width = frame_windows(n_features // 2, int(window))
    frames = np.arange(n_features) // 2
    smallest = np.zeros(n_samples)
    n_tests = np.zeros(n_samples)
    pool = np.ones(n_samples, dtype=bool)
    if exclude is not None:
        pool = ~np.asarray(exclude, dtype=bool)
    if np.count_nonzero(pool) < dim + 4:
        return np.ones(n_samples)
    for start in starts:
        cols = (frames >= start) & (frames < start + width)
        x, m = X0[:, cols], mask[:, cols].astype(np.float64)
        parts = [
            _window_statistics(x, m, rows, dim, n_neighbors, beta, pool)
            for rows in row_chunks(n_samples, _CHUNK)
        ]
        stat, dof1, dof2, tested, measured = (
            np.concatenate(p) for p in zip(*parts, strict=True)
        )
        if tested.sum() < MIN_TESTED:
            continue
        # calibrated on the tracks whose noise is measured; where none is
        # (noise-free tracks), rounding is the noise
        calibrate = tested & measured
        if calibrate.sum() >= MIN_TESTED:
            ratio = np.median(
                stat[calibrate] / stats.f.median(dof1[calibrate], dof2[calibrate])
            )
            stat = stat / max(ratio, np.finfo(np.float64).tiny)
        log_p = np.maximum(stats.f.logsf(stat, dof1, dof2), _LOG_FLOOR)
        if empirical_null and calibrate.sum() >= MIN_TESTED:
            log_p = _empirical_null(log_p, calibrate)
        smallest = np.where(tested, np.minimum(smallest, log_p), smallest)
        n_tests += tested
    log_bonferroni = smallest + np.log(np.maximum(n_tests, 1))
    return np.minimum(np.exp(log_bonferroni), 1.0)
