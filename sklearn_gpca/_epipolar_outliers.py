"""Tracks that fit no motion's epipolar geometry: a perspective-exact check.

The local test of :mod:`sklearn_gpca._local_outliers` fits each track with a
low-dimensional subspace of its neighbours. Under strong perspective (a camera
driving forward through a scene whose depths span a decade) that linear model
is wrong for the tracks at the edge of the depth range: the nearest points of
the background have no neighbour as near as they are, their trajectory
``x_t = (X - C_t) / (Z - c_t)`` is extrapolated in ``1 / Z`` from farther
ones, and their misfit is many times the noise (on the driving draws of
``benchmarks/bench_outliers.py``, 8 % of the inliers flagged at a nominal
0.1 %, nearly all of them background tracks nearer than their neighbours).
The epipolar constraint of two views holds whatever the depth (Hartley &
Zisserman, *Multiple View Geometry*, section 9.2): a point of a rigid motion
seen at ``x`` in frame ``f`` and ``x'`` in frame ``f + g`` satisfies
``[x'; 1]^T F [x; 1] = 0`` for that motion's fundamental matrix ``F``.

For each frame pair ``(f, f + g)``, ``g`` in ``GAPS``, up to ``n_motions``
fundamental matrices are fitted one after the other (least median of squares
over ``N_HYPOTHESES`` random 8-point samples of the tracks no earlier matrix
explains, then the normalised 8-point algorithm on those within ``CUTOFF``
noise deviations); the noise deviation ``sigma`` is the first one's inliers'
(corrected for the truncation at ``CUTOFF``). To first order, a point pair of
a fitted motion has a Sampson distance ``d`` with ``(d / sigma)^2 ~
chi^2(1)`` (HZ section 11.4.3); a track's p-value in a pair is that of its
best matrix times their number, and over the pairs the smallest times the
number of pairs (Bonferroni, valid whatever the dependence between pairs that
share a frame).

This test has one degree of freedom per frame pair, where the local test has
the whole window: a drift onto a motion that moves alike often satisfies
the epipolar constraint. It therefore only *checks* the local test's flags,
and only on strongly perspective sequences, where the local test's null
model is wrong (:func:`perspective_checked_pvalues`): a track is flagged when
both tests reject it, so the probability of flagging an inlier stays at most
the threshold. A sequence is strongly perspective when the first motion's
inliers misfit their best *affine* epipolar constraint (HZ section 14.2) by
``PERSPECTIVE_DEVIATION`` noise deviations or more, median over the frame
pairs: about 1 on the lab draws of ``make_tracks``, 1-4 on the hand-held
ones (growing with the gap), 4-20 on the driving ones.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
from scipy import stats
from sklearn.utils import check_random_state

from sklearn_gpca._rows import TINY
from sklearn_gpca._two_view import fit_fundamental, sampson_fundamental

#: Median affine deviation (over the frame pairs, in noise deviations) above
#: which a sequence is treated as strongly perspective.
PERSPECTIVE_DEVIATION = 3.0
#: Frame gaps of the pairs tested.
GAPS = (1, 2, 4, 8)
#: Random 8-point samples per frame pair (least median of squares).
N_HYPOTHESES = 200
#: Inliers of the refit: Sampson distance within this many robust deviations.
CUTOFF = 2.5
#: Fewest point pairs a model explains (within ``CUTOFF`` noise deviations).
MIN_SUPPORT = 20
# E[z^2 | |z| < CUTOFF] for a standard normal z: the truncated variance.
_TRUNCATED = 1.0 - 2.0 * CUTOFF * stats.norm.pdf(CUTOFF) / (
    2.0 * stats.norm.cdf(CUTOFF) - 1.0
)
_LOG_FLOOR = -700.0


def affine_deviation(points1, points2):
    """RMS distance of point pairs to their best affine epipolar constraint.

    The affine fundamental matrix (HZ section 14.2) is the linear constraint
    ``a x' + b y' + c x + d y + e = 0``; the total-least-squares fit is the
    smallest principal direction of the centred 4-D points ``(x', y', x, y)``
    (HZ algorithm 14.1), the RMS geometric distance its singular value.
    """
    stacked = np.hstack([points2, points1])
    centred = stacked - stacked.mean(axis=0)
    smallest = np.linalg.svd(centred, compute_uv=False)[-1]
    return smallest / np.sqrt(max(stacked.shape[0] - 4, 1))


def _lmeds(points1, points2, rng):
    """Least-median-of-squares fundamental matrix and its robust scale."""
    n = points1.shape[0]
    samples = np.argsort(rng.uniform(size=(N_HYPOTHESES, n)), axis=1)[:, :8]
    F = fit_fundamental(points1[samples], points2[samples])
    d2 = sampson_fundamental(F, points1, points2) ** 2
    best = np.argmin(np.median(d2, axis=0))
    # least-median-of-squares scale with its small-sample correction
    scale = 1.4826 * (1.0 + 5.0 / (n - 8)) * np.sqrt(np.median(d2[:, best]))
    return F[best : best + 1], max(scale, TINY)


def epipolar_residuals(points1, points2, n_models, rng):
    """Sampson distances to the best of ``n_models`` motions, over the noise.

    The models are fitted one after the other: the first by least median of
    squares on every point pair, each next one on the pairs no earlier model
    explains; each is refitted on the pairs within ``CUTOFF`` noise
    deviations of it. The noise deviation ``sigma`` is the first model's (the
    tracker's noise, common to every motion). A later model needs
    ``MIN_SUPPORT`` unexplained pairs within ``CUTOFF`` deviations, or the
    search stops.

    Parameters
    ----------
    points1, points2 : ndarray of shape (n_points, 2)
        Positions of the tracks seen in both frames, ``n_points >= MIN_SUPPORT``.
    n_models : int
        Largest number of models.
    rng : RandomState

    Returns
    -------
    z : ndarray of shape (n_points,)
        Smallest Sampson distance over ``sigma`` (a standard normal deviate in
        absolute value for a pair of a fitted motion, to first order).
    n_fitted : int
        Models fitted.
    affine : float
        RMS distance of the first model's inliers to their best affine
        epipolar constraint, over ``sigma`` (about 1 when an affine camera
        explains the motion as well as the perspective one).
    """
    remaining = np.ones(points1.shape[0], dtype=bool)
    best = np.full(points1.shape[0], np.inf)
    sigma = None
    n_fitted, affine = 0, 0.0
    for _ in range(n_models):
        if np.count_nonzero(remaining) < MIN_SUPPORT:
            break
        F, scale = _lmeds(points1[remaining], points2[remaining], rng)
        cut = CUTOFF * (scale if sigma is None else sigma)
        d = sampson_fundamental(F, points1, points2)[:, 0]
        support = remaining & (d <= cut)
        if np.count_nonzero(support) < MIN_SUPPORT:
            break
        F = fit_fundamental(points1[support][None], points2[support][None])
        d = sampson_fundamental(F, points1, points2)[:, 0]
        if sigma is None:
            inliers = d <= cut
            if np.count_nonzero(inliers) < MIN_SUPPORT:
                # the refit lost its support (degenerate points): no model
                break
            sigma = max(np.sqrt(np.mean(d[inliers] ** 2) / _TRUNCATED), TINY)
            affine = affine_deviation(points1[inliers], points2[inliers]) / sigma
        best = np.minimum(best, d)
        remaining &= d > CUTOFF * sigma
        n_fitted += 1
    if sigma is None:
        return best, 0, 0.0
    return best / sigma, n_fitted, affine


def epipolar_outlier_pvalues(X0, mask, n_models, *, gaps=GAPS, random_state=None):
    """Probability that each track fits the dominant motion as well as noise would.

    Parameters
    ----------
    X0 : ndarray of shape (n_samples, 2 * n_frames)
        Tracks, zero where missing.
    mask : ndarray of shape (n_samples, 2 * n_frames), dtype=bool
        Observed entries.
    n_models : int
        Fundamental matrices fitted per frame pair (the number of motions).
    gaps : tuple of int, default=GAPS
        Frame gaps of the pairs tested.
    random_state : int, RandomState instance or None, default=None
        Seeds the 8-point samples.

    Returns
    -------
    pvalues : ndarray of shape (n_samples,)
        Bonferroni-corrected p-value in ``[0, 1]`` (see module doc); 0 for a
        track in no tested pair (no evidence that it fits: the larger of this
        and the local test's p-value is then the local test's).
    deviation : float
        Median over the tested pairs of the dominant motion's affine
        deviation, in noise deviations (0 without any pair).
    """
    rng = check_random_state(random_state)
    n_samples, n_features = X0.shape
    seen = mask[:, ::2] & mask[:, 1::2]
    points = X0.reshape(n_samples, n_features // 2, 2)
    smallest = np.zeros(n_samples)
    n_tests = np.zeros(n_samples)
    deviations = []
    for gap in gaps:
        for f in range(n_features // 2 - gap):
            both = np.flatnonzero(seen[:, f] & seen[:, f + gap])
            if both.size < MIN_SUPPORT:
                continue
            z, n_fitted, affine = epipolar_residuals(
                points[both, f], points[both, f + gap], n_models, rng
            )
            if n_fitted == 0:
                continue
            deviations.append(affine)
            # best of n_fitted models: Bonferroni over them too
            log_p = np.log(n_fitted) + stats.chi2.logsf(z**2, 1)
            log_p = np.maximum(np.minimum(log_p, 0.0), _LOG_FLOOR)
            smallest[both] = np.minimum(smallest[both], log_p)
            n_tests[both] += 1
    log_bonferroni = smallest + np.log(np.maximum(n_tests, 1))
    # a track in no tested pair has no evidence of fitting: p-value 0
    pvalues = np.where(n_tests > 0, np.minimum(np.exp(log_bonferroni), 1.0), 0.0)
    return pvalues, float(np.median(deviations)) if deviations else 0.0


def perspective_checked_pvalues(X0, mask, pvalues, n_motions, *, random_state=None):
    """The local test's p-values, checked by the two-view test under perspective.

    When the sequence is strongly perspective (the median over the frame
    pairs of the dominant motion's affine deviation is at least
    ``PERSPECTIVE_DEVIATION`` noise deviations), each track's p-value is the
    larger of the local test's and the epipolar test's: a track is flagged
    only if both reject it, and the probability that an inlier is flagged is
    still at most the threshold. Otherwise the local test's p-values are
    returned unchanged: where an affine camera explains the motions, the
    local linear model is right and the two-view test, with one degree of
    freedom per frame pair, would only lose outliers (drifts onto a motion
    that moves alike satisfy its epipolar constraint).

    Parameters
    ----------
    X0 : ndarray of shape (n_samples, 2 * n_frames)
        Tracks, zero where missing.
    mask : ndarray of shape (n_samples, 2 * n_frames), dtype=bool
        Observed entries.
    pvalues : ndarray of shape (n_samples,)
        The local test's p-values.
    n_motions : int
        Number of motions (models fitted per frame pair).
    random_state : int, RandomState instance or None, default=None
        Seeds the 8-point samples.

    Returns
    -------
    pvalues : ndarray of shape (n_samples,)
    """
    epipolar, deviation = epipolar_outlier_pvalues(
        X0, mask, n_motions, random_state=random_state
    )
    if deviation < PERSPECTIVE_DEVIATION:
        return pvalues
    return np.maximum(pvalues, epipolar)
