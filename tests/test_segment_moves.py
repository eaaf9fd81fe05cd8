"""Tests for the merge/split moves of segment_motions (sklearn_gpca._merge_split)."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest

from sklearn_gpca import segment_motions
from sklearn_gpca._merge_split import (
    cached_split,
    merge_split_moves,
    merge_split_search,
    significantly_better,
)
from sklearn_gpca._segment_selection import select_segmentation
from sklearn_gpca.datasets import make_motions, make_tracks
from sklearn_gpca.metrics import misclassification_rate, oracle_labels


def _apart_draw(missing, seed):
    """Three motions (120, 40, 40 tracks), each object in its own image region."""
    X, y = make_motions(
        3,
        n_points=[120, 40, 40],
        n_frames=12,
        missing=missing,
        missing_pattern="occlusion",
        random_state=seed,
    )
    return X + (400.0 * y)[:, None] * np.tile([1.0, 0.0], 12), y


def _merged_and_cut(X, y):
    """Motions 1 and 2 share label 1; the background is cut in left and right."""
    planted = np.where(y == 2, 1, y)
    first = np.nanmean(X[:, 0::2], axis=1)
    background = y == 0
    planted[background & (first > np.median(first[background]))] = 2
    return planted


@pytest.mark.parametrize("selection", ["consistency", "separability"])
@pytest.mark.parametrize(("missing", "seed"), [(0.0, 0), (0.0, 1), (0.3, 0)])
def test_moves_fix_planted_merge_and_cut(missing, seed, selection):
    # half the tracks are misassigned, and the refinement alone keeps the
    # error (each half of the background fits its own subspace, the two
    # merged objects share a 4-D subspace well enough); one move fixes both
    X, y = _apart_draw(missing, seed)
    planted = _merged_and_cut(X, y)
    assert misclassification_rate(y, planted) == 0.5
    refined = segment_motions(X, 3, init=planted, selection=selection, random_state=0)
    assert misclassification_rate(y, refined) > 0.3
    moved, info = segment_motions(
        X,
        3,
        init=planted,
        merge_split=True,
        selection=selection,
        random_state=0,
        return_info=True,
    )
    assert info.n_moves >= 1
    assert misclassification_rate(y, moved) < 0.02


def test_moves_keep_the_truth():
    X, y = _apart_draw(0.3, 0)
    moved, info = segment_motions(
        X, 3, init=y, merge_split=True, random_state=0, return_info=True
    )
    assert info.n_moves == 0
    assert misclassification_rate(y, moved) < 0.01


def test_merge_split_moves_enumerates_every_merge_and_split():
    labels = np.repeat([0, 1, 2], 4)

    def split(members):  # alternate members
        return (np.arange(members.size) % 2).astype(np.intp)

    moves = merge_split_moves(labels, 3, split)
    # 3 pairs (a, b) x 2 clusters to cut (the union or the third label)
    assert len(moves) == 6
    for move in moves:
        assert set(np.unique(move)) == {0, 1, 2}
        assert not np.array_equal(move, labels)
    # merging 1 and 2 and cutting 0
    expected = np.array([0, 2, 0, 2, 1, 1, 1, 1, 1, 1, 1, 1])
    assert any(np.array_equal(move, expected) for move in moves)


def test_merge_split_moves_skip_unsplittable_clusters():
    labels = np.repeat([0, 1], 5)
    assert merge_split_moves(labels, 2, lambda members: None) == []


def test_cached_split_calls_once_per_member_set():
    calls = []

    def split(members):
        calls.append(members.copy())
        return np.zeros(members.size, dtype=np.intp)

    cached = cached_split(split)
    cached(np.array([1, 2, 3]))
    cached(np.array([1, 2, 3]))
    cached(np.array([1, 2]))
    assert len(calls) == 2


def _separability_choice(judge, *, tolerance):
    def choose(segmentations):
        scores = np.array([judge(s) for s in segmentations])
        return select_segmentation(
            scores[:, 0], scores[:, 1], selection="separability", tolerance=tolerance
        )

    return choose


def test_merge_split_search_stops_when_the_rule_keeps_the_current():
    labels = np.repeat([0, 1], 5)

    def judge(candidate):
        # the current labelling is the least ambiguous and shortest
        same = np.array_equal(candidate, labels)
        return (0.0, 0.0) if same else (1.0, 1.0)

    found, n_moves = merge_split_search(
        labels,
        2,
        split=lambda m: (np.arange(m.size) % 2).astype(np.intp),
        refine=lambda start: [start],
        choose=_separability_choice(judge, tolerance=0.04),
        max_rounds=3,
    )
    assert n_moves == 0 and np.array_equal(found, labels)


def test_merge_split_search_takes_a_better_move():
    truth = np.repeat([0, 1], 6)
    start = np.array([0, 0, 0, 1, 1, 1, 0, 0, 0, 0, 0, 0])

    def judge(candidate):
        wrong = misclassification_rate(truth, candidate)
        return (100.0 * wrong, wrong)

    found, n_moves = merge_split_search(
        start,
        2,
        split=lambda m: (np.arange(m.size) >= m.size // 2).astype(np.intp),
        refine=lambda s: [s],
        choose=_separability_choice(judge, tolerance=0.0),
        max_rounds=3,
    )
    assert n_moves >= 1
    assert misclassification_rate(truth, found) < misclassification_rate(truth, start)


def test_realistic_draw_within_three_points_of_its_oracle():
    # a lab scene (Hopkins155-like boxes, 40 % missing in windows), small
    X, y = make_tracks(
        scene="lab", n_tracks=200, n_frames=20, missing=0.4, random_state=0
    )
    X, y = X[y >= 0], y[y >= 0]
    labels = segment_motions(X, 2, init="auto", random_state=0)
    oracle = misclassification_rate(y, oracle_labels(X, y))
    assert misclassification_rate(y, labels) <= oracle + 0.03


@pytest.mark.parametrize("value", ["yes", 1.5])
def test_merge_split_must_be_boolean(value):
    X, _ = _apart_draw(0.0, 0)
    with pytest.raises(ValueError, match="merge_split"):
        segment_motions(X, 3, merge_split=value)


def test_estimator_passes_merge_split():
    from sklearn_gpca import MotionSegmentation

    X, _ = _apart_draw(0.0, 1)
    expected = segment_motions(X, 3, init="fragments", merge_split=True, random_state=0)
    found = MotionSegmentation(
        3, init="fragments", merge_split=True, random_state=0
    ).fit(X)
    assert np.array_equal(found.labels_, expected)


# --- the significance of a move (Vuong's test) -------------------------------


def _terms(fit, misfit):
    return np.column_stack([fit, misfit]).astype(float)


def test_a_move_that_fits_every_track_better_is_significant():
    rng = np.random.default_rng(0)
    current = _terms(rng.uniform(1.0, 2.0, 300), np.zeros(300))
    move = current - _terms(rng.uniform(0.05, 0.15, 300), np.zeros(300))
    assert significantly_better(current, move, misfit_cost=8, n_compared=12)
    # and not the other way round, nor a move that changes nothing
    assert not significantly_better(move, current, misfit_cost=8, n_compared=12)
    assert not significantly_better(current, current, misfit_cost=8, n_compared=1)


def test_a_few_tracks_less_misfit_are_not_significant_against_noise():
    # the move lowers the sum (four fewer misfits, 32) but the tracks' fits
    # move up and down by more than that: chance, not a better model
    rng = np.random.default_rng(1)
    current = _terms(rng.uniform(1.0, 2.0, 300), np.r_[np.ones(10), np.zeros(290)])
    noise = rng.normal(scale=1.0, size=300)
    move = _terms(
        current[:, 0] + noise - noise.mean(), np.r_[np.ones(6), np.zeros(294)]
    )
    assert np.sum(move[:, 0] + 8 * move[:, 1]) < np.sum(
        current[:, 0] + 8 * current[:, 1]
    )
    assert not significantly_better(current, move, misfit_cost=8, n_compared=1)


def test_more_moves_compared_need_more_evidence():
    # z = -2.2: significant alone (5 % one-sided), not among ten moves
    d = np.r_[np.full(50, -1.0), np.full(50, 1.0)]
    d = d - 2.2 * d.std() / np.sqrt(d.size)
    current = _terms(np.full(100, 5.0), np.zeros(100))
    move = _terms(5.0 + d, np.zeros(100))
    assert significantly_better(current, move, misfit_cost=8, n_compared=1)
    assert not significantly_better(current, move, misfit_cost=8, n_compared=10)


def test_untested_tracks_are_left_out_of_the_test():
    current = _terms(np.full(50, 2.0), np.zeros(50))
    move = current - _terms(np.linspace(0.5, 1.5, 50), np.zeros(50))
    move[:40] = np.nan
    assert significantly_better(current, move, misfit_cost=8, n_compared=1)
    move[:49] = np.nan  # one track tested in both: no test
    assert not significantly_better(current, move, misfit_cost=8, n_compared=1)
