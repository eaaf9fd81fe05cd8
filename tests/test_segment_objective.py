"""Tests of the refinement objective (``_refine_observed.refinement_objective``)."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
from numpy.testing import assert_allclose

from sklearn_gpca._motion_graph import edge_weights, motion_affinity
from sklearn_gpca._observed_subspaces import (
    fit_observed_subspace,
    observed_entries,
    subspace_residuals,
)
from sklearn_gpca._refine_observed import refine_observed, refinement_objective
from sklearn_gpca._segment import segment_motions, track_graph
from sklearn_gpca._track_neighbors import track_neighbors
from sklearn_gpca.datasets import make_motions


def _setup(seed=0, missing=0.3):
    X, y = make_motions(
        3,
        n_points=[120, 40, 40],
        n_frames=12,
        missing=missing,
        missing_pattern="occlusion",
        random_state=seed,
    )
    X0, mask = observed_entries(X)
    neighbors = track_neighbors(X0, mask, 10)
    weights = edge_weights(motion_affinity(X0, mask, neighbors), neighbors)
    return X0, mask, y, dict(neighbors=neighbors, neighbor_weights=weights)


@pytest.mark.parametrize("seed", range(3))
def test_objective_prefers_truth_to_merge_split_and_noise(seed):
    X0, mask, y, graph = _setup(seed)
    merged_split = np.where(y == 2, 1, y)
    merged_split[(y == 0) & (np.arange(y.size) % 2 == 0)] = 2
    rng = np.random.RandomState(seed)
    noisy = np.where(rng.rand(y.size) < 0.1, rng.randint(0, 3, y.size), y)
    truth = refinement_objective(X0, mask, y, 3, **graph)
    assert truth < refinement_objective(X0, mask, merged_split, 3, **graph)
    assert truth < refinement_objective(X0, mask, noisy, 3, **graph)


def test_smoothing_term_counts_disagreeing_neighbours():
    # by hand: neighbours p -> p + 1 (the last has none), unit weights; the
    # labels change twice along the chain: two disagreeing edges
    X0, mask, y, _ = _setup(missing=0.0)
    n = y.size
    neighbors = np.append(np.arange(1, n), -1)[:, None]
    labels = np.zeros(n, dtype=np.intp)
    labels[n // 3 : 2 * n // 3] = 1
    labels[2 * n // 3 :] = 2
    kwargs = dict(neighbors=neighbors, subspace_dim=4)
    data = refinement_objective(X0, mask, labels, 3, smoothing=0.0, **kwargs)
    total = refinement_objective(X0, mask, labels, 3, smoothing=2.5, **kwargs)
    assert_allclose(total - data, 2.5 * 2)


def test_objective_does_not_depend_on_label_names_and_units():
    X0, mask, y, graph = _setup(seed=1)
    rng = np.random.RandomState(1)
    other = np.where(rng.rand(y.size) < 0.2, rng.randint(0, 3, y.size), y)
    permuted = np.array([2, 0, 1])[y]
    base = refinement_objective(X0, mask, y, 3, **graph)
    assert_allclose(refinement_objective(X0, mask, permuted, 3, **graph), base)
    # a change of units shifts every labelling's value alike
    gap = refinement_objective(X0, mask, other, 3, **graph) - base
    scaled = 7.0 * X0
    gap_scaled = refinement_objective(
        scaled, mask, other, 3, **graph
    ) - refinement_objective(scaled, mask, y, 3, **graph)
    assert_allclose(gap_scaled, gap, rtol=1e-6)


def test_refinement_does_not_raise_the_objective():
    # the refinement descends the objective: from corrupted labels it ends lower
    X0, mask, y, graph = _setup(seed=2)
    rng = np.random.RandomState(2)
    start = np.where(rng.rand(y.size) < 0.3, rng.randint(0, 3, y.size), y)
    refined = refine_observed(X0, mask, start, 3, random_state=rng, **graph)[0]
    assert refinement_objective(X0, mask, refined, 3, **graph) < (
        refinement_objective(X0, mask, start, 3, **graph)
    )


@pytest.mark.parametrize(
    ("labels", "match"),
    [(np.array([0, 1, 5]), "one label in 0 .. 2"), (np.zeros(3), "per track")],
)
def test_objective_bad_labels(labels, match):
    X0, mask, _, graph = _setup()
    if labels.size == 3 and labels.max() > 2:
        labels = np.resize(labels, X0.shape[0])
    with pytest.raises(ValueError, match=match):
        refinement_objective(X0, mask, labels, 3, **graph)


def test_objective_matches_definition():
    # the docstring's sum, from the residuals of each group's own subspace
    X0, mask, y, graph = _setup(seed=0)
    fits = [fit_observed_subspace(X0[y == k], mask[y == k], 4) for k in range(3)]
    residuals, dofs = subspace_residuals(
        X0, mask, [b for b, _ in fits], [s for _, s in fits]
    )
    rows = np.arange(y.size)
    m = dofs.max(axis=1)
    rho = residuals[rows, y] / dofs[rows, y]
    scales = np.array([np.median(rho[y == k]) for k in range(3)])
    expected = np.sum(m * (rho / scales[y] + np.log(scales[y]))) / np.median(m)
    got = refinement_objective(X0, mask, y, 3, smoothing=0.0, **graph)
    assert_allclose(got, expected, rtol=1e-6)


def test_segment_motions_reports_the_objective_of_each_candidate():
    X, y = make_motions(2, n_points=[60, 40], n_frames=8, missing=0.2, random_state=3)
    labels, info = segment_motions(
        X, 2, init=y, perspective_background=False, random_state=0, return_info=True
    )
    X0, mask = observed_entries(X)
    X0 = X0 / info.scale
    neighbors, _, _, weights = track_graph(
        X0, mask, 10, random_state=np.random.RandomState(0)
    )
    expected = refinement_objective(
        X0,
        mask,
        labels,
        2,
        neighbors=neighbors[:, : weights.shape[1]],
        neighbor_weights=weights,
    )
    assert info.objectives.shape == (1,)
    assert_allclose(info.objectives[0], expected)
