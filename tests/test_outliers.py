"""Tests of the outlier test (label -1) of segment_motions."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
from _outlier_draws import affine_lab_draw
from hypothesis import given
from hypothesis import strategies as st

from sklearn_gpca import MotionSegmentation, segment_motions
from sklearn_gpca._observed_subspaces import observed_entries
from sklearn_gpca._outliers import frame_windows, outlier_pvalues
from sklearn_gpca.metrics import misclassification_rate


@given(n_frames=st.integers(1, 80), window=st.integers(1, 30))
def test_frame_windows_cover_every_frame(n_frames, window):
    starts, width = frame_windows(n_frames, window)
    assert width == min(window, n_frames)
    covered = np.zeros(n_frames, dtype=bool)
    for start in starts:
        covered[start : start + width] = True
    assert covered.all()
    assert starts[0] == 0
    assert starts[-1] + width == n_frames
    assert np.all(np.diff(starts) > 0)


def _subspace_tracks(n_per_motion, n_frames, noise, rng, missing=0.0):
    """Tracks on random 4-D subspaces of R^{2F} plus Gaussian noise."""
    X, y = [], []
    for k, n in enumerate(n_per_motion):
        basis = np.linalg.qr(rng.normal(size=(2 * n_frames, 4)))[0]
        X.append(rng.normal(size=(n, 4)) @ basis.T)
        y.append(np.full(n, k))
    X = np.vstack(X) + noise * rng.normal(size=(sum(n_per_motion), 2 * n_frames))
    if missing:
        # one window of frames per track
        length = rng.randint(4, n_frames + 1, size=X.shape[0])
        birth = rng.randint(0, n_frames - length + 1)
        frames = np.arange(n_frames)
        seen = (frames >= birth[:, None]) & (frames < (birth + length)[:, None])
        X[~np.repeat(seen, 2, axis=1)] = np.nan
    return X, np.concatenate(y)


@pytest.mark.parametrize("missing", [False, True])
def test_pvalues_of_gaussian_inliers_are_conservative(missing):
    # Under the test's own model (subspaces of dimension <= the test's, Gaussian
    # noise), P(p < alpha) <= alpha for each track: Bonferroni over windows is
    # conservative. 600 tracks: the fraction below 0.05 is at most 0.05 plus
    # three binomial standard deviations.
    rng = np.random.RandomState(0)
    X, y = _subspace_tracks([300, 300], 24, 0.01, rng, missing=missing)
    X0, mask = observed_entries(X)
    p = outlier_pvalues(X0, mask, y, 2)
    for alpha in (0.05, 0.2):
        slack = 3 * np.sqrt(alpha * (1 - alpha) / y.size)
        assert np.mean(p < alpha) <= alpha + slack
    # ... and not degenerate: with one window the p-values are uniform, so a
    # good share is small
    assert np.mean(p < 0.2) > 0.05


def test_pvalues_scale_free_and_shape():
    rng = np.random.RandomState(1)
    X, y = _subspace_tracks([80, 60], 10, 0.01, rng)
    X0, mask = observed_entries(X)
    p = outlier_pvalues(X0, mask, y, 2)
    assert p.shape == (y.size,)
    assert np.all((p >= 0) & (p <= 1))
    X0s, masks = observed_entries(1000.0 * X)
    np.testing.assert_allclose(outlier_pvalues(X0s, masks, y, 2), p, rtol=1e-6)


def test_untestable_tracks_get_pvalue_one():
    rng = np.random.RandomState(2)
    X, y = _subspace_tracks([60, 60], 10, 0.01, rng)
    X[:5, 4:] = np.nan  # seen in 2 frames: no residual degree of freedom
    X[:5, :4] = rng.normal(size=(5, 4))  # and anywhere
    X0, mask = observed_entries(X)
    assert np.all(outlier_pvalues(X0, mask, y, 2)[:5] == 1.0)


def _excess_misfit(info, y):
    """Noise-free residual of every track to its nearest true motion subspace,
    on its observed frames, in units of the noise variance per coordinate."""
    clean = info.X_clean
    mask = ~np.isnan(clean)
    clean = np.where(mask, clean, 0.0) / np.tile(info.noise, clean.shape[1] // 2)
    best = np.full(y.size, np.inf)
    for M in info.motion_matrices:
        M = M / np.tile(info.noise, M.shape[0] // 2)[:, None]
        for p in range(y.size):  # a test helper: few tracks
            A, b = M[mask[p]], clean[p, mask[p]]
            r = b - A @ np.linalg.lstsq(A, b, rcond=None)[0]
            best[p] = min(best[p], r @ r)
    return best


@pytest.mark.parametrize("seed", range(2))
def test_true_labels_flag_every_clear_outlier_and_no_inlier(seed):
    # Affine camera: every inlier is exactly on its motion's 4-D subspace plus
    # Gaussian noise, so the chance that any of the n inliers is flagged at
    # alpha is about n * alpha (0.0014 here; the test's p-values are within a
    # factor 2 of calibrated on Gaussian draws of this size); an outlier whose
    # noise-free misfit to every true subspace is 2000 noise variances (vs. a chi-square
    # with <= 24 degrees of freedom) is flagged in some window of 16 frames
    # whatever the split of its misfit between the 1-2 windows of a 12-frame
    # draw.
    X, y, info = affine_lab_draw(seed)
    X0, mask = observed_entries(X)
    flagged = outlier_pvalues(X0, mask, y, int(y.max()) + 1) < 1e-5
    assert not np.any(flagged & (y >= 0))
    clear = (y == -1) & (_excess_misfit(info, y) > 2000)
    assert clear.sum() >= 5
    assert np.all(flagged[clear])


def test_segment_motions_flags_outliers_of_a_draw():
    # segment_motions (outliers not known) started from the true motions with
    # every outlier put in a random motion: the local test flags the clear
    # outliers (as above) and no inlier, and the inliers keep their labels.
    X, y, info = affine_lab_draw(0)
    n = int(y.max()) + 1
    start = np.where(y >= 0, y, np.random.RandomState(0).randint(n, size=y.size))
    labels = segment_motions(X, n, init=start, outlier_threshold=1e-5, random_state=0)
    inliers = y >= 0
    assert not np.any(labels[inliers] == -1)
    clear = (y == -1) & (_excess_misfit(info, y) > 2000)
    assert np.all(labels[clear] == -1)
    assert misclassification_rate(y[inliers], labels[inliers]) <= 0.01
    # the -1 of segment_motions is scored as noise, never renamed
    rate = misclassification_rate(y, labels)
    missed = np.sum((y == -1) & (labels != -1))
    assert rate <= (missed + np.sum(inliers) * 0.01) / y.size + 1e-12


def test_clean_draw_flags_no_inlier():
    X, y, _ = affine_lab_draw(1, outlier_fraction=0.0)
    labels = segment_motions(X, int(y.max()) + 1, outlier_threshold=1e-3)
    assert not np.any(labels == -1)


def test_outlier_labels_drawn_by_the_display():
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    from sklearn_gpca.plotting import TrajectoryDisplay

    X, y, _ = affine_lab_draw(0)
    start = np.where(y >= 0, y, 0)
    labels = segment_motions(X, 2, init=start, outlier_threshold=1e-5, random_state=0)
    display = TrajectoryDisplay.from_predictions(X, labels, y_true=y)
    legend = [t.get_text() for t in display.ax_.get_legend().get_texts()]
    assert "outliers (-1)" in legend


@pytest.mark.parametrize("threshold", [0.0, 1.0, 20.0, -0.5])
def test_bad_thresholds_refused(threshold):
    X = np.random.RandomState(0).normal(size=(12, 8))
    with pytest.raises(ValueError, match=r"outlier_threshold.*range"):
        segment_motions(X, 2, outlier_threshold=threshold)
    with pytest.raises(ValueError, match=r"outlier_threshold.*range"):
        MotionSegmentation(2, outlier_threshold=threshold).fit(X)
