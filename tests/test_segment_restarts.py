"""Tests for n_init: several runs of segment_motions, the best-judged kept."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
from sklearn.utils import Bunch
from sklearn.utils._param_validation import InvalidParameterError

from sklearn_gpca import MotionSegmentation, segment_motions
from sklearn_gpca._restarts import best_of_runs
from sklearn_gpca.datasets import make_tracks


@pytest.fixture(scope="module")
def lab_draw():
    X, y = make_tracks(
        scene="lab", n_tracks=150, n_frames=12, missing=0.3, random_state=3
    )[:2]
    return X[y >= 0], y[y >= 0]


def _scrambled(y, share, seed):
    """``y`` with ``share`` of the tracks given another motion."""
    rng = np.random.RandomState(seed)
    wrong = y.copy()
    moved = rng.rand(y.size) < share
    wrong[moved] = (y[moved] + 1) % (y.max() + 1)
    return wrong


@pytest.mark.parametrize("truth_at", [0, 1, 2])
def test_best_of_runs_keeps_the_run_the_rule_prefers(lab_draw, truth_at):
    # three runs: the true labels and two with a fifth and a third of the
    # tracks moved; the kept run is the truth wherever it comes
    X, y = lab_draw
    wrong = iter([_scrambled(y, 0.2, 0), _scrambled(y, 0.33, 1)])
    outcomes = [None if k == truth_at else next(wrong) for k in range(3)]
    states = []

    def run(state):
        states.append(state)
        found = outcomes[len(states) - 1]
        return (y if found is None else found), Bunch()

    labels, info = best_of_runs(
        run, X, 2, 3, 0, subspace_dim=4, perspective_background=True, n_neighbors=10
    )
    np.testing.assert_array_equal(labels, y)
    assert info.run == truth_at and info.n_init == 3
    assert info.run_scores.shape == (3, 2)
    # every run timed, and the judgement apart from them
    assert info.run_seconds.shape == (3,) and np.all(info.run_seconds >= 0)
    assert info.judge_seconds >= 0
    # the first run has the caller's random state, the others their own seeds
    assert states[0] == 0 and len(set(states)) == 3


def test_best_of_runs_judges_on_the_tracks_no_run_calls_an_outlier(lab_draw):
    # the truth with the first 30 tracks labelled -1 beside a wrong run that
    # labels every track: judged on the common tracks, the truth is kept
    X, y = lab_draw
    flagged = y.copy()
    flagged[:30] = -1
    outcomes = [_scrambled(y, 0.25, 2), flagged]
    labels = best_of_runs(
        lambda state: outcomes.pop(0),
        X,
        2,
        2,
        np.random.RandomState(0),
        subspace_dim=4,
        perspective_background=False,
        n_neighbors=10,
    )
    np.testing.assert_array_equal(labels, flagged)


def test_n_init_runs_the_plain_call_first_and_keeps_one_of_its_runs(lab_draw):
    X, _ = lab_draw
    plain = segment_motions(X, 2, random_state=0)
    once = segment_motions(X, 2, random_state=0, n_init=1)
    np.testing.assert_array_equal(once, plain)
    labels, info = segment_motions(X, 2, random_state=0, n_init=2, return_info=True)
    assert len(info.run_labels) == 2
    np.testing.assert_array_equal(info.run_labels[0], plain)
    np.testing.assert_array_equal(labels, info.run_labels[info.run])
    model = MotionSegmentation(2, n_init=2, random_state=0).fit(X)
    np.testing.assert_array_equal(model.labels_, labels)


@pytest.mark.parametrize("n_init", [0, -1, 1.5, "4"])
def test_n_init_must_be_a_positive_integer(lab_draw, n_init):
    X, _ = lab_draw
    with pytest.raises(InvalidParameterError, match="n_init"):
        segment_motions(X, 2, n_init=n_init)
    with pytest.raises(InvalidParameterError, match="n_init"):
        MotionSegmentation(2, n_init=n_init).fit(X)
