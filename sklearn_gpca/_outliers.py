"""Tracks that follow no motion, and the segmentation that sets them aside.

:func:`screened_segmentation` is what ``segment_motions(outlier_threshold=...)``
runs: the label-free local test of :mod:`sklearn_gpca._local_outliers`, then
the segmentation of the tracks that pass it, then the check of
:mod:`sklearn_gpca._explained_outliers` (a set-aside track that a segmented
motion's model explains is given that motion). :func:`outlier_pvalues` below
is the earlier test, against each motion's subspace (it needs labels): it
serves ``refine_observed(outlier_threshold=...)`` and
``benchmarks/bench_outliers.py`` (given the true labels, as a ceiling).

A track of motion ``k`` observed on the coordinates ``O`` of a window of
frames has, under Gaussian noise of variance ``sigma_k^2`` per coordinate,
a squared residual ``r`` to the motion's subspace with ``r / sigma_k^2 ~
chi^2(|O| - d)`` (``d`` the subspace dimension). A track that fits *no*
motion in some window is an outlier: a random walk fits none anywhere, a
tracker's drift or jump from one motion to another fits none in the windows
that straddle its switch (before and after it, it fits one motion each).

Choices, measured on ``make_tracks`` draws with the true labels
(``benchmarks/results/outliers.md``):

- windows of ``WINDOW`` frames, every ``WINDOW // 2`` frames: a switch is
  inside a window, and a perspective camera bends a track less over a window
  than over the whole sequence;
- subspaces of dimension ``TEST_DIM`` (8), not the 4 of an affine camera:
  over a window the tracks of a rigid motion seen in perspective lie close
  to a subspace of a few more dimensions (the depth enters the motion field
  through ``1 / Z``, ``x / Z``, ``y / Z``); with 4 dimensions the perspective
  bend of far-from-affine inliers is as large as a drift's misfit;
- the noise of each motion in each window, ``sigma_kw^2``, is robust: the
  median over the motion's tracks of ``r / m(dof)``, ``m(dof)`` the median
  of ``chi^2(dof)`` (so tracks with few degrees of freedom weigh right);
- the p-value of a track is ``P(chi^2(dof) >= r / sigma_kw^2)`` for its
  best-fitting motion, the smallest over its windows times the number of
  windows it is tested in (Bonferroni): the probability that a track with
  Gaussian residuals is flagged is then at most the threshold.
"""

# SPDX-License-Identifier: BSD-3-Clause

import copy
import logging

import numpy as np
from joblib import effective_n_jobs
from scipy import stats

from sklearn_gpca._observed_subspaces import (
    fit_observed_subspace,
    subspace_residuals,
)

_log = logging.getLogger(__name__)

#: Frames per window of the outlier test.
WINDOW = 16
#: Dimension of the motion subspaces of the outlier test (see module doc).
TEST_DIM = 8
# log-p-values are floored here: chi2.logsf underflows to -inf far in the tail.
_LOG_FLOOR = -700.0
#: Reweighted fits of each motion's window subspace (see _window_log_pvalues).
ROBUST_ROUNDS = 2
# Misfit (residual per degree of freedom over the noise) above which a track
# weighs less than 1 in the robust fit.
_HUBER = 4.0


def frame_windows(n_frames, window=WINDOW):
    """First frames of windows of ``window`` frames, every ``window // 2``.

    The last window ends at the last frame; one window when ``n_frames <=
    window``.

    Returns
    -------
    starts : ndarray of int
    width : int
        ``min(window, n_frames)``.
    """
    width = min(window, n_frames)
    last = n_frames - width
    starts = np.arange(0, last + 1, max(width // 2, 1))
    if starts[-1] != last:
        starts = np.append(starts, last)
    return starts, width


def _fold_dim(mw, folds, dim, min_dim):
    """Largest dimension <= dim that every fold of tracks can fit, or None.

    A subspace of dimension d needs d + 3 tracks and d + 2 coordinates
    observed by d of them.
    """
    d = min(dim, min(int(f.sum()) for f in folds) - 3)
    for fold in folds:
        seen = np.count_nonzero(mw[fold], axis=0)
        while d >= min_dim and np.count_nonzero(seen >= d) < d + 2:
            d -= 1
    return d if d >= min_dim else None


def _fit_log_pvalues(Xw, mw, members, dim, min_dim, weights=None):
    """Cross-fitted log-p-values and misfits of every track to one motion.

    The members are split in two folds (alternately, in row order); each
    member is scored against the subspace fitted to the other fold (so that
    an outlier among them cannot be absorbed by spare dimensions of a fit
    that contains it: a 4-D affine motion leaves ``dim - 4`` of them free),
    every other track against the better of the two fits.

    Returns None when the motion has too few tracks, else ``(log_p, z)``:
    ``log_p`` 0 for a track without a residual degree of freedom, ``z`` the
    residual per degree of freedom over the noise variance.
    """
    rows = np.flatnonzero(members)
    folds = []
    for part in (rows[0::2], rows[1::2]):
        fold = np.zeros_like(members)
        fold[part] = True
        folds.append(fold)
    d = _fold_dim(mw, folds, dim, min_dim)
    if d is None:
        return None
    r = np.empty((Xw.shape[0], 2))
    dof = np.empty((Xw.shape[0], 2), dtype=np.intp)
    for j, fold in enumerate(folds):
        w = None if weights is None else weights[fold]
        basis, support = fit_observed_subspace(Xw[fold], mw[fold], d, weights=w)
        residuals, dofs = subspace_residuals(Xw, mw, [basis], [support])
        r[:, j], dof[:, j] = residuals[:, 0], dofs[:, 0]
    # members: the other fold's fit; the others: the better fit
    other = np.where(folds[0], 1, 0)
    best = np.argmin(np.where(dof > 0, r / np.maximum(dof, 1), np.inf), axis=1)
    pick = np.where(members, other, best)
    r = r[np.arange(r.shape[0]), pick]
    dof = dof[np.arange(dof.shape[0]), pick]
    has = dof > 0
    own = has & members
    if np.count_nonzero(own) < 3:
        return None
    df = np.maximum(dof, 1)
    sigma2 = float(np.median(r[own] / stats.chi2.median(df[own])))
    sigma2 = max(sigma2, np.finfo(np.float64).tiny)
    log_p = np.maximum(stats.chi2.logsf(r / sigma2, df), _LOG_FLOOR)
    # strictly below 0 where tested, so that ``tested`` can be read off it
    log_p = np.where(has, np.minimum(log_p, -np.finfo(np.float64).tiny), 0.0)
    return log_p, np.where(has, r / (sigma2 * df), 0.0)


def _window_log_pvalues(Xw, mw, labels, n_motions, dim, min_dim):
    """``log P(chi^2 >= r / sigma^2)`` of every track to every motion.

    Returns ``(log_p, tested)``: ``log_p`` of shape (n_samples, n_motions),
    0 where the track has no residual degree of freedom or the motion has too
    few tracks in the window to fit; ``tested`` whether the track has a
    residual degree of freedom to some motion. The tracks of a motion too
    small to fit in the window are not tested there (they would be compared
    with the other motions only).
    """
    n_samples = Xw.shape[0]
    counts = np.count_nonzero(mw, axis=1)
    log_p = np.zeros((n_samples, n_motions))
    tested = np.zeros(n_samples, dtype=bool)
    unfitted = np.zeros(n_samples, dtype=bool)
    for k in range(n_motions):
        members = (labels == k) & (counts > min_dim)
        # Robust fit (iteratively reweighted): a first fit of dimension
        # min_dim, too small to absorb the outliers, sets weights
        # min(1, _HUBER / z) on the tracks' misfits z, then weighted fits of
        # dimension dim; a gross outlier weighs ~ 1/z, a bent inlier ~ 1.
        fit, weights = None, None
        for d in [min_dim] + [dim] * ROBUST_ROUNDS:
            attempt = _fit_log_pvalues(Xw, mw, members, d, min_dim, weights)
            if attempt is None:
                break
            fit, z = attempt
            weights = np.minimum(1.0, _HUBER / np.maximum(z, _HUBER))
        if fit is None:
            unfitted |= labels == k
            continue
        log_p[:, k] = fit
        tested |= fit < 0
    return log_p, tested & ~unfitted


def outlier_pvalues(
    X0, mask, labels, n_motions, *, dim=TEST_DIM, min_dim=4, window=WINDOW
):
    """Probability that each track fits its best motion as well as noise would.

    Parameters
    ----------
    X0 : ndarray of shape (n_samples, 2 * n_frames)
        Tracks, zero where missing.
    mask : ndarray of shape (n_samples, 2 * n_frames), dtype=bool
        Observed entries.
    labels : ndarray of shape (n_samples,)
        Motion of each track in ``0 .. n_motions - 1``; ``-1`` for tracks left
        out of the subspace fits and noise levels (they are still tested).
    n_motions : int
        Number of motions.
    dim : int, default=TEST_DIM
        Dimension of the subspaces of the test (lowered, not below
        ``min_dim``, for a motion with few tracks in a window).
    min_dim : int, default=4
        Smallest dimension fitted; a motion with too few tracks for it in a
        window leaves that window untested.
    window : int, default=WINDOW
        Frames per window.

    Returns
    -------
    pvalues : ndarray of shape (n_samples,)
        Bonferroni-corrected p-value in ``[0, 1]`` (see module doc); 1 for a
        track that cannot be tested (no residual degree of freedom in any
        window, e.g. seen in 2 frames or fewer).
    """
    labels = np.asarray(labels)
    n_samples, n_features = X0.shape
    starts, width = frame_windows(n_features // 2, window)
    frames = np.arange(n_features) // 2
    smallest = np.zeros(n_samples)
    n_tests = np.zeros(n_samples)
    for start in starts:
        cols = (frames >= start) & (frames < start + width)
        log_p, tested = _window_log_pvalues(
            X0[:, cols], mask[:, cols], labels, n_motions, dim, min_dim
        )
        best = log_p.max(axis=1)
        smallest = np.where(tested, np.minimum(smallest, best), smallest)
        n_tests += tested
    log_bonferroni = smallest + np.log(np.maximum(n_tests, 1))
    return np.minimum(np.exp(log_bonferroni), 1.0)


def screened_segmentation(
    segment,
    X,
    n_motions,
    *,
    outlier_threshold,
    init,
    return_info,
    assign=False,
    pooled=False,
    **kwargs,
):
    """Set aside the tracks that fail the local test, segment the others.

    The set-aside tracks are labelled ``-1``, or, with ``assign``, given the
    motion whose model fits them best once the others are segmented (then
    without the two-view test, which only clears false alarms).

    The test (:func:`sklearn_gpca._local_outliers.local_outlier_pvalues`)
    needs no segmentation, so the outliers are set aside *before* the
    candidate segmentations are drawn and one is selected: they can no
    longer pull a motion's subspace or merge two motions. Under strong
    perspective, a flagged track must also fail the two-view test of
    :func:`sklearn_gpca._epipolar_outliers.perspective_checked_pvalues`.
    Once the kept tracks are segmented, a set-aside track must also fit none
    of the motions' models
    (:func:`sklearn_gpca._explained_outliers.motion_model_log_pvalues`, not with
    ``assign``): one that fits is given that motion.

    Parameters
    ----------
    segment : callable
        ``sklearn_gpca._segment._segment_tracks``, called on the tracks that
        pass the test with the other keywords (``return_info`` and
        ``kwargs``).
    X : ndarray of shape (n_samples, 2 * n_frames)
        Tracks, NaN where missing (checked by the caller).
    n_motions : int
    outlier_threshold : float in (0, 1)
        False-alarm probability of the test per track.
    init : str or array-like of shape (n_samples,)
        As for ``segment``; an array is restricted to the kept tracks.
    return_info : bool
        Also return ``segment``'s Bunch (about the tracks segmented), with
        ``outlier_pvalues`` (every track's p-value: for a set-aside track the
        larger of the local test's and the motions' models') and
        ``outliers`` (bool mask of the tracks labelled ``-1``).
    assign : bool, default=False
        Give each set-aside track the motion whose model, fitted to the
        motion's kept tracks (its 4-D subspace on their observed entries;
        for the largest motion also its perspective cameras), fits the
        track best (the largest chi-square p-value,
        :func:`sklearn_gpca._explained_outliers.motion_model_log_pvalues`),
        instead of ``-1``.
    pooled : bool, default=False
        When tracks are set aside, also call ``segment`` on every track
        (``candidates_only=True``) and pass its refined candidates,
        restricted to the kept tracks, to the call on the kept tracks as
        ``extra_candidates``: judged there beside the kept tracks' own, on
        the kept tracks (see ``segment_motions``'s ``screen_outliers``).
    **kwargs
        Passed to ``segment``.

    Returns
    -------
    labels : ndarray of shape (n_samples,), dtype=intp
    info : Bunch
        Only with ``return_info``.
    """
    from sklearn_gpca._epipolar_outliers import perspective_checked_pvalues
    from sklearn_gpca._explained_outliers import (
        MIN_MODEL_TRACKS,
        motion_model_log_pvalues,
    )
    from sklearn_gpca._local_outliers import local_outlier_pvalues
    from sklearn_gpca._observed_subspaces import observed_entries

    n_samples = X.shape[0]
    if not isinstance(init, str):
        init = np.asarray(init)
        if init.shape != (n_samples,):
            raise ValueError(
                f"init must hold one label in 0 .. {n_motions - 1} per track "
                f"({n_samples}), got shape {init.shape}."
            )
    X0, mask = observed_entries(X)
    pvalues = local_outlier_pvalues(X0, mask)
    # a set-aside track that is then assigned costs little if it was a false
    # alarm: the two-view check, which only clears false alarms, is skipped
    if not assign and np.any(pvalues < outlier_threshold):
        pvalues = perspective_checked_pvalues(
            X0, mask, pvalues, n_motions, random_state=kwargs.get("random_state")
        )
    outliers = pvalues < outlier_threshold
    if np.count_nonzero(~outliers) <= n_motions:
        # too few tracks left to segment: the test is not applied
        outliers[:] = False
    kept = ~outliers
    _log.info(
        "outlier screening: %d of %d tracks set aside",
        np.count_nonzero(outliers),
        n_samples,
    )
    extra = {}
    if pooled and outliers.any() and n_motions > 1:
        extra = _pooled_candidates(segment, X, kept, n_motions, init=init, **kwargs)
    result = segment(
        X[kept],
        n_motions,
        init=init if isinstance(init, str) else init[kept],
        return_info=return_info,
        **kwargs,
        **extra,
    )
    labels = np.full(n_samples, -1, dtype=np.intp)
    labels[kept] = result[0] if return_info else result
    if outliers.any():
        log_pvalues, nearest = motion_model_log_pvalues(
            X0,
            mask,
            labels,
            n_motions,
            perspective=kwargs.get("perspective_background", True),
            # assigned: every motion competes, however few its kept tracks
            min_tracks=1 if assign else MIN_MODEL_TRACKS,
        )
        if assign:
            labels = _assigned(X0, mask, labels, kept, n_motions, log_pvalues, nearest)
        else:
            cleared = outliers & (log_pvalues >= np.log(outlier_threshold))
            labels[cleared] = nearest[cleared]
            _log.info(
                "outlier check: %d of %d set-aside tracks fit a motion's model "
                "and keep it",
                np.count_nonzero(cleared),
                np.count_nonzero(outliers),
            )
            pvalues = np.where(
                outliers, np.maximum(pvalues, np.exp(log_pvalues)), pvalues
            )
            outliers &= ~cleared
    if return_info:
        info = result[1]
        info.outlier_pvalues = pvalues
        info.outliers = outliers
        return labels, info
    return labels


def _assigned(X0, mask, labels, kept, n_motions, log_pvalues, nearest):
    """Labels with every set-aside track given the motion whose model fits it best.

    ``nearest`` and ``log_pvalues`` are from
    :func:`sklearn_gpca._explained_outliers.motion_model_log_pvalues`: the
    largest motion is also modelled by a perspective camera, which its
    nearest tracks need (they are the ones the local test sets aside under
    strong perspective). A track that no model tests gets the nearest 4-D
    subspace of the kept tracks' motions on its observed entries.
    """
    from sklearn_gpca._segment import _nearest_labels

    assigned = np.where(kept, labels, nearest).astype(np.intp)
    untested = ~kept & ~np.isfinite(log_pvalues)
    if untested.any():
        fallback = _nearest_labels(X0, mask, np.maximum(labels, 0), kept, n_motions)
        assigned[untested] = fallback[untested]
    return assigned


def _pooled_candidates(segment, X, kept, n_motions, *, init, **kwargs):
    """Keywords of the call on the kept tracks that judges every track's candidates too.

    The candidates of every track and those of the kept tracks are drawn and
    refined (``segment(..., candidates_only=True)``), in two processes when
    ``kwargs["n_jobs"]`` allows (each then with half the jobs), and the
    former, restricted to the kept tracks, join the latter's judgement as
    ``extra_candidates``, with their background cameras (which start the
    perspective fits that judge them, as they do the kept tracks' own).
    Every track's candidates draw from a copy of a ``RandomState`` instance,
    so that the labels do not depend on the jobs.
    """
    from sklearn_gpca._jobs import map_jobs
    from sklearn_gpca._projective_motion import rescaled_cameras

    n_jobs = effective_n_jobs(kwargs.get("n_jobs"))
    inner = dict(kwargs, return_info=False, n_jobs=max(1, n_jobs // 2))
    random_state = kwargs.get("random_state")
    if isinstance(random_state, np.random.RandomState):
        random_state = copy.deepcopy(random_state)
    calls = [
        (X, init, dict(inner, random_state=random_state)),
        (X[kept], init if isinstance(init, str) else init[kept], inner),
    ]

    def refined_candidates(call):
        tracks, start, keywords = call
        return segment(tracks, n_motions, init=start, candidates_only=True, **keywords)

    everything, own = map_jobs(refined_candidates, calls, min(n_jobs, 2))
    extra = [
        (
            f"{name}, from every track",
            labels[kept],
            None if cameras is None else rescaled_cameras(cameras, everything.scale),
        )
        for name, labels, cameras in zip(
            everything.candidates, everything.refined, everything.cameras, strict=True
        )
    ]
    return {"extra_candidates": extra, "candidates": own}
