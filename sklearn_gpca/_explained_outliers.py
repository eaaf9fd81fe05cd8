"""Set-aside tracks that a fitted motion explains: the local test's false alarms.

The local test of :mod:`sklearn_gpca._local_outliers` flags a track that
misfits the subspace of its neighbours, before any segmentation. Some inliers
fail it: the nearest tracks of a perspective background (no neighbour is as
near the camera as they are), and the edge tracks of a small motion. Once the
kept tracks are segmented, every motion has a model fitted to many tracks,
and each set-aside track is tested against those models:

- every motion's 4-D subspace (the affine camera of section 2 of the paper),
  fitted to its kept tracks on their observed entries;
- for the largest motion, also a perspective camera per frame
  (:mod:`sklearn_gpca._projective_motion`, the exact model of a
  background seen by a moving camera); a track keeps the smaller of its two
  residuals, both counted with ``2 m - 4`` degrees of freedom for ``m``
  frames seen.

Under Gaussian noise of variance ``sigma^2`` per coordinate, a track of
motion ``k`` with residual ``r_k`` on ``dof_k`` degrees of freedom has ``r_k
/ sigma^2 ~ chi^2(dof_k)``. The tracker's noise is common to the motions:
``sigma^2`` is the median, over the kept tracks, of their own motion's
``r / median(chi^2(dof))``. A track's p-value is that of its best motion,
``max_k P(chi^2(dof_k) >= r_k / sigma^2)``: a track of motion ``k`` is
rejected by every motion only if it is rejected by ``k``, so no correction
for the number of motions is needed. Real tracks' noise is not one Gaussian
level (it differs from track to track), so the p-values go through an
empirical null, as the local test's do (Efron, JASA 2004): each is turned
into a normal score, divided by the spread of the segmented tracks' scores
under their own motion (the median minus the lower quartile, over 0.6745,
which the misfits of the upper tail do not reach; never below 1). On
Hopkins155's hand-cleaned tracks it nearly halves the tracks labelled ``-1``
(6.9 -> 3.8 % of all 155 sequences; ``benchmarks/results/false_alarms.md``). The
scores keep their order, so the motion that fits a track best does not
change. A track stays set aside only when this
test rejects it too: an inlier is then flagged with probability at most the
threshold, as with the local test alone. A motion of fewer than
``MIN_MODEL_TRACKS`` kept tracks explains no track (a model fitted to a few
tracks fits almost anything), nor does a model that leaves a track no degree
of freedom. To *assign* the set-aside tracks (the default, without
``outlier_threshold``) every motion with a kept track competes
(``min_tracks=1``): there a small motion's model must be able to win.

This test alone is not an outlier test: the models of motions that are not
exactly affine (perspective objects, a wrong segmentation) misfit many inliers
of their own (flagging the tracks it rejects would flag a quarter of the
inliers of the driving draws). It only clears the local test's flags. Measured
on the draws of ``benchmarks/bench_outliers.py``, seeds 10-17
(``benchmarks/results/outliers.md``).
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
from scipy import special, stats

from sklearn_gpca._local_outliers import normal_scores, null_width
from sklearn_gpca._motion_models import MotionModels
from sklearn_gpca._rows import TINY

#: Fewest kept tracks of a motion whose models explain set-aside tracks (as
#: many as the perspective refinement needs, ``MIN_PROJECTIVE_TRACKS``).
MIN_MODEL_TRACKS = 12
#: Dimension of each motion's subspace: an affine camera's.
MOTION_DIM = 4
#: Fewest segmented tracks whose scores measure the empirical null.
MIN_NULL_TRACKS = 10


def _motion_residuals(X0, mask, labels, n_motions, perspective, min_tracks):
    """Residuals and degrees of freedom of every track to every motion's model.

    Motions with fewer than ``min_tracks`` members get an infinite residual
    (they explain nothing).
    """
    models = MotionModels(
        X0,
        mask,
        labels,
        n_motions,
        subspace_dim=MOTION_DIM,
        perspective=perspective,
        min_tracks=min_tracks,
    )
    return models.residuals(X0, mask)


def motion_model_log_pvalues(
    X0, mask, labels, n_motions, *, perspective=True, min_tracks=MIN_MODEL_TRACKS
):
    """Log p-value of each track under its best-fitting motion's model.

    Parameters
    ----------
    X0 : ndarray of shape (n_samples, 2 * n_frames)
        Tracks, zero where missing.
    mask : ndarray of shape (n_samples, 2 * n_frames), dtype=bool
        Observed entries.
    labels : ndarray of shape (n_samples,)
        Motion of each track in ``0 .. n_motions - 1``; ``-1`` for a track
        that fits no model (the set-aside tracks).
    n_motions : int
    perspective : bool, default=True
        Also model the largest motion with a perspective camera.
    min_tracks : int, default=MIN_MODEL_TRACKS
        Fewest kept tracks of a motion whose model is tested. To *assign* a
        set-aside track rather than clear it, every motion with a track
        must compete (1): a small object's tracks that the local test sets
        aside otherwise all go to another motion (Hopkins155 ``head``, 7
        kept tracks of 14: 3.0 -> 9.1 %).

    Returns
    -------
    log_pvalues : ndarray of shape (n_samples,)
        ``max_k log P(chi^2(dof_k) >= r_k / sigma^2)`` (see the module doc),
        finite far in the tail; ``-inf`` for a track that no model can
        test, and for every track when the noise cannot be measured.
    nearest : ndarray of shape (n_samples,), dtype=intp
        The motion of that largest p-value: a track every motion misfits
        gets the one it misfits least.
    """
    residuals, dofs = _motion_residuals(
        X0, mask, labels, n_motions, perspective, min_tracks
    )
    kept = np.flatnonzero(labels >= 0)
    own_r = residuals[kept, labels[kept]]
    own_d = dofs[kept, labels[kept]]
    measured = (own_d > 0) & np.isfinite(own_r)
    n_samples = X0.shape[0]
    if not measured.any():
        return np.full(n_samples, -np.inf), np.zeros(n_samples, dtype=np.intp)
    noise = float(np.median(own_r[measured] / stats.chi2.median(own_d[measured])))
    testable = (dofs > 0) & np.isfinite(residuals)
    log_pvalues = np.full(residuals.shape, -np.inf)
    log_pvalues[testable] = _chi2_log_sf(
        residuals[testable] / max(noise, TINY), dofs[testable]
    )
    own = log_pvalues[kept, labels[kept]][measured]
    if own.size >= MIN_NULL_TRACKS:
        log_pvalues = np.where(testable, _empirical_null(log_pvalues, own), -np.inf)
    nearest = np.argmax(log_pvalues, axis=1).astype(np.intp)
    return log_pvalues[np.arange(n_samples), nearest], nearest


def _empirical_null(log_pvalues, own_log_pvalues):
    """Log p-values whose normal scores are divided by the width of the null.

    The width is that of the segmented tracks' scores under their own
    motion, measured on their lower half (see the module doc).
    """
    width = null_width(normal_scores(own_log_pvalues))
    return stats.norm.logsf(normal_scores(log_pvalues) / width)


def _chi2_log_sf(x, dof):
    """``log P(chi^2(dof) >= x)``, finite far in the tail too.

    Where scipy's ``logsf`` underflows, the leading term of the upper
    incomplete gamma function, ``Gamma(a, y) ~ y^(a - 1) e^(-y)`` (``a =
    dof / 2``, ``y = x / 2``), which then holds to a small relative error:
    the motions that a track misfits by far are still ranked.
    """
    out = stats.chi2.logsf(x, dof)
    far = ~np.isfinite(out)
    half, y = dof[far] / 2, x[far] / 2
    out[far] = (half - 1) * np.log(y) - y - special.gammaln(half)
    return out
