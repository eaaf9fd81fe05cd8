"""Tests for the coding-length descent and the refined trajectory coding length
that ``GPCAClustering("auto", segmentation_dim=5)`` counts motions with."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose, assert_array_equal
from sklearn.pipeline import make_pipeline

from sklearn_gpca import (
    GPCAClustering,
    PowerFactorization,
    refined_trajectory_coding_length_cost,
    select_n_clusters,
    trajectory_coding_length_cost,
)
from sklearn_gpca._coding_descent import coding_length_descent, coding_length_moves
from sklearn_gpca._coding_length import coding_length
from sklearn_gpca._model_selection import MAX_CODED_TRAJECTORIES, MIN_MOTION_POINTS
from sklearn_gpca._rows import unit_rows
from sklearn_gpca.datasets import load_hopkins155
from sklearn_gpca.metrics import misclassification_rate


def _subspaces(n, *, n_per=60, dim=4, width=20, noise=1e-3, seed=0):
    """Points on ``n`` random ``dim``-dimensional subspaces of R^width (a
    direct sum for n <= 5), grouped by subspace."""
    rng = np.random.RandomState(seed)
    bases = [np.linalg.qr(rng.randn(width, dim))[0] for _ in range(n)]
    X = np.vstack([rng.randn(n_per, dim) @ B.T for B in bases])
    X += noise * rng.randn(*X.shape)
    return X, np.repeat(np.arange(n), n_per)


@pytest.mark.parametrize("distortion", [0.01, 0.1])
def test_moves_are_the_exact_change_of_the_coding_length(distortion):
    """Each entry equals the coding length recomputed with that one move,
    including moves out of a singleton group and into an empty one."""
    rng = np.random.RandomState(0)
    points = unit_rows(rng.randn(30, 5))
    labels = rng.randint(0, 3, 30)
    labels[0] = 3  # a singleton group; group 4 stays empty
    moves = coding_length_moves(points, labels, 5, distortion)
    before = coding_length(points, labels, distortion)
    expected = np.empty_like(moves)
    for i in range(30):
        for k in range(5):
            moved = labels.copy()
            moved[i] = k
            expected[i, k] = coding_length(points, moved, distortion) - before
    assert_allclose(moves, expected, atol=1e-8)


def test_descent_reaches_a_local_minimum_below_its_start():
    X, y = _subspaces(3, n_per=40)
    unit = unit_rows(X)
    start = np.random.RandomState(1).randint(0, 3, y.size)
    labels, bits = coding_length_descent(unit, start, 0.01)
    assert_allclose(bits, coding_length(unit, labels, 0.01))
    assert bits < coding_length(unit, start, 0.01)
    # no single move lowers it further
    assert coding_length_moves(unit, labels, 3, 0.01).min() > -1e-6


def test_descent_restores_misassigned_points():
    X, y = _subspaces(2, n_per=80)
    wrong = y.copy()
    wrong[:8] = 1  # 8 points of the first subspace given to the second
    labels, bits = coding_length_descent(unit_rows(X), wrong, 0.007)
    assert_array_equal(labels, y)
    assert_allclose(bits, coding_length(unit_rows(X), y, 0.007))


def test_descent_stays_at_a_local_minimum():
    X, y = _subspaces(2)
    labels, bits = coding_length_descent(unit_rows(X), y, 0.007)
    assert_array_equal(labels, y)
    assert_allclose(bits, coding_length(unit_rows(X), y, 0.007))


def test_refined_cost_is_the_trajectory_code_after_the_descent():
    X, y = _subspaces(2, n_per=80)
    wrong = y.copy()
    wrong[:8] = 1
    refined = refined_trajectory_coding_length_cost(X, wrong)
    assert_allclose(refined, trajectory_coding_length_cost(X, y))
    assert refined < trajectory_coding_length_cost(X, wrong)


def test_groups_below_the_motion_floor_are_rejected():
    """A handful of outlying trajectories is no motion, nor is an emptied
    group; a single group always qualifies, whatever its size."""
    X, y = _subspaces(2, n_per=80)
    rng = np.random.RandomState(0)
    outliers = unit_rows(rng.randn(MIN_MOTION_POINTS - 1, X.shape[1]))
    with_outliers = np.vstack([X, outliers])
    labels = np.r_[y, np.full(MIN_MOTION_POINTS - 1, 2)]
    assert refined_trajectory_coding_length_cost(with_outliers, labels) == np.inf
    assert np.isfinite(refined_trajectory_coding_length_cost(with_outliers, 0 * labels))
    assert np.isfinite(refined_trajectory_coding_length_cost(X[:5], np.zeros(5)))
    # a third group whose points all belong elsewhere empties
    emptied = np.where(np.arange(y.size) % 40 == 0, 2, y)
    assert refined_trajectory_coding_length_cost(X, emptied) == np.inf


def test_refinement_changes_the_count_to_the_right_one():
    """Two motions: a segmentation with the true n that misassigns 12
    trajectories costs more than one with a motion split in two, so the
    unrefined code counts three; refined, the first is the true labels and
    counts two."""
    X, y = _subspaces(2, n_per=80, noise=3e-3)
    wrong = y.copy()
    wrong[:12] = 1
    split = np.where((y == 1) & (np.arange(y.size) % 2 == 0), 2, y)
    candidates = {1: np.zeros_like(y), 2: wrong, 3: split}

    def segment(n):
        return X, candidates[n], None

    unrefined, costs, _ = select_n_clusters(
        segment, [1, 2, 3], criterion=trajectory_coding_length_cost
    )
    refined, _, _ = select_n_clusters(
        segment, [1, 2, 3], criterion=refined_trajectory_coding_length_cost
    )
    assert unrefined == 2 and costs[2] < costs[1]  # three motions
    assert refined == 1  # two motions


def test_refined_cost_of_the_truth_beats_other_counts():
    X, y = _subspaces(3, n_per=50)
    true = refined_trajectory_coding_length_cost(X, y)
    assert true < refined_trajectory_coding_length_cost(X, 0 * y)
    split = np.where(np.arange(y.size) % 2, y, y + 3)
    assert true < refined_trajectory_coding_length_cost(X, split)


def test_many_trajectories_are_judged_on_an_even_subset():
    """Above 1000 trajectories the cost is that of 1000 evenly spaced ones,
    scaled to all of them (bits per trajectory unchanged)."""
    X, y = _subspaces(3, n_per=400, noise=1e-2)  # 1200 trajectories
    kept = np.linspace(0, y.size - 1, MAX_CODED_TRAJECTORIES).round().astype(int)
    wrong = np.where(np.arange(y.size) % 50 == 0, (y + 1) % 3, y)
    expected = refined_trajectory_coding_length_cost(X[kept], wrong[kept])
    assert np.isfinite(expected)
    assert_allclose(
        refined_trajectory_coding_length_cost(X, wrong),
        expected * y.size / MAX_CODED_TRAJECTORIES,
    )


@settings(deadline=None, max_examples=20)
@given(
    n_groups=st.integers(1, 3),
    n_per=st.integers(16, 30),
    scale=st.floats(1e-3, 1e3),
    seed=st.integers(0, 2**16),
)
def test_refined_cost_is_invariant(n_groups, n_per, scale, seed):
    """Like the unrefined code: not the trajectories' lengths, nor the names
    of the groups."""
    X, y = _subspaces(n_groups, n_per=n_per, seed=seed, noise=1e-2)
    rng = np.random.RandomState(seed)
    start = np.where(rng.rand(y.size) < 0.1, rng.randint(0, n_groups, y.size), y)
    lengths = scale * rng.uniform(0.1, 10.0, size=(X.shape[0], 1))
    renamed = rng.permutation(n_groups)[start] + 7
    cost = refined_trajectory_coding_length_cost(X, start)
    assert_allclose(
        refined_trajectory_coding_length_cost(lengths * X, renamed), cost, rtol=1e-7
    )
    assert cost <= trajectory_coding_length_cost(X, start) + 1e-6


@pytest.mark.parametrize(
    "points, labels, match",
    [
        (np.ones((10, 3)), np.zeros(9), "10 points but 9 labels"),
        (np.ones((10, 3)), -np.ones(10), "non-negative integers"),
        (np.ones((10, 3)), np.full(10, 0.5), "non-negative integers"),
        (np.full((10, 3), np.nan), np.zeros(10), "finite"),
        (np.ones(10), np.zeros(10), "2-D"),
    ],
)
def test_bad_inputs_are_named(points, labels, match):
    with pytest.raises(ValueError, match=match):
        refined_trajectory_coding_length_cost(points, labels)


def test_auto_counts_a_real_sequence_the_unrefined_code_overcounts(hopkins155_dir):
    """cars1 (two motions): the fit with n = 2 is right, but the unrefined
    code prefers a third group of 9 outlying trajectories; refined, that
    group falls below the motion floor."""
    seq = load_hopkins155(hopkins155_dir, sequences="cars1")[0]

    def counting(criterion):
        return make_pipeline(
            PowerFactorization(20, whiten=False, random_state=0),
            GPCAClustering(
                "auto", segmentation_dim=5, criterion=criterion, random_state=0
            ),
        ).fit(seq.X)[-1]

    refined = counting("auto")
    unrefined = counting("trajectory_coding_length")
    assert unrefined.n_clusters_ == 3
    assert refined.n_clusters_ == seq.n_motions == 2
    assert misclassification_rate(seq.y, refined.labels_) < 0.01
