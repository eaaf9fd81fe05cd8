"""Tests for the consistency of a segmentation with its own motion models."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
from _subspace_draws import subspace_tracks

from sklearn_gpca._model_consistency import model_consistency
from sklearn_gpca._observed_subspaces import observed_entries
from sklearn_gpca._segment_selection import select_segmentation
from sklearn_gpca.datasets import make_tracks


@pytest.mark.parametrize("missing", [0.0, 0.3])
@pytest.mark.parametrize("seed", range(2))
def test_truth_is_consistent_and_fits_best(missing, seed):
    X, y = subspace_tracks(missing=missing, seed=seed)
    X0, mask = observed_entries(X)
    rng = np.random.default_rng(seed)
    # motions 1 and 2 merged, motion 0 cut in two
    merged = np.where(y == 2, 1, y)
    merged[np.flatnonzero(y == 0)[::2]] = 2
    # 30 % of the tracks relabelled at random
    mixed = y.copy()
    moved = rng.choice(y.size, 3 * y.size // 10, replace=False)
    mixed[moved] = (y[moved] + rng.integers(1, 3, moved.size)) % 3
    truth, fit = model_consistency(X0, mask, y, 1.0, perspective_background=False)
    assert truth == 0.0
    # per degree of freedom, unit noise: each true track adds about log(1 + 1)
    assert fit == pytest.approx(y.size * np.log(2), rel=0.15)
    wrong, wrong_fit = model_consistency(
        X0, mask, merged, 1.0, perspective_background=False
    )
    # the merged motions misfit their 4-D subspace by far
    assert wrong_fit > 4 * fit
    assert wrong > 0.05
    # tracks of another motion in a group stay nearer their true motion
    assert model_consistency(X0, mask, mixed, 1.0, perspective_background=False)[
        0
    ] == pytest.approx(0.3, abs=0.12)


def test_perspective_background_is_consistent_where_subspaces_are_not():
    # 100 hand-held frames: the background spans no 4-D subspace
    X, y = make_tracks(scene="handheld", n_tracks=400, random_state=3)
    X, y = X[y >= 0], y[y >= 0]
    X0, mask = observed_entries(X)
    X0 = X0 / np.sqrt(np.mean(X0[mask] ** 2))
    background = np.argmax(np.bincount(y))
    first = np.argmax(mask[:, ::2], axis=1)
    x = X0[np.arange(y.size), 2 * first]
    right = (y == background) & (x > np.median(x[y == background]))
    # the background cut in two, the objects merged
    cut = np.where(right, 2, np.where(y == background, 0, 1))
    noise = 1e-6
    truth = model_consistency(X0, mask, y, noise)[0]
    affine = model_consistency(X0, mask, y, noise, perspective_background=False)[0]
    wrong = model_consistency(X0, mask, cut, noise)[0]
    assert truth < 0.02 < affine
    assert wrong > truth + 0.1


@pytest.mark.parametrize("missing", [0.0, 0.3])
def test_fit_measures_misfits_when_the_noise_is_underestimated(missing):
    # a noise estimate 10^6 times too small (near-duplicate neighbours) puts
    # every track far beyond it: the fit still ranks the truth first
    X, y = subspace_tracks(missing=missing, seed=0)
    X0, mask = observed_entries(X)
    moved = y.copy()
    moved[np.flatnonzero(y == 0)[:3]] = 1
    for noise in (1.0, 1e-6):
        truth = model_consistency(X0, mask, y, noise, perspective_background=False)
        wrong = model_consistency(X0, mask, moved, noise, perspective_background=False)
        assert truth[1] < wrong[1]


def test_too_few_modelled_groups_give_nan():
    X, y = subspace_tracks(sizes=(40, 5), n_frames=8)
    X0, mask = observed_entries(X)
    # 5 tracks are enough for a 4-D subspace with a residual, 4 are not
    assert np.isfinite(model_consistency(X0, mask, y, 1.0)).all()
    X, y = subspace_tracks(sizes=(40, 4), n_frames=8)
    X0, mask = observed_entries(X)
    assert np.isnan(model_consistency(X0, mask, y, 1.0)).all()
    assert np.isnan(model_consistency(X0, mask, np.zeros_like(y), 1.0)).all()
    # one observed frame: no track keeps a residual degree of freedom
    X, y = subspace_tracks(sizes=(40, 40), n_frames=8)
    X[:, 2:] = np.nan
    X0, mask = observed_entries(X)
    assert np.isnan(model_consistency(X0, mask, y, 1.0)).all()


def test_tracks_of_a_group_too_small_to_model_count_as_misfits():
    # three of a motion's tracks set apart fit their own group exactly; they
    # are judged by the nearest modelled group instead, as misfits, so that
    # setting the worst-fitting tracks apart does not pay
    X, y = subspace_tracks(sizes=(60, 40, 40), n_frames=8)
    X0, mask = observed_entries(X)
    apart = y.copy()
    apart[:3] = 3
    kw = {"perspective_background": False, "per_track": True}
    truth, truth_fit, _ = model_consistency(X0, mask, y, 1.0, **kw)
    share, fit, tracks = model_consistency(X0, mask, apart, 1.0, **kw)
    np.testing.assert_array_equal(tracks[:3, 1], 1.0)
    assert share == pytest.approx(truth + 3 / y.size)
    assert np.all(np.isfinite(tracks[:3, 0]))
    assert fit == pytest.approx(truth_fit, abs=1.0)


@pytest.mark.parametrize(
    ("inconsistency", "residual", "expected"),
    [
        # candidate 1 fits best but is inconsistent; 0 and 2 within 0.02
        ([0.0, 0.5, 0.01], [3.0, 1.0, 2.0], 2),
        ([0.0, 0.5, 0.1], [3.0, 1.0, 2.0], 0),
        # NaN (fewer than two motions modelled): never kept, unless all are
        ([0.0, np.nan, 0.01], [3.0, np.nan, 2.0], 2),
        ([np.nan, np.nan, np.nan], [np.nan, np.nan, np.nan], 0),
    ],
)
def test_select_by_consistency(inconsistency, residual, expected):
    chosen = select_segmentation(
        [1.0, 1.0, 1.0],
        [0.0, 0.0, 0.0],
        selection="consistency",
        tolerance=0.02,
        inconsistency=inconsistency,
        residual=residual,
    )
    assert chosen == expected


@pytest.mark.parametrize(
    ("misfit_cost", "expected"),
    [
        # 100 tracks: candidate 1 has 10 more inconsistent tracks and fits
        # 50 better; at cost 4 they cost 40 (it wins), at cost 8, 80 (it loses)
        (4.0, 1),
        (8.0, 0),
        (None, 1),
    ],
)
def test_select_by_penalised_fit(misfit_cost, expected):
    chosen = select_segmentation(
        [1.0, 1.0],
        [0.0, 0.0],
        selection="consistency",
        tolerance=1.0,
        inconsistency=[0.0, 0.1],
        residual=[300.0, 250.0],
        misfit_cost=misfit_cost,
        n_tracks=100,
    )
    assert chosen == expected


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({}, "needs inconsistency and residual"),
        ({"inconsistency": [0.1], "residual": [1.0, 2.0]}, "one value per candidate"),
        (
            {"inconsistency": [0.1, 0.0], "residual": [1.0, 2.0], "misfit_cost": 8.0},
            "misfit_cost needs n_tracks",
        ),
    ],
)
def test_select_by_consistency_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        select_segmentation(
            [1.0, 2.0], [0.1, 0.1], selection="consistency", tolerance=0.02, **kwargs
        )


def test_perspective_fit_also_starts_from_the_affine_cameras(monkeypatch):
    # a sequential perspective fit that settles badly (here: cameras that see
    # nothing of the tracks) must not count against the segmentation: the fit
    # started from the group's affine cameras explains it
    import sklearn_gpca._model_consistency as module

    X, y = make_tracks(
        scene="lab", camera="affine", n_tracks=200, n_frames=20, random_state=0
    )
    X, y = X[y >= 0], y[y >= 0]
    X0, mask = observed_entries(X)
    X0 = X0 / np.sqrt(np.mean(X0[mask] ** 2))
    noise = 1e-6
    affine = model_consistency(X0, mask, y, noise, perspective_background=False)
    working = model_consistency(X0, mask, y, noise)
    fit = module.fit_projective_motion

    def settles_badly(X0, mask, cameras=None):
        if cameras is not None:
            return fit(X0, mask, cameras=cameras)
        fitted = np.zeros((mask.shape[1] // 2, 3, 4))
        fitted[:, 2, 3] = 1.0
        return fitted, np.ones(mask.shape[1] // 2, dtype=bool)

    monkeypatch.setattr(module, "fit_projective_motion", settles_badly)
    rescued = model_consistency(X0, mask, y, noise)
    assert rescued[0] == pytest.approx(working[0], abs=0.02)
    # an affine camera is a perspective one: no worse than the 4-D subspaces
    # by more than the perspective model's fewer parameters per track allow
    assert rescued[1] <= max(working[1], affine[1]) + 0.05 * y.size


@pytest.mark.parametrize("perspective_background", [False, True])
def test_per_track_terms_add_up_to_the_scores(perspective_background):
    X, y = subspace_tracks(missing=0.3, seed=0)
    X0, mask = observed_entries(X)
    mixed = y.copy()
    mixed[::7] = (y[::7] + 1) % 3
    inconsistency, fit, tracks = model_consistency(
        X0,
        mask,
        mixed,
        1.0,
        perspective_background=perspective_background,
        per_track=True,
    )
    assert (inconsistency, fit) == model_consistency(
        X0, mask, mixed, 1.0, perspective_background=perspective_background
    )
    tested = np.isfinite(tracks).all(axis=1)
    assert tested.sum() > 0.9 * y.size
    assert np.sum(tracks[tested, 0]) == pytest.approx(fit)
    assert np.mean(tracks[tested, 1]) == pytest.approx(inconsistency)
    assert set(np.unique(tracks[tested, 1])) <= {0.0, 1.0}
    # the relabelled tracks are those nearer another group's model
    assert np.mean(tracks[::7, 1][tested[::7]]) > 0.8
