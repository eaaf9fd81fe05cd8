"""Tests for the re-segmented starts of segment_motions (sklearn_gpca._resegment)."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest

from sklearn_gpca import segment_motions
from sklearn_gpca._merge_split import significantly_better
from sklearn_gpca._observed_subspaces import observed_entries
from sklearn_gpca._resegment import resegmented_starts
from sklearn_gpca._segment import GRAPH_NEIGHBORS, MISFIT_COST, RESEGMENT_LEVEL
from sklearn_gpca.datasets import make_motions, make_tracks
from sklearn_gpca.metrics import misclassification_rate


def _draw(seed, n_motions=3, missing=0.0):
    sizes = [240] + [50] * (n_motions - 1)
    X, y = make_motions(
        n_motions,
        n_points=sizes,
        n_frames=12,
        noise=0.5,
        missing=missing,
        missing_pattern="occlusion",
        random_state=seed,
    )
    X0, mask = observed_entries(X)
    scale = np.sqrt(np.mean(X0[mask] ** 2))
    return X0 / scale, mask, y, (0.5 / scale) ** 2


def _starts(X0, mask, labels, n_motions, noise, seed=0):
    return resegmented_starts(
        X0,
        mask,
        labels,
        n_motions,
        noise,
        n_neighbors=GRAPH_NEIGHBORS,
        random_state=np.random.RandomState(seed),
    )


def _mixed_objects(y, seed):
    """The largest motion right, the other tracks' labels drawn at random."""
    rng = np.random.default_rng(seed)
    largest = np.argmax(np.bincount(y))
    others = np.delete(np.unique(y), largest)
    labels = y.copy()
    rest = np.flatnonzero(y != largest)
    labels[rest] = rng.choice(others, rest.size)
    return labels, largest


@pytest.mark.parametrize(("seed", "missing"), [(0, 0.0), (1, 0.0), (2, 0.3)])
def test_resegmented_start_separates_objects_a_start_mixed(seed, missing):
    # the background found, the two objects' tracks labelled at random: the
    # rest's own motion graph separates them again
    X0, mask, y, noise = _draw(seed, missing=missing)
    labels, largest = _mixed_objects(y, seed)
    assert misclassification_rate(y, labels) > 0.1
    starts = _starts(X0, mask, labels, 3, noise)
    assert starts
    assert all(name.startswith("re-segmented ") for name, _ in starts)
    errors = [misclassification_rate(y, start) for _, start in starts]
    assert min(errors) < 0.02
    for _, start in starts:
        # the largest motion keeps its tracks and its label
        np.testing.assert_array_equal(start == largest, y == largest)
        assert set(np.unique(start)) <= set(range(3))


def test_resegmented_starts_use_every_label_but_the_largest_for_the_rest():
    X0, mask, y, noise = _draw(3, n_motions=4)
    labels, largest = _mixed_objects(y, 3)
    starts = _starts(X0, mask, labels, 4, noise)
    assert starts
    for _, start in starts:
        assert set(np.unique(start[y != largest])) <= set(range(4)) - {largest}


def test_no_resegmented_start_for_two_motions_or_too_few_other_tracks():
    X0, mask, y, noise = _draw(0)
    largest = np.argmax(np.bincount(y))
    # two motions: the rest is one motion, nothing to segment
    two = np.where(y == largest, 0, 1)
    assert _starts(X0, mask, two, 2, noise) == []
    # three motions, but only a handful of tracks outside the largest
    few = np.full(y.size, largest)
    few[np.flatnonzero(y != largest)[:10]] = (largest + 1) % 3
    assert _starts(X0, mask, few, 3, noise) == []


@pytest.mark.parametrize(("n_motions", "expected"), [(2, False), (3, True)])
def test_segment_motions_judges_resegmented_candidates(n_motions, expected):
    X, y = make_motions(
        n_motions,
        n_points=[150] + [40] * (n_motions - 1),
        n_frames=10,
        missing=0.2,
        random_state=0,
    )
    labels, info = segment_motions(X, n_motions, random_state=0, return_info=True)
    names = info.candidates
    assert any(name.startswith("re-segmented") for name in names) is expected
    assert misclassification_rate(y, labels) < 0.05


def test_resegmentation_mends_a_motion_the_routes_cut():
    # make_tracks lab scene with 3 motions, seed 2: the candidate the routes
    # keep errs on 9 % of the tracks; a re-segmented one is significantly
    # better (Vuong's test) and replaces it
    X, y = make_tracks(
        scene="lab", n_motions=3, n_frames=30, missing=0.3, random_state=2
    )[:2]
    X, y = X[y >= 0], y[y >= 0]
    labels, info = segment_motions(X, 3, random_state=0, return_info=True)
    assert info.candidates[info.chosen].startswith("re-segmented")
    assert misclassification_rate(y, labels) < 0.03


def test_the_resegmented_candidate_is_tested_at_resegment_level(monkeypatch):
    # the stage that keeps a re-segmented candidate asks Vuong's test at
    # RESEGMENT_LEVEL (the level itself is tested below, on constructed scores)
    import sklearn_gpca._segment as segment

    levels = []
    test = segment._significantly_better

    def recorded(*args, level, **kwargs):
        levels.append(level)
        return test(*args, level=level, **kwargs)

    monkeypatch.setattr(segment, "_significantly_better", recorded)
    X, y = make_tracks(
        scene="lab", n_motions=3, n_frames=30, missing=0.3, random_state=2
    )[:2]
    X = X[y >= 0]
    info = segment_motions(X, 3, random_state=0, return_info=True)[1]
    assert info.candidates[info.chosen].startswith("re-segmented")
    assert levels == [RESEGMENT_LEVEL]


def test_resegmented_candidates_do_not_depend_on_n_jobs():
    X, _ = make_motions(
        3, n_points=[150, 40, 40], n_frames=10, missing=0.2, random_state=0
    )
    runs = [
        segment_motions(X, 3, random_state=0, return_info=True, n_jobs=n_jobs)
        for n_jobs in (1, 2)
    ]
    (one, first), (two, second) = runs
    assert any(name.startswith("re-segmented") for name in first.candidates)
    assert first.candidates == second.candidates
    for a, b in zip(first.refined, second.refined, strict=True):
        np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(one, two)


def test_a_resegmented_candidate_one_standard_error_better_replaces_the_kept():
    # RESEGMENT_LEVEL is the one-standard-error rule: a re-segmented
    # candidate whose per-track scores are lower by 1.6 standard errors of
    # their differences replaces the kept one, not at the textbook 5 %. (The
    # end-to-end case it was measured on, make_tracks driving seed 1, where a
    # re-segmented candidate 1.6 standard errors better mended two mixed
    # cars, is not a test: on another machine rounding draws other
    # candidates there; the lab draw above checks the stage end to end.)
    n_tracks = 100
    noise = np.tile([-1.0, 1.0], n_tracks // 2)
    kept = np.column_stack([np.full(n_tracks, 2.0), np.zeros(n_tracks)])
    resegmented = kept.copy()
    resegmented[:, 0] += -0.16 + noise  # z = -0.16 n / (sqrt(n) * 1) = -1.6
    assert significantly_better(
        kept, resegmented, misfit_cost=MISFIT_COST, n_compared=1, level=RESEGMENT_LEVEL
    )
    assert not significantly_better(
        kept, resegmented, misfit_cost=MISFIT_COST, n_compared=1, level=0.05
    )
    # nor when the scores are lower by less than one standard error
    resegmented[:, 0] = kept[:, 0] - 0.08 + noise
    assert not significantly_better(
        kept, resegmented, misfit_cost=MISFIT_COST, n_compared=1, level=RESEGMENT_LEVEL
    )
