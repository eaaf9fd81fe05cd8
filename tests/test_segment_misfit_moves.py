"""Tests for the misfit moves of segment_motions (sklearn_gpca._misfit_moves)."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest

from sklearn_gpca import _segment, segment_motions
from sklearn_gpca._misfit_moves import (
    MIN_MISFIT_FRAMES,
    background_misfits,
    misfit_starts,
)
from sklearn_gpca._observed_subspaces import observed_entries
from sklearn_gpca._refine_observed import MIN_PROJECTIVE_TRACKS
from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.metrics import misclassification_rate


def test_misfit_starts_free_each_label_once():
    labels = np.array([0, 0, 0, 0, 1, 1, 2, 2])
    starts = dict(misfit_starts(labels, 3, 0, np.array([0, 1])))
    assert len(starts) == 3
    expected = {
        # label 1 given to the background, the misfits to 1
        "misfits of 0 to 1, 1 into 0": [1, 1, 0, 0, 0, 0, 2, 2],
        "misfits of 0 to 2, 2 into 0": [2, 2, 0, 0, 1, 1, 0, 0],
        # labels 1 and 2 merged (one start for the pair), the misfits to 2
        "misfits of 0 to 2, 2 into 1": [2, 2, 0, 0, 1, 1, 1, 1],
    }
    assert set(starts) == set(expected)
    for name, start in expected.items():
        np.testing.assert_array_equal(starts[name], start)


def test_misfit_starts_keep_the_label_of_the_largest_motion_given():
    labels = np.array([2, 2, 2, 2, 0, 1])
    starts = misfit_starts(labels, 3, 2, np.array([3]))
    assert all(name.startswith("misfits of 2 ") for name, _ in starts)
    for _, start in starts:
        assert start[3] != 2
        assert set(np.unique(start)) <= {0, 1, 2}


@pytest.mark.parametrize("seed", [0, 1])
def test_background_misfits_find_an_object_merged_into_the_background(seed):
    # a hand-held scene's background with one object merged into it: the
    # trimmed perspective fit leaves the object's long tracks out, and keeps
    # the background's
    X, y, info = make_tracks(
        scene="handheld",
        n_motions=3,
        n_frames=40,
        missing=0.5,
        random_state=seed,
        return_info=True,
    )
    X, y = X[y >= 0], y[y >= 0]
    X0, mask = observed_entries(X)
    scale = np.sqrt(np.mean(X0[mask] ** 2))
    X0 = X0 / scale
    noise = np.mean(np.square(info["noise"])) / scale**2
    group = np.flatnonzero(y <= 1)
    misfits = background_misfits(X0, mask, group, noise)
    long = np.count_nonzero(mask[:, ::2], axis=1) >= MIN_MISFIT_FRAMES
    assert set(misfits) <= set(group[long[group]])
    object_tracks = np.flatnonzero((y == 1) & long)
    found = np.isin(misfits, object_tracks)
    assert found.mean() >= 0.9
    assert np.isin(object_tracks, misfits).mean() >= 0.6


def test_background_misfits_none_in_a_small_group():
    # too few tracks for a perspective fit: none is called a misfit, even of
    # tracks that follow no motion at all
    X0 = np.random.default_rng(0).normal(size=(MIN_PROJECTIVE_TRACKS - 1, 20))
    mask = np.ones_like(X0, dtype=bool)
    members = np.arange(X0.shape[0])
    assert background_misfits(X0, mask, members, 1e-6).size == 0


def test_segment_motions_moves_recover_an_object_merged_into_the_background():
    # four hand-held motions over 30 frames, half the entries missing: the
    # kept candidate merges an object into the background; a misfit move
    # gives it back its own label
    X, y = make_tracks(
        scene="handheld",
        n_motions=4,
        n_tracks=300,
        n_frames=30,
        missing=0.5,
        random_state=1010,
    )[:2]
    X, y = X[y >= 0], y[y >= 0]
    without = segment_motions(X, 4, random_state=0, misfit_moves=False)
    labels, info = segment_motions(X, 4, random_state=0, return_info=True)
    assert misclassification_rate(y, without) > 0.18
    assert misclassification_rate(y, labels) < 0.12
    assert info.candidates[info.chosen].startswith("misfits of ")


def test_segment_motions_tries_no_move_with_three_motions():
    # a draw whose kept background has misfits: with 2 and 3 motions the
    # moves only made segmentations worse where measured (see
    # MIN_MISFIT_MOVE_MOTIONS), so none is tried
    X, y = make_tracks(
        scene="handheld",
        n_motions=3,
        n_tracks=200,
        n_frames=30,
        missing=0.5,
        random_state=1,
    )[:2]
    X = X[y >= 0]
    _, info = segment_motions(X, 3, random_state=0, return_info=True)
    assert not any(name.startswith("misfits of ") for name in info.candidates)


def test_background_misfits_none_when_no_track_carries_a_residual():
    # every track seen in two frames: no residual degree of freedom
    rng = np.random.default_rng(0)
    X = np.full((30, 12), np.nan)
    for i in range(30):
        frame = rng.integers(0, 5)
        X[i, 2 * frame : 2 * frame + 4] = rng.normal(size=4)
    X0, mask = observed_entries(X)
    assert background_misfits(X0, mask, np.arange(30), 1.0).size == 0


def test_misfit_moves_false_reaches_the_subsamples_of_dense_tracks(monkeypatch):
    # tracks count as dense above 60 seen per frame, so that each of the
    # subsamples is segmented on its own: misfit_moves=False must reach them
    monkeypatch.setattr(_segment, "MAX_TRACKS_PER_FRAME", 40)

    def never(*args, **kwargs):
        raise AssertionError("misfit moves tried with misfit_moves=False")

    monkeypatch.setattr(_segment, "_add_misfit_moves", never)
    X, y = make_tracks(
        scene="handheld", n_motions=4, n_tracks=300, n_frames=20, random_state=0
    )[:2]
    X = X[y >= 0]
    assert _segment.draws_subsamples("all", ~np.isnan(X))
    labels = segment_motions(X, 4, random_state=0, misfit_moves=False)
    assert labels.shape == (X.shape[0],)
