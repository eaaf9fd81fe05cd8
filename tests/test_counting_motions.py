"""Tests for counting motions in a wide projection: GPCAClustering's
``segmentation_dim`` and the trajectory coding length of ``n_clusters="auto"``."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose, assert_array_equal
from sklearn.model_selection import GridSearchCV
from sklearn.pipeline import make_pipeline

from sklearn_gpca import (
    GPCAClustering,
    PowerFactorization,
    distinct_coding_length_cost,
    refined_trajectory_coding_length_cost,
    trajectory_coding_length_cost,
)
from sklearn_gpca._coding_length import coding_length
from sklearn_gpca._model_selection import TRAJECTORY_DISTORTION
from sklearn_gpca._rows import unit_rows
from sklearn_gpca.datasets import make_motions
from sklearn_gpca.metrics import misclassification_rate


def _subspaces(n, *, n_per=60, dim=4, width=20, noise=1e-3, seed=0):
    """Points on ``n`` random ``dim``-dimensional subspaces of R^width: the
    union of ``n <= 5`` generic 4-D subspaces of R^20 is direct, so each
    group is a distinct subspace and ``n`` is the number to find."""
    rng = np.random.RandomState(seed)
    bases = [np.linalg.qr(rng.randn(width, dim))[0] for _ in range(n)]
    X = np.vstack([rng.randn(n_per, dim) @ B.T for B in bases])
    X += noise * rng.randn(*X.shape)
    return X, np.repeat(np.arange(n), n_per)


@pytest.mark.parametrize("n", [1, 2, 3, 4, 5])
def test_auto_finds_the_number_of_distinct_subspaces(n):
    X, y = _subspaces(n)
    model = GPCAClustering(
        "auto", segmentation_dim=5, max_clusters=min(n + 1, 5), random_state=0
    ).fit(X)
    assert model.n_clusters_ == n
    assert misclassification_rate(y, model.labels_) < 0.05
    # the costs are the trajectory coding length of each segmentation
    assert np.argmin(model.n_clusters_costs_) == n - 1


def test_segmentation_space_is_the_whitened_projection():
    """With complete data, GPCAClustering(segmentation_dim=5) on the unwhitened
    rank-20 projection segments what PowerFactorization(5) returns."""
    X, _ = make_motions(3, n_points=150, min_angle=30, random_state=0)
    wide = PowerFactorization(20, whiten=False, random_state=0).fit_transform(X)
    narrow = PowerFactorization(5, random_state=0).fit_transform(X)
    model = GPCAClustering(3, segmentation_dim=5, random_state=0).fit(wide)
    direct = GPCAClustering(3, random_state=0).fit(narrow)
    assert misclassification_rate(direct.labels_, model.labels_) == 0
    Z = (wide @ model.segmentation_components_.T) / model.segmentation_scale_
    assert_allclose(np.abs(Z), np.abs(narrow), atol=1e-4)
    assert model.n_features_in_ == 20 and model.normals_.shape == (3, 5)
    assert_array_equal(model.predict(wide), model.labels_)


def test_default_criterion_follows_segmentation_dim():
    X, _ = _subspaces(2)
    wide = GPCAClustering("auto", segmentation_dim=5, max_clusters=3, random_state=0)
    narrow = GPCAClustering("auto", max_clusters=3, random_state=0)
    wide.fit(X)
    narrow.fit(X[:, :5])
    labels = wide.labels_
    assert_allclose(
        -wide.score(X) * X.shape[0], refined_trajectory_coding_length_cost(X, labels)
    )
    assert_allclose(
        -narrow.score(X[:, :5]) * X.shape[0],
        distinct_coding_length_cost(X[:, :5], narrow.labels_),
    )


@pytest.mark.filterwarnings("ignore:One or more of the test scores are non-finite")
@pytest.mark.filterwarnings("ignore::RuntimeWarning")
def test_grid_search_over_the_wide_pipeline_agrees_with_auto():
    """The unsupervised GridSearchCV over n_clusters scores by the same
    criterion as n_clusters="auto" (the refined trajectory coding length, inf
    where a refined group is too small to be a motion): on the training data
    they agree, costs included."""
    X, _ = _subspaces(3, n_per=50)
    pipe = make_pipeline(
        PowerFactorization(20, whiten=False, random_state=0),
        GPCAClustering(segmentation_dim=5, random_state=0),
    )
    everything = [(np.arange(X.shape[0]), np.arange(X.shape[0]))]
    search = GridSearchCV(
        pipe, {"gpcaclustering__n_clusters": [1, 2, 3, 4]}, cv=everything
    ).fit(X)
    auto = pipe.set_params(
        gpcaclustering__n_clusters="auto", gpcaclustering__max_clusters=4
    ).fit(X)
    assert search.best_params_["gpcaclustering__n_clusters"] == 3
    assert auto[-1].n_clusters_ == 3
    costs = -search.cv_results_["mean_test_score"] * X.shape[0]
    assert_allclose(costs, auto[-1].n_clusters_costs_, rtol=1e-6)
    assert np.isinf(costs[-1])  # a fourth group of the descent empties


def test_trajectory_coding_length_codes_few_points_in_fewer_directions():
    """Below 4 points per dimension the unit points are coded in their
    n_samples // 4 leading (uncentred) principal directions."""
    X, y = _subspaces(2, n_per=20)  # 40 points in R^20: 10 directions
    _, _, components = np.linalg.svd(unit_rows(X), full_matrices=False)
    projected = unit_rows(X) @ components[:10].T
    expected = coding_length(unit_rows(projected), y, TRAJECTORY_DISTORTION)
    assert_allclose(trajectory_coding_length_cost(X, y), expected)
    X, y = _subspaces(2, n_per=40)  # 80 points: all 20 directions
    expected = coding_length(unit_rows(X), y, TRAJECTORY_DISTORTION)
    assert_allclose(trajectory_coding_length_cost(X, y), expected)


def test_trajectory_coding_length_prefers_whole_motions():
    """Merging two subspaces or splitting one both cost bits."""
    X, y = _subspaces(2, n_per=100)
    split = np.where(np.arange(y.size) % 2, y, y + 2)
    true = trajectory_coding_length_cost(X, y)
    assert true < trajectory_coding_length_cost(X, 0 * y)
    assert true < trajectory_coding_length_cost(X, split)


@pytest.mark.parametrize("dim", [1, 2.5, True, "5"])
def test_bad_segmentation_dim_is_named(dim):
    X, _ = _subspaces(2)
    with pytest.raises(ValueError, match="'segmentation_dim' parameter"):
        GPCAClustering(2, segmentation_dim=dim).fit(X)


def test_segmentation_dim_beyond_the_data_is_explained():
    X, _ = _subspaces(2)
    with pytest.raises(ValueError, match="segmentation_dim=21 exceeds the n_samples"):
        GPCAClustering(2, segmentation_dim=21).fit(X)
    with pytest.raises(ValueError, match="min\\(n_samples, n_features\\)"):
        GPCAClustering(2, segmentation_dim=8).fit(X[:6])


def test_predict_needs_the_training_width():
    X, _ = _subspaces(2)
    model = GPCAClustering(2, segmentation_dim=5, random_state=0).fit(X)
    with pytest.raises(ValueError, match="features"):
        model.predict(X[:, :5])


@settings(deadline=None, max_examples=25)
@given(
    n_groups=st.integers(1, 4),
    n_per=st.integers(3, 30),
    scale=st.floats(1e-3, 1e3),
    seed=st.integers(0, 2**16),
)
def test_trajectory_coding_length_is_invariant(n_groups, n_per, scale, seed):
    """The code depends on the directions of the trajectories and on the
    partition only: not on their lengths, an orthogonal change of
    coordinates (the projection's basis) or the names of the groups."""
    X, y = _subspaces(n_groups, n_per=n_per, seed=seed)
    rng = np.random.RandomState(seed)
    rotation = np.linalg.qr(rng.randn(X.shape[1], X.shape[1]))[0]
    lengths = scale * rng.uniform(0.1, 10.0, size=(X.shape[0], 1))
    renamed = rng.permutation(n_groups)[y] + 7
    cost = trajectory_coding_length_cost(X, y)
    assert_allclose(
        trajectory_coding_length_cost(lengths * X @ rotation, renamed),
        cost,
        rtol=1e-7,
    )
