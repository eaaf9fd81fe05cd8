"""Tests for the peeled starts of segment_motions (sklearn_gpca._peel_starts)."""

# SPDX-License-Identifier: BSD-3-Clause

import logging

import numpy as np
import pytest

from sklearn_gpca import MotionSegmentation, segment_motions
from sklearn_gpca._observed_subspaces import observed_entries
from sklearn_gpca._peel_starts import (
    fragment_misfits,
    peel_background,
    peel_candidates,
)
from sklearn_gpca._segment import PEEL_INCONSISTENCY
from sklearn_gpca.datasets import make_motions, make_tracks
from sklearn_gpca.metrics import misclassification_rate


def _true_fragments(y, size, seed):
    """Each motion's tracks cut at random into fragments of about ``size``."""
    rng = np.random.default_rng(seed)
    fragments = np.empty(y.size, dtype=np.intp)
    offset = 0
    for k in np.unique(y):
        members = rng.permutation(np.flatnonzero(y == k))
        pieces = max(1, members.size // size)
        fragments[members] = offset + np.arange(members.size) % pieces
        offset += pieces
    return fragments


def _draw(seed, missing=0.0):
    X, y = make_motions(
        3,
        n_points=[150, 40, 40],
        n_frames=12,
        noise=0.5,
        missing=missing,
        missing_pattern="occlusion",
        random_state=seed,
    )
    X0, mask = observed_entries(X)
    scale = np.sqrt(np.mean(X0[mask] ** 2))
    # the noise variance per coordinate in the scaled units
    return X0 / scale, mask, y, (0.5 / scale) ** 2


@pytest.mark.parametrize(("seed", "missing"), [(0, 0.0), (1, 0.0), (2, 0.3)])
def test_pure_fragments_peel_to_the_truth(seed, missing):
    # fragments that are pieces of the true motions: the largest consensus a
    # 4-D subspace fits is the largest motion, labelled 0, and the rest merge
    # into the two objects
    X0, mask, y, noise = _draw(seed, missing)
    fragments = _true_fragments(y, 20, seed)
    misfit = fragment_misfits(X0, mask, fragments, noise)
    # complete tracks: a fragment fits the subspaces of its own motion's
    # fragments (about the noise: misfit ~ 1) better than any other motion's
    # (with occlusions a fragment's subspace is missing frames)
    motion = np.array(
        [np.bincount(y[fragments == g]).argmax() for g in range(len(misfit))]
    )
    same = motion[:, None] == motion[None, :]
    if missing == 0:
        assert misfit[same].max() < 4.0 < misfit[~same].min()
    labels = peel_background(X0, mask, fragments, 3, noise, threshold=4.0)
    assert misclassification_rate(y, labels) == 0.0
    assert np.all(labels[y == np.argmax(np.bincount(y))] == 0)


def _lab_draw(seed):
    # the setting "lab, 3 motions" of benchmarks/bench_segment.py
    X, y = make_tracks(
        scene="lab", n_motions=3, n_frames=30, missing=0.3, random_state=seed
    )
    return X[y >= 0], y[y >= 0]


def test_peel_finds_a_start_the_fragments_route_misses():
    # make_tracks lab scene, 3 motions, 30 frames, 30 % missing, seed 3 (the
    # setting "lab, 3 motions" of benchmarks/bench_segment.py): the fragments
    # route's start refines to 23 % (background and an object merged, the
    # other object cut), a peeled start to the truth's basin (0.7 %)
    X, y = _lab_draw(3)
    # the starts alone: no outlier screening, which also mends this draw
    kwargs = dict(random_state=0, screen_outliers=False)
    old = segment_motions(X, 3, init="fragments", **kwargs)
    new, info = segment_motions(X, 3, init="peel", return_info=True, **kwargs)
    assert misclassification_rate(y, old) > 0.15
    assert misclassification_rate(y, new) < 0.02
    assert all(name.startswith("peel ") for name in info.candidates)


def test_peel_returns_none_when_nothing_is_left():
    # one motion only: its consensus takes every fragment, leaving fewer
    # than n_motions - 1 for the other motions
    X, _ = make_motions(1, n_points=120, n_frames=10, noise=0.5, random_state=0)
    X0, mask = observed_entries(X)
    fragments = np.arange(120) % 6
    assert peel_background(X0, mask, fragments, 3, 1.0, threshold=1e6) is None
    assert peel_candidates(X0, mask, fragments, 3, 1e6) == []
    # segment_motions labels every track with init="peel", and the estimator
    # takes the option and gives the same segmentation
    labels, info = segment_motions(X, 2, init="peel", random_state=0, return_info=True)
    assert labels.shape == (120,) and set(np.unique(labels)) <= {0, 1}
    seg = MotionSegmentation(n_clusters=2, init="peel", random_state=0).fit(X)
    assert seg.candidates_ == info.candidates
    np.testing.assert_array_equal(seg.labels_, labels)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"fragments": np.zeros(5, dtype=int)}, "one integer label per track"),
        ({"fragments": np.zeros(40)}, "one integer label per track"),
        ({"fragments": -np.ones(40, dtype=int)}, "non-negative"),
        ({"n_motions": 1}, "at least 2"),
        ({"noise": 0.0}, "positive variance"),
        ({"noise": np.nan}, "positive variance"),
        ({"threshold": -1.0}, "threshold must be positive"),
        ({"dim": 0}, "dim must be at least 1"),
        ({"mask": np.ones((40, 3), dtype=bool)}, "one shape"),
    ],
)
def test_peel_background_bad_inputs(kwargs, match):
    X0 = np.random.default_rng(0).normal(size=(40, 6))
    args = {
        "X0": X0,
        "mask": np.ones_like(X0, dtype=bool),
        "fragments": np.arange(40) % 4,
        "n_motions": 2,
        "noise": 1.0,
        "threshold": 4.0,
        "dim": 2,
    }
    args.update(kwargs)
    threshold, dim = args.pop("threshold"), args.pop("dim")
    with pytest.raises(ValueError, match=match):
        peel_background(**args, threshold=threshold, dim=dim)


def test_default_draws_peeled_starts_when_its_choice_is_inconsistent(caplog):
    # seed 83: every candidate of init="all" merges two motions (the "votes"
    # one, kept, errs on 17 % of the tracks and leaves 12 % of them nearer
    # another motion's model); the peeled starts then join and one is kept
    X, y = _lab_draw(83)
    with caplog.at_level(logging.INFO, logger="sklearn_gpca"):
        labels, info = segment_motions(
            X, 3, random_state=0, screen_outliers=False, return_info=True
        )
    assert any("peeled starts are drawn" in r.getMessage() for r in caplog.records)
    peeled = [name.startswith("peel ") for name in info.candidates]
    assert any(peeled) and peeled[info.chosen]
    # the routes' candidates (the re-segmented ones come after the peeled)
    first = [
        k
        for k, (name, p) in enumerate(zip(info.candidates, peeled, strict=True))
        if not p and not name.startswith("re-segmented")
    ]
    assert min(info.inconsistency[first]) > PEEL_INCONSISTENCY
    assert misclassification_rate(y, labels) < 0.05


def test_default_draws_no_peeled_start_beside_a_consistent_choice():
    # seed 3: the kept candidate is consistent (under 1 % of the tracks nearer
    # another model): no peeled start is drawn
    X, y = _lab_draw(3)
    labels, info = segment_motions(
        X, 3, random_state=0, screen_outliers=False, return_info=True
    )
    assert not any(name.startswith("peel") for name in info.candidates)
    assert info.inconsistency[info.chosen] <= PEEL_INCONSISTENCY
    assert misclassification_rate(y, labels) < 0.02
