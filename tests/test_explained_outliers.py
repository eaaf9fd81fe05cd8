"""The check that clears the local outlier test's false alarms."""

import numpy as np
import pytest
from _outlier_draws import affine_lab_draw

import sklearn_gpca._local_outliers as local_outliers
from sklearn_gpca import segment_motions
from sklearn_gpca._explained_outliers import (
    MIN_MODEL_TRACKS,
    motion_model_log_pvalues,
)
from sklearn_gpca._observed_subspaces import (
    fit_observed_subspace,
    observed_entries,
    subspace_residuals,
)
from sklearn_gpca._outliers import _assigned
from sklearn_gpca._segment import _nearest_labels
from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.metrics import misclassification_rate


def _motions(rng, sizes, n_frames=20, noise=0.01, n_outliers=10):
    """Tracks on random 4-D subspaces plus noise, and random outlier tracks."""
    X, y = [], []
    for k, n in enumerate(sizes):
        basis = np.linalg.qr(rng.normal(size=(2 * n_frames, 4)))[0]
        X.append(rng.normal(size=(n, 4)) @ basis.T)
        y.append(np.full(n, k))
    X.append(rng.normal(size=(n_outliers, 2 * n_frames)))
    y.append(np.full(n_outliers, -1))
    X = np.vstack(X)
    return X + noise * rng.normal(size=X.shape), np.concatenate(y)


@pytest.mark.parametrize("perspective", [False, True])
def test_inliers_fit_their_motion_and_outliers_none(perspective):
    rng = np.random.RandomState(0)
    X, y = _motions(rng, [150, 100, 80])
    X0, mask = observed_entries(X)
    log_p, nearest = motion_model_log_pvalues(X0, mask, y, 3, perspective=perspective)
    pvalues = np.exp(log_p)
    inliers = y >= 0
    assert np.all(pvalues[~inliers] < 1e-6)
    # far in the tail the log p-values stay finite: the outliers still get
    # the motion they misfit least
    assert np.all(np.isfinite(log_p))
    assert np.array_equal(nearest[inliers], y[inliers])
    # the inliers' p-values are those of their own motion's chi-square test:
    # few are small (the fit is in sample: if anything, conservative)
    slack = 3 * np.sqrt(0.05 * 0.95 / inliers.sum())
    assert np.mean(pvalues[inliers] < 0.05) <= 0.05 + slack
    assert np.mean(pvalues[inliers] < 0.5) > 0.2


@pytest.mark.parametrize("scale", [1e-3, 1e3])
def test_pvalues_do_not_depend_on_the_units(scale):
    rng = np.random.RandomState(1)
    X, y = _motions(rng, [60, 60], n_frames=12)
    X0, mask = observed_entries(X)
    Xs0, masks = observed_entries(scale * X)
    p, nearest = motion_model_log_pvalues(X0, mask, y, 2, perspective=False)
    ps, nearests = motion_model_log_pvalues(Xs0, masks, y, 2, perspective=False)
    np.testing.assert_allclose(ps, p, rtol=1e-6, atol=1e-9)
    assert np.array_equal(nearests, nearest)


def test_small_motions_and_untestable_tracks_explain_nothing():
    rng = np.random.RandomState(2)
    X, y = _motions(rng, [80, 80, 40], n_frames=12, n_outliers=0)
    labels = y.copy()
    # motion 2 keeps fewer tracks than a model needs: its others fit no model
    third = np.flatnonzero(y == 2)
    labels[third[MIN_MODEL_TRACKS - 1 :]] = -1
    # a track of motion 0 seen in 2 frames has no residual degree of freedom
    X[0, 4:] = np.nan
    labels[0] = -1
    X0, mask = observed_entries(X)
    log_p, _ = motion_model_log_pvalues(X0, mask, labels, 3, perspective=False)
    assert log_p[0] == -np.inf
    assert np.all(log_p[third[MIN_MODEL_TRACKS - 1 :]] < np.log(1e-6))


def test_no_measurable_noise_clears_nothing():
    rng = np.random.RandomState(3)
    X, y = _motions(rng, [20, 20], n_frames=12)
    labels = np.full(y.size, -1)
    X0, mask = observed_entries(X)
    log_p, nearest = motion_model_log_pvalues(X0, mask, labels, 2)
    assert np.all(log_p == -np.inf)
    assert np.all(nearest == 0)


def _flagged_lab_draw(monkeypatch):
    """A lab draw whose local test (faked) flags every outlier and 8 inliers."""
    X, y = affine_lab_draw(0)[:2]
    false_alarms = np.flatnonzero(y >= 0)[::16][:8]
    flagged = (y == -1) | np.isin(np.arange(y.size), false_alarms)
    monkeypatch.setattr(
        local_outliers,
        "local_outlier_pvalues",
        lambda X0, mask, *args, **kwargs: np.where(flagged, 1e-9, 1.0),
    )
    return X, y, false_alarms, flagged


def test_segment_motions_keeps_false_alarms_a_motion_explains(monkeypatch):
    # The inliers the local test flags fit their motion's model and get its
    # label back; the outliers (random walks and switches far from every
    # motion) stay -1.
    X, y, false_alarms, _ = _flagged_lab_draw(monkeypatch)
    n = int(y.max()) + 1
    labels, info = segment_motions(
        X, n, outlier_threshold=1e-3, random_state=0, return_info=True
    )
    inliers = y >= 0
    assert np.all(labels[inliers] >= 0)
    assert misclassification_rate(y[inliers], labels[inliers]) <= 0.01
    assert np.array_equal(info.outliers, labels == -1)
    assert np.all(info.outlier_pvalues[false_alarms] >= 1e-3)
    # the outliers are those of make_tracks: a few drift onto a motion that
    # moves alike and fit it; most do not
    assert np.mean(labels[y == -1] == -1) >= 0.8


@pytest.mark.parametrize("seed", [1, 3])
def test_set_aside_background_tracks_go_back_to_the_background(seed):
    # Under strong perspective the background tracks that misfit its 4-D
    # subspace most (the nearest ones, which the local test sets aside) fit
    # its perspective cameras: the default's assignment gives every one of
    # them back to the background, where the nearest 4-D subspace sends
    # some of them to another motion (2-13 of 30 on seeds 0-3).
    X, y = make_tracks(scene="driving", random_state=seed)[:2]
    X, y = X[y >= 0], y[y >= 0]
    X0, mask = observed_entries(X)
    background = y == np.argmax(np.bincount(y))
    basis, support = fit_observed_subspace(X0[background], mask[background], 4)
    residuals, dofs = subspace_residuals(X0, mask, [basis], [support])
    misfit = np.where(background, residuals[:, 0] / np.maximum(dofs[:, 0], 1), -1.0)
    aside = np.isin(np.arange(y.size), np.argsort(misfit)[-30:])
    labels = np.where(aside, -1, y)
    log_p, nearest = motion_model_log_pvalues(X0, mask, labels, 3)
    assigned = _assigned(X0, mask, labels, ~aside, 3, log_p, nearest)
    assert np.array_equal(assigned, y)
    subspace_only = _nearest_labels(X0, mask, np.maximum(labels, 0), ~aside, 3)
    assert np.sum(subspace_only[aside] != y[aside]) >= 2


def test_default_gives_set_aside_tracks_their_motion(monkeypatch):
    # Without outlier_threshold the set-aside tracks (every outlier and
    # eight inliers) all get a motion, the inliers their own.
    X, y, _, flagged = _flagged_lab_draw(monkeypatch)
    n = int(y.max()) + 1
    labels, info = segment_motions(X, n, random_state=0, return_info=True)
    assert np.array_equal(info.outliers, flagged)
    assert np.all((labels >= 0) & (labels < n))
    inliers = y >= 0
    assert misclassification_rate(y[inliers], labels[inliers]) <= 0.01


def test_uneven_noise_widens_the_null():
    # Real tracks' noise differs from track to track: here each inlier's
    # noise is 0.5 to 2 times a common level. Against one Gaussian level a
    # quarter of the inliers is rejected; under the empirical null few are,
    # while the outliers still fit no motion.
    rng = np.random.RandomState(4)
    X, y = _motions(rng, [150, 100, 80], noise=0.0)
    inliers = y >= 0
    levels = 0.01 * np.exp(rng.uniform(np.log(0.5), np.log(2.0), size=y.size))
    X[inliers] += levels[inliers, None] * rng.normal(size=X[inliers].shape)
    X0, mask = observed_entries(X)
    log_p, nearest = motion_model_log_pvalues(X0, mask, y, 3, perspective=False)
    assert np.mean(log_p[inliers] < np.log(1e-3)) <= 0.02
    assert np.array_equal(nearest[inliers], y[inliers])
    assert np.all(log_p[~inliers] < np.log(1e-6))


def test_tracks_no_model_tests_get_the_nearest_subspace():
    # Motions of fewer than MIN_MODEL_TRACKS kept tracks explain nothing: the
    # set-aside tracks then get the nearest 4-D subspace of the kept tracks.
    rng = np.random.RandomState(5)
    X, y = _motions(rng, [10, 10], n_frames=12, n_outliers=0)
    kept = np.ones(y.size, dtype=bool)
    kept[[0, 10]] = False
    labels = np.where(kept, y, -1)
    X0, mask = observed_entries(X)
    log_p, nearest = motion_model_log_pvalues(X0, mask, labels, 2)
    assert np.all(log_p == -np.inf)
    assert np.array_equal(_assigned(X0, mask, labels, kept, 2, log_p, nearest), y)


def test_default_gives_a_small_motion_its_set_aside_tracks(monkeypatch):
    # A small object (14 tracks) whose local test (faked) sets half its
    # tracks aside keeps 7, fewer than MIN_MODEL_TRACKS: its model must
    # still compete for the set-aside tracks, or they all go to the
    # background (Hopkins155 head: 3.0 -> 9.1 %).
    rng = np.random.RandomState(6)
    X, y = _motions(rng, [100, 14], n_frames=12, n_outliers=0)
    flagged = np.isin(np.arange(y.size), [0, 1, *range(100, 107)])
    monkeypatch.setattr(
        local_outliers,
        "local_outlier_pvalues",
        lambda X0, mask, *args, **kwargs: np.where(flagged, 1e-9, 1.0),
    )
    labels, info = segment_motions(X, 2, random_state=0, return_info=True)
    assert np.array_equal(info.outliers, flagged)
    assert misclassification_rate(y, labels) == 0.0
