"""Tests for the smoothed K-subspaces refinement."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal
from sklearn.metrics import adjusted_rand_score

from sklearn_gpca._affinity import sign_invariant_neighbors
from sklearn_gpca._ksubspaces import k_subspaces, refill_small_clusters
from sklearn_gpca._subspaces import fit_subspace, fit_subspaces, sine_residuals


def unit(X):
    return X / np.linalg.norm(X, axis=1, keepdims=True)


def union(dims, n_per, rng, noise=1e-3, n_features=5):
    bases = [np.linalg.qr(rng.randn(n_features, d))[0] for d in dims]
    X = np.vstack([rng.randn(n_per, B.shape[1]) @ B.T for B in bases])
    X += noise * rng.randn(*X.shape)
    return unit(X), np.repeat(np.arange(len(dims)), n_per), bases


@pytest.mark.parametrize("dim", [1, 2, 4])
def test_fit_subspace_recovers_span(dim):
    rng = np.random.RandomState(dim)
    X, _, (basis,) = union([dim], 50, rng, noise=0.0)
    fitted = fit_subspace(X, dim, 0.05)
    assert fitted.shape == (5, dim)
    assert_allclose(fitted.T @ fitted, np.eye(dim), atol=1e-10)
    assert_allclose(np.linalg.svd(basis.T @ fitted, compute_uv=False), 1.0)
    assert fit_subspace(X, "auto", 0.05).shape == (5, dim)


def test_sine_residuals_range():
    rng = np.random.RandomState(0)
    X, _, bases = union([2, 3], 20, rng, noise=0.0)
    residuals = sine_residuals(X, bases)
    assert residuals.shape == (40, 2)
    assert np.all((residuals >= 0) & (residuals <= 1))
    assert_allclose(residuals[:20, 0], 0.0, atol=1e-12)
    assert_allclose(residuals[20:, 1], 0.0, atol=1e-12)


@pytest.mark.parametrize("smoothing", [0.0, 5.0])
def test_refinement_fixes_corrupted_labels(smoothing):
    rng = np.random.RandomState(1)
    X, y, _ = union([4, 4, 4], 100, rng)
    labels = y.copy()
    flip = rng.choice(300, 60, replace=False)
    labels[flip] = (labels[flip] + 1) % 3
    neighbors = sign_invariant_neighbors(X, 10)
    refined, bases, n_iter, converged = k_subspaces(
        X,
        labels,
        3,
        neighbors=neighbors,
        smoothing=smoothing,
        subspace_dim=4,
        subspace_dim_tol=0.05,
        max_iter=50,
    )
    assert converged and 1 <= n_iter < 50
    assert len(bases) == 3
    assert np.mean(refined != y) < 0.02


@pytest.mark.parametrize("smoothing", [0.0, 5.0])
def test_one_round_is_the_smoothed_assignment_to_the_fitted_subspaces(smoothing):
    """A round fits one subspace per cluster, takes the median squared sine
    distance of the points to their own as the scale, and gives each point
    the label of least ``residual / scale + smoothing * disagreements``."""
    rng = np.random.RandomState(2)
    X, y, _ = union([3, 3, 3], 60, rng, noise=0.05)
    labels = np.where(rng.rand(y.size) < 0.3, rng.randint(0, 3, y.size), y)
    neighbors = sign_invariant_neighbors(X, 8)
    bases, _ = fit_subspaces(X, labels, 3, 3, 0.05)
    residuals = sine_residuals(X, bases)
    scale = np.median(residuals[np.arange(y.size), labels])
    disagree = (labels[neighbors][:, :, None] != np.arange(3)).sum(axis=1)
    expected = np.argmin(residuals / scale + smoothing * disagree, axis=1)
    found, _, n_iter, _ = k_subspaces(
        X,
        labels,
        3,
        neighbors=neighbors,
        smoothing=smoothing,
        subspace_dim=3,
        max_iter=1,
    )
    assert n_iter == 1 and not np.array_equal(expected, labels)
    assert_array_equal(found, expected)


def test_refinement_keeps_true_labels():
    rng = np.random.RandomState(2)
    X, y, _ = union([3, 3], 80, rng)
    refined, _, n_iter, converged = k_subspaces(
        X,
        y,
        2,
        neighbors=sign_invariant_neighbors(X, 10),
        smoothing=5.0,
        subspace_dim=3,
        subspace_dim_tol=0.05,
        max_iter=5,
    )
    assert_array_equal(refined, y)
    assert converged and n_iter == 1


def test_small_cluster_is_reseeded_on_the_worst_fit_subspace():
    """Two planes of R^3 all labelled 0, cluster 1 empty: the reseeded cluster
    takes mostly points of one plane, and the refinement then separates them."""
    rng = np.random.RandomState(0)
    X, y, _ = union([2, 2], 30, rng, noise=0.0, n_features=3)
    labels = refill_small_clusters(X, np.zeros(60, dtype=np.intp), 2, 2, 0.05)
    moved = labels == 1
    assert moved.sum() >= 4
    assert np.bincount(y[moved]).max() >= 0.8 * moved.sum()
    refined, *_ = k_subspaces(X, np.zeros(60, dtype=np.intp), 2, smoothing=0.0)
    assert adjusted_rand_score(y, refined) == 1.0


def test_no_reseed_when_no_cluster_can_spare_points():
    rng = np.random.RandomState(0)
    X, _, _ = union([4], 10, rng)
    labels = np.zeros(10, dtype=np.intp)
    assert_array_equal(refill_small_clusters(X, labels, 3, 4, 0.05), labels)
    refined, bases, _, converged = k_subspaces(X, labels, 3, smoothing=0.0)
    assert converged
    assert_array_equal(refined, 0)
    assert [b.shape[1] for b in bases] == [4, 0, 0]


def test_smoothed_cost_counts_disagreeing_neighbours():
    from sklearn_gpca._ksubspaces import smoothed_cost

    rng = np.random.RandomState(0)
    residuals = rng.rand(50, 3)
    neighbor_labels = rng.randint(3, size=(50, 7))
    cost = smoothed_cost(residuals, 0.5, neighbor_labels, 2.0)
    # derived truth: residual / scale + smoothing * #{neighbours labelled != k}
    expected = residuals / 0.5 + 2.0 * np.array(
        [[np.sum(row != k) for k in range(3)] for row in neighbor_labels]
    )
    np.testing.assert_allclose(cost, expected)
