"""Tests for choosing the number of clusters: the criterion, select_n_clusters,
NClustersSearch and n_clusters="auto"."""

# SPDX-License-Identifier: BSD-3-Clause

import warnings

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal
from sklearn.base import clone
from sklearn.exceptions import FitFailedWarning
from sklearn.model_selection import GridSearchCV, KFold
from sklearn.pipeline import make_pipeline

from sklearn_gpca import (
    GPCAClustering,
    NClustersSearch,
    PowerFactorization,
    coding_length_cost,
    distinct_coding_length_cost,
    gpca,
    merge_ratio,
    select_n_clusters,
    sine_likelihood_cost,
)
from sklearn_gpca._coding_length import coding_length
from sklearn_gpca._model_selection import MIN_MERGE_RATIO
from sklearn_gpca.datasets import make_motions
from sklearn_gpca.metrics import misclassification_rate


def test_coding_length_prefers_true_segmentation():
    rng = np.random.RandomState(0)
    bases = [np.linalg.qr(rng.randn(5, 2))[0] for _ in range(2)]
    X = np.vstack([rng.randn(100, 2) @ B.T for B in bases])
    X += 1e-3 * rng.randn(*X.shape)
    X /= np.linalg.norm(X, axis=1, keepdims=True)
    y = np.repeat([0, 1], 100)
    true = coding_length(X, y, 0.03)
    assert true < coding_length(X, np.zeros_like(y), 0.03)  # merged
    split = np.where(np.arange(200) % 2 == 0, y, y + 2)  # each one split in two
    assert true < coding_length(X, split, 0.03)
    # labels are names only
    assert coding_length(X, 1 - y, 0.03) == pytest.approx(true)


@pytest.mark.parametrize("n_motions", [1, 2])
@pytest.mark.parametrize("seed", [0, 1])
def test_auto_finds_number_of_motions(n_motions, seed):
    # Three motions of make_motions often have two of them near one
    # hyperplane of R^5 (merge ratio 3-4 < 5): the default criterion then
    # finds two (benchmarks/results/n_motions.md). Three distinct hyperplanes
    # are tested in test_auto_finds_the_number_of_hyperplanes.
    X, y = make_motions(
        n_motions,
        n_points=100 * n_motions,
        noise=0.5,
        missing=0.2,
        random_state=seed,
    )
    pipe = make_pipeline(
        PowerFactorization(random_state=0),
        GPCAClustering("auto", random_state=0),
    ).fit(X)
    model = pipe[-1]
    assert model.n_clusters_ == n_motions
    assert model.n_clusters_costs_.shape == (5,)
    assert np.argmin(model.n_clusters_costs_) == n_motions - 1
    assert misclassification_rate(y, model.labels_) <= 0.05
    assert model.labels_.max() == n_motions - 1
    assert len(model.subspace_bases_) == n_motions
    # the fitted model is the fixed-n fit, and score uses its n
    fixed = GPCAClustering(n_motions, random_state=0).fit(pipe[0].transform(X))
    assert_array_equal(model.labels_, fixed.labels_)
    assert model.score(pipe[0].transform(X)) == pytest.approx(
        fixed.score(pipe[0].transform(X))
    )


def test_auto_skips_degrees_without_enough_points():
    rng = np.random.RandomState(0)
    X = rng.randn(40, 5)  # degree 3 needs 34 points, degree 4 needs 69
    # the plain coding length is finite wherever a fit was made
    model = GPCAClustering(
        "auto", max_clusters=5, criterion="coding_length", random_state=0
    ).fit(X)
    assert np.all(np.isfinite(model.n_clusters_costs_[:3]))
    assert np.all(np.isinf(model.n_clusters_costs_[3:]))
    assert 1 <= model.n_clusters_ <= 3
    # a Gaussian cloud is no union of distinct subspaces: one group
    assert GPCAClustering("auto", random_state=0).fit(X).n_clusters_ == 1


def test_auto_with_too_few_points_for_one_subspace():
    with pytest.raises(ValueError, match="n_samples=3 is too few"):
        GPCAClustering("auto").fit(np.random.RandomState(0).randn(3, 5))


def test_auto_respects_max_clusters():
    X, _ = make_motions(3, n_points=300, random_state=0)
    Z = PowerFactorization(random_state=0).fit_transform(X)
    model = GPCAClustering("auto", max_clusters=2, random_state=0).fit(Z)
    assert model.n_clusters_costs_.shape == (2,)
    assert model.n_clusters_ <= 2


def test_fixed_n_clusters_sets_n_clusters_():
    X, _ = make_motions(2, n_points=100, random_state=0)
    Z = PowerFactorization(random_state=0).fit_transform(X)
    model = GPCAClustering(2, random_state=0).fit(Z)
    assert model.n_clusters_ == 2
    assert not hasattr(model, "n_clusters_costs_")


@pytest.mark.parametrize("bad", ["two", 0, 2.5])
def test_bad_n_clusters_names_auto(bad):
    with pytest.raises(ValueError, match="'n_clusters' parameter"):
        GPCAClustering(bad).fit(np.random.RandomState(0).randn(30, 5))


def test_auto_warns_once_about_zero_rows():
    X, _ = make_motions(2, n_points=100, random_state=0)
    Z = PowerFactorization(random_state=0).fit_transform(X)
    Z = np.vstack([Z, np.zeros((2, Z.shape[1]))])
    with pytest.warns(UserWarning, match="all-zero") as records:
        model = GPCAClustering("auto", max_clusters=3, random_state=0).fit(Z)
    assert sum("all-zero" in str(r.message) for r in records) == 1
    assert model.labels_.shape == (102,)


# Model selection outside the clusterer.


def _projected_motions(n_motions, seed=0, noise=1.0):
    X, y = make_motions(
        n_motions, n_points=100 * n_motions, noise=noise, random_state=seed
    )
    return PowerFactorization(random_state=0).fit_transform(X), y


def test_auto_is_select_n_clusters_over_gpca():
    Z, _ = _projected_motions(3)
    model = GPCAClustering("auto", max_clusters=4, random_state=0).fit(Z)

    def segment(n):
        result = gpca(Z, n, random_state=0)
        return Z, result.labels, result

    best, costs, results = select_n_clusters(segment, [1, 2, 3, 4])
    assert_allclose(costs, model.n_clusters_costs_)
    assert best + 1 == model.n_clusters_
    assert_array_equal(results[best].labels, model.labels_)
    assert costs[best] == coding_length_cost(Z, model.labels_)


def test_select_n_clusters_takes_any_criterion():
    Z, _ = _projected_motions(2)

    def segment(n):
        return Z, gpca(Z, n, random_state=0).labels, n

    # a criterion that prefers more groups picks the largest candidate
    best, costs, fitted = select_n_clusters(
        segment, [1, 2, 3], criterion=lambda points, labels: -len(set(labels))
    )
    assert fitted[best] == 3
    assert_array_equal(costs, [-1, -2, -3])


@pytest.mark.parametrize("n_motions", [2, 3])
def test_search_around_a_pipeline_finds_the_number_of_motions(n_motions):
    X, _ = make_motions(n_motions, n_points=100 * n_motions, random_state=1)
    pipe = make_pipeline(
        PowerFactorization(random_state=0), GPCAClustering(random_state=0)
    )
    search = NClustersSearch(pipe, n_clusters_grid=[1, 2, 3, 4]).fit(X)
    assert search.best_n_clusters_ == n_motions
    assert search.best_estimator_[-1].n_clusters == n_motions
    assert search.costs_.shape == (4,)
    assert np.argmin(search.costs_) == n_motions - 1
    # the winner is the fixed-n pipeline
    fixed = clone(pipe).set_params(gpcaclustering__n_clusters=n_motions).fit(X)
    assert_array_equal(search.labels_, fixed[-1].labels_)
    assert_array_equal(search.predict(X), fixed.predict(X))
    # the pipeline's last step saw the projection the criterion was measured on
    Z = search.best_estimator_[:-1].transform(X)
    assert search.costs_[n_motions - 1] == pytest.approx(
        coding_length_cost(Z, search.labels_), rel=1e-6
    )
    assert not hasattr(pipe[-1], "labels_")  # the estimator was cloned


def test_search_agrees_with_auto():
    Z, _ = _projected_motions(3, seed=2)
    search = NClustersSearch(GPCAClustering(random_state=0)).fit(Z)
    auto = GPCAClustering("auto", random_state=0).fit(Z)
    assert search.best_n_clusters_ == auto.n_clusters_
    assert_allclose(search.costs_, auto.n_clusters_costs_)
    assert search.score(Z) == pytest.approx(auto.score(Z))


def test_search_skips_candidates_that_cannot_be_fitted():
    X = np.random.RandomState(0).randn(40, 5)  # degree 4 needs 69 points
    with pytest.warns(FitFailedWarning) as records:
        search = NClustersSearch(GPCAClustering(random_state=0)).fit(X)
    messages = [str(r.message) for r in records]
    assert any("n_clusters=4 was skipped" in m and "69" in m for m in messages)
    assert any("n_clusters=5 was skipped" in m for m in messages)
    assert np.isinf(search.costs_[3:]).all()
    assert search.best_n_clusters_ <= 3
    with pytest.raises(ValueError, match="too few for the Veronese"):
        NClustersSearch(GPCAClustering(), n_clusters_grid=[4, 5]).fit(X)


def test_score_is_minus_the_criterion_per_point():
    Z, _ = _projected_motions(2)
    model = GPCAClustering(2, random_state=0).fit(Z)
    expected = -coding_length_cost(Z, model.predict(Z)) / Z.shape[0]
    assert model.score(Z) == pytest.approx(expected)


def test_the_criterion_is_a_parameter_of_auto_and_score():
    Z, _ = _projected_motions(2)
    auto = GPCAClustering("auto", criterion="sine_likelihood", random_state=0).fit(Z)
    fixed = GPCAClustering(auto.n_clusters_, criterion="sine_likelihood").fit(Z)
    assert auto.score(Z) == pytest.approx(
        -sine_likelihood_cost(Z, auto.predict(Z)) / Z.shape[0]
    )
    assert np.argmin(auto.n_clusters_costs_) + 1 == auto.n_clusters_
    assert fixed.score(Z) == pytest.approx(
        -sine_likelihood_cost(Z, fixed.predict(Z)) / Z.shape[0]
    )


def test_sine_likelihood_prefers_exact_hyperplanes_at_their_number():
    rng = np.random.RandomState(0)
    bases = [np.linalg.qr(rng.randn(5, 4))[0] for _ in range(3)]
    X = np.vstack([rng.randn(60, 4) @ B.T for B in bases])
    y = np.repeat([0, 1, 2], 60)
    true = sine_likelihood_cost(X, y)
    assert true < sine_likelihood_cost(X, np.minimum(y, 1))  # two merged
    assert true < sine_likelihood_cost(X, np.where(np.arange(180) % 2, y, y + 3))


# The default criterion: the coding length among segmentations into distinct
# subspaces.


def _hyperplanes(n_planes, n_per_plane=30, noise=1e-3, seed=0):
    """Points on ``n_planes`` hyperplanes of R^5 with orthonormal normals."""
    rng = np.random.RandomState(seed)
    normals = np.linalg.qr(rng.randn(5, 5))[0][:, :n_planes].T
    blocks = [
        rng.randn(n_per_plane, 5) @ (np.eye(5) - np.outer(normal, normal))
        for normal in normals
    ]
    X = np.vstack(blocks) + noise * rng.randn(n_planes * n_per_plane, 5)
    return X, np.repeat(np.arange(n_planes), n_per_plane)


def _energy(points):
    """Squared sines of the 90 % best-fitted unit points to their hyperplane,
    refitted once to these points (by SVD)."""
    unit = points / np.linalg.norm(points, axis=1, keepdims=True)
    n_kept = max(int(np.ceil(0.9 * len(unit))), unit.shape[1])
    normal = np.linalg.svd(unit)[2][-1]
    kept = np.argsort(np.abs(unit @ normal))[:n_kept]
    normal = np.linalg.svd(unit[kept])[2][-1]
    return np.sum(np.sort(np.abs(unit @ normal))[:n_kept] ** 2)


def test_merge_ratio_is_the_worst_pair():
    X, y = _hyperplanes(3, noise=1e-2)
    ratios = [
        _energy(X[(y == a) | (y == b)]) / (_energy(X[y == a]) + _energy(X[y == b]))
        for a, b in [(0, 1), (0, 2), (1, 2)]
    ]
    assert merge_ratio(X, y) == pytest.approx(min(ratios), rel=1e-6)
    assert min(ratios) > 100  # three distinct hyperplanes
    # labels are names only, and scale does not matter
    assert merge_ratio(3 * X, 7 - 2 * y) == pytest.approx(min(ratios), rel=1e-6)


def test_merge_ratio_of_one_hyperplane_split_in_two():
    X, y = _hyperplanes(1, n_per_plane=80, noise=1e-2)
    halves = np.arange(80) % 2
    assert merge_ratio(X, halves) < 2  # both halves lie on the same hyperplane
    assert merge_ratio(X, y) == np.inf  # a single group
    assert merge_ratio(X, np.r_[np.zeros(77), np.ones(3)].astype(int)) == 0.0


def test_distinct_coding_length_gates_the_coding_length():
    X, y = _hyperplanes(2, noise=1e-2)
    assert distinct_coding_length_cost(X, y) == pytest.approx(coding_length_cost(X, y))
    split = np.where(np.arange(60) % 2 == 0, y, y + 2)  # each plane split in two
    assert merge_ratio(X, split) < MIN_MERGE_RATIO
    assert coding_length_cost(X, split) < np.inf
    assert distinct_coding_length_cost(X, split) == np.inf


@pytest.mark.parametrize("n_planes", [1, 2, 3, 4, 5])
def test_auto_finds_the_number_of_hyperplanes(n_planes):
    # degree 5 needs 125 points on distinct lines
    X, y = _hyperplanes(n_planes, n_per_plane=max(40, 250 // n_planes))
    model = GPCAClustering(
        "auto", max_clusters=min(n_planes + 1, 5), random_state=0
    ).fit(X)
    assert model.n_clusters_ == n_planes
    assert misclassification_rate(y, model.labels_) <= 0.02
    assert np.argmin(model.n_clusters_costs_) == n_planes - 1


@pytest.mark.parametrize("n_motions", [1, 4, 5])
def test_auto_finds_one_four_and_five_motions(n_motions):
    X, y = make_motions(
        n_motions,
        n_points=60 * n_motions + 70,
        noise=0.5,
        min_angle=20,
        random_state=0,
    )
    pipe = make_pipeline(
        PowerFactorization(random_state=0),
        GPCAClustering("auto", random_state=0),
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # empty clusters at n > 1
        pipe.fit(X)
    assert pipe[-1].n_clusters_ == n_motions
    assert misclassification_rate(y, pipe[-1].labels_) <= 0.05


def test_the_former_criterion_over_counts_pieces_of_one_plane():
    # two planes, each made of two 2-D subspaces: four Gaussians, two hyperplanes
    rng = np.random.RandomState(0)
    normals = np.linalg.qr(rng.randn(5, 5))[0].T
    blocks = []
    for plane in range(2):
        inside = np.linalg.qr(np.eye(5) - np.outer(normals[plane], normals[plane]))
        basis = inside[0][:, :4]
        for piece in range(2):
            blocks.append(rng.randn(60, 2) @ basis[:, 2 * piece : 2 * piece + 2].T)
    X = np.vstack(blocks) + 1e-3 * rng.randn(240, 5)
    former = GPCAClustering("auto", criterion="coding_length", random_state=0).fit(X)
    default = GPCAClustering("auto", random_state=0).fit(X)
    assert former.n_clusters_ > 2
    assert default.n_clusters_ == 2


@pytest.mark.filterwarnings("ignore:One or more of the test scores are non-finite")
@pytest.mark.filterwarnings("ignore::RuntimeWarning")
@pytest.mark.filterwarnings("ignore:.*clusters are empty:UserWarning")
@pytest.mark.parametrize("n_planes", [2, 3])
def test_grid_search_over_n_clusters_agrees_with_auto(n_planes):
    # Held-out halves of 150 points: the coding length of a few points per
    # group favours fewer groups (the bits of the memberships and of each
    # group's Gaussian), so the agreement needs folds of this size.
    X, _ = _hyperplanes(n_planes, n_per_plane=300 // n_planes)
    grid = list(range(1, n_planes + 2))
    search = GridSearchCV(
        GPCAClustering(random_state=0),
        {"n_clusters": grid},
        cv=KFold(2, shuffle=True, random_state=0),
    ).fit(X)
    auto = GPCAClustering("auto", max_clusters=grid[-1], random_state=0).fit(X)
    assert search.best_params_["n_clusters"] == auto.n_clusters_ == n_planes
    scores = search.cv_results_["mean_test_score"]
    assert np.isneginf(scores[-1])  # pieces of one hyperplane


@pytest.mark.filterwarnings("ignore:One or more of the test scores are non-finite")
@pytest.mark.filterwarnings("ignore::RuntimeWarning")
def test_grid_search_over_a_pipeline_agrees_with_auto():
    X, _ = make_motions(2, n_points=300, noise=0.5, min_angle=20, random_state=0)
    pipe = make_pipeline(
        PowerFactorization(random_state=0), GPCAClustering(random_state=0)
    )
    search = GridSearchCV(
        pipe,
        {"gpcaclustering__n_clusters": [1, 2, 3]},
        cv=KFold(2, shuffle=True, random_state=0),
    ).fit(X)
    auto = clone(pipe).set_params(
        gpcaclustering__n_clusters="auto", gpcaclustering__max_clusters=3
    )
    auto.fit(X)
    assert search.best_params_["gpcaclustering__n_clusters"] == 2
    assert auto[-1].n_clusters_ == 2


@pytest.mark.parametrize(
    "criterion, match",
    [("distinct", "'criterion' parameter"), (5, "'criterion' parameter")],
)
def test_bad_criterion_is_named(criterion, match):
    with pytest.raises(ValueError, match=match):
        GPCAClustering("auto", criterion=criterion).fit(_hyperplanes(2)[0])


@pytest.mark.parametrize("max_clusters", [0, 2.5, True])
def test_bad_max_clusters_is_named(max_clusters):
    with pytest.raises(ValueError, match="'max_clusters' parameter"):
        GPCAClustering("auto", max_clusters=max_clusters).fit(_hyperplanes(2)[0])


def test_auto_raises_the_warnings_of_the_kept_fit_only():
    X, _ = _hyperplanes(2, n_per_plane=40)
    with pytest.warns(UserWarning, match="clusters are empty"):
        gpca(X, 4, random_state=0)  # the refinement empties two clusters
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        model = GPCAClustering("auto", max_clusters=4, random_state=0).fit(X)
    assert model.n_clusters_ == 2
