"""Tests for GPCAClustering."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose, assert_array_equal
from scipy.optimize import linear_sum_assignment
from sklearn.metrics import adjusted_rand_score
from sklearn.model_selection import GridSearchCV, KFold
from sklearn.pipeline import make_pipeline
from sklearn.utils.estimator_checks import parametrize_with_checks

from sklearn_gpca import PowerFactorization
from sklearn_gpca._affinity import local_normal_bases, sign_invariant_neighbors
from sklearn_gpca._gpca import GPCAClustering
from sklearn_gpca._veronese import veronese_map
from sklearn_gpca.datasets import make_motions

NOISE = 1e-3


def misclassification_rate(y_true, y_pred):
    """Error rate after the best one-to-one matching of labels."""
    n_labels = max(y_true.max(), y_pred.max()) + 1
    counts = np.zeros((n_labels, n_labels))
    np.add.at(counts, (y_true, y_pred), 1)
    rows, cols = linear_sum_assignment(-counts)
    return 1.0 - counts[rows, cols].sum() / y_true.size


def random_bases(dims, n_features, rng):
    return [np.linalg.qr(rng.randn(n_features, dim))[0] for dim in dims]


def sample_subspaces(bases, n_per_subspace, rng, noise=NOISE):
    """Gaussian points on each subspace plus isotropic Gaussian noise."""
    X = np.vstack([rng.randn(n_per_subspace, B.shape[1]) @ B.T for B in bases])
    X += noise * rng.randn(*X.shape)
    return X, np.repeat(np.arange(len(bases)), n_per_subspace)


def hyperplane_normal(basis):
    return np.linalg.svd(basis, full_matrices=True)[0][:, -1]


@pytest.fixture(scope="module")
def three_hyperplanes():
    rng = np.random.RandomState(0)
    bases = random_bases([4, 4, 4], 5, rng)
    X, y = sample_subspaces(bases, 200, rng)
    X_new, y_new = sample_subspaces(bases, 200, rng)
    model = GPCAClustering(n_clusters=3, random_state=0).fit(X)
    return bases, X, y, X_new, y_new, model


def test_three_hyperplanes_segmented(three_hyperplanes):
    _, _, y, _, _, model = three_hyperplanes
    assert misclassification_rate(y, model.labels_) <= 0.01
    assert model.labels_.dtype.kind == "i"
    assert set(model.labels_) == {0, 1, 2}


def test_three_hyperplanes_normals_recovered(three_hyperplanes):
    bases, _, _, _, _, model = three_hyperplanes
    assert model.normals_.shape == (3, 5)
    assert_allclose(np.linalg.norm(model.normals_, axis=1), 1.0)
    true_normals = np.array([hyperplane_normal(B) for B in bases])
    cosines = np.abs(true_normals @ model.normals_.T)
    assert np.all(cosines.max(axis=1) > 0.99)


def test_fitted_attributes_are_consistent(three_hyperplanes):
    _, X, _, _, _, model = three_hyperplanes
    assert model.n_features_in_ == 5
    assert model.exponents_.shape == (35, 5)
    assert model.coef_.shape == (35,)
    assert_allclose(np.linalg.norm(model.coef_), 1.0)
    assert model.point_normals_.shape == X.shape
    assert_allclose(np.linalg.norm(model.point_normals_, axis=1), 1.0)
    # the polynomial nearly vanishes on the data (noise 1e-3, points of norm ~2)
    values = veronese_map(X, 3) @ model.coef_
    assert np.median(np.abs(values)) < 1e-2
    manual = np.prod(X[:, None, :] ** model.exponents_, axis=2) @ model.coef_
    assert_allclose(manual, values, atol=1e-12)


def test_predict_fresh_points(three_hyperplanes):
    _, _, _, X_new, y_new, model = three_hyperplanes
    labels = model.predict(X_new)
    assert labels.shape == y_new.shape
    assert misclassification_rate(y_new, labels) <= 0.01


@pytest.mark.parametrize("dims", [(2, 4), (3, 4)])
@pytest.mark.parametrize("seed", [0, 1])
def test_degenerate_subspace_beside_hyperplane(dims, seed):
    # section 2.2.4: one polynomial picks a hyperplane containing the low-dim one
    rng = np.random.RandomState(seed)
    X, y = sample_subspaces(random_bases(dims, 5, rng), 200, rng)
    model = GPCAClustering(n_clusters=2, random_state=0).fit(X)
    assert misclassification_rate(y, model.labels_) <= 0.02


@pytest.mark.parametrize("seed", [0, 1])
def test_dependent_hyperplanes(seed):
    # two hyperplanes of R^5 intersecting in a 3-D subspace
    rng = np.random.RandomState(seed)
    Q = np.linalg.qr(rng.randn(5, 5))[0]
    bases = [Q[:, [0, 1, 2, 3]], Q[:, [0, 1, 2, 4]]]
    X, y = sample_subspaces(bases, 200, rng)
    model = GPCAClustering(n_clusters=2, random_state=0).fit(X)
    assert misclassification_rate(y, model.labels_) <= 0.02


def test_lines_in_the_plane():
    angles = np.array([0.1, 1.2, 2.3])
    directions = np.column_stack([np.cos(angles), np.sin(angles)])
    rng = np.random.RandomState(0)
    t = rng.randn(3, 50, 1)
    X = (t * directions[:, None, :]).reshape(-1, 2) + NOISE * rng.randn(150, 2)
    model = GPCAClustering(n_clusters=3, random_state=0).fit(X)
    assert misclassification_rate(np.repeat(np.arange(3), 50), model.labels_) == 0


def test_single_cluster_gives_least_singular_vector():
    rng = np.random.RandomState(0)
    X, _ = sample_subspaces(random_bases([3], 4, rng), 50, rng)
    model = GPCAClustering(n_clusters=1).fit(X)
    assert_array_equal(model.labels_, 0)
    smallest = np.linalg.svd(X / np.linalg.norm(X, axis=1, keepdims=True))[2][-1]
    assert_allclose(np.abs(model.normals_[0] @ smallest), 1.0, atol=1e-10)
    assert_array_equal(model.predict(X), 0)


def test_score_prefers_true_number_of_hyperplanes():
    rng = np.random.RandomState(0)
    for n_true in [2, 3]:
        bases = random_bases([4] * n_true, 5, rng)
        X, _ = sample_subspaces(bases, 200, rng)
        X_test, _ = sample_subspaces(bases, 200, rng)
        scores = [
            GPCAClustering(n_clusters=n, random_state=0).fit(X).score(X_test)
            for n in range(1, 6)
        ]
        assert np.argmax(scores) + 1 == n_true
        assert isinstance(scores[0], float)


def test_deterministic_with_random_state(three_hyperplanes):
    _, X, _, _, _, model = three_hyperplanes
    again = GPCAClustering(n_clusters=3, random_state=0).fit(X)
    assert_array_equal(again.labels_, model.labels_)
    assert_allclose(again.normals_, model.normals_)
    assert_allclose(again.coef_, model.coef_)


@settings(max_examples=10, deadline=None, derandomize=True)
@given(
    scale=st.floats(min_value=1e-2, max_value=1e2),
    seed=st.integers(min_value=0, max_value=2**16),
)
def test_scaling_keeps_and_permuting_permutes(scale, seed):
    rng = np.random.RandomState(seed)
    X, _ = sample_subspaces(random_bases([3, 3], 4, rng), 40, rng)
    model = GPCAClustering(n_clusters=2, random_state=0).fit(X)
    scaled = GPCAClustering(n_clusters=2, random_state=0).fit(scale * X)
    assert adjusted_rand_score(model.labels_, scaled.labels_) == 1.0
    assert_allclose(scaled.point_normals_, model.point_normals_, atol=1e-8)
    # the polynomial and the normals are permutation equivariant; k-means draws
    # its seeds by row index, so only the normals are compared exactly
    permutation = rng.permutation(X.shape[0])
    permuted = GPCAClustering(n_clusters=2, random_state=0).fit(X[permutation])
    assert_allclose(permuted.coef_, model.coef_, atol=1e-8)
    assert_allclose(
        permuted.point_normals_, model.point_normals_[permutation], atol=1e-8
    )


def test_nan_points_to_power_factorization():
    X = np.random.RandomState(0).randn(20, 3)
    X[[2, 5], 1] = np.nan
    with pytest.raises(ValueError, match=r"NaN \(2 missing.*PowerFactorization"):
        GPCAClustering().fit(X)


def test_too_few_samples():
    X = np.random.RandomState(0).randn(10, 5)
    msg = (
        r"n_samples=10 is too few .* n_clusters=3 in n_features=5 .* "
        r"35 monomials, so at least 34"
    )
    with pytest.raises(ValueError, match=msg):
        GPCAClustering(n_clusters=3).fit(X)


@pytest.mark.parametrize("n_clusters", [0, -1])
def test_bad_n_clusters(n_clusters):
    X = np.random.RandomState(0).randn(10, 3)
    with pytest.raises(ValueError, match="'n_clusters' parameter"):
        GPCAClustering(n_clusters=n_clusters).fit(X)


def test_one_feature_rejected():
    with pytest.raises(ValueError, match=r"1 feature\(s\)"):
        GPCAClustering().fit(np.arange(1.0, 11.0)[:, None])


def test_zero_rows_warn_and_are_left_out():
    rng = np.random.RandomState(0)
    X, _ = sample_subspaces(random_bases([2, 2], 3, rng), 30, rng)
    X_zero = X.copy()
    X_zero[[3, 7, 40]] = 0.0
    with pytest.warns(UserWarning, match=r"3 \(3, 7, 40\) all-zero rows"):
        model = GPCAClustering(random_state=0).fit(X_zero)
    assert_array_equal(model.labels_[[3, 7, 40]], 0)
    assert_array_equal(model.point_normals_[[3, 7, 40]], 0.0)
    keep = np.ones(60, dtype=bool)
    keep[[3, 7, 40]] = False
    clean = GPCAClustering(random_state=0).fit(X[keep])
    assert adjusted_rand_score(model.labels_[keep], clean.labels_) == 1.0


def test_only_zero_rows_is_too_few():
    with pytest.raises(ValueError, match=r"n_samples=6 \(6 of them all-zero\)"):
        GPCAClustering().fit(np.zeros((6, 2)))


def test_predict_checks_features(three_hyperplanes):
    model = three_hyperplanes[-1]
    with pytest.raises(ValueError, match="X has 4 features"):
        model.predict(np.ones((2, 4)))


@parametrize_with_checks([GPCAClustering()])
def test_sklearn_compatible_estimator(estimator, check):
    check(estimator)


# Beyond the paper: low-dimensional, dependent subspaces, number of motions.

PAPER = dict(
    normalize=False,
    affinity="polynomial",
    n_neighbors=None,
    affinity_power=1,
    refine=False,
)


@pytest.mark.parametrize("dims", [(2, 2), (2, 3), (2, 2, 4), (2, 3, 4)])
@pytest.mark.parametrize("seed", [0, 1])
def test_several_low_dimensional_subspaces(dims, seed):
    # one polynomial cannot model two or more low-dimensional subspaces; local
    # normal subspaces with estimated codimension can
    rng = np.random.RandomState(seed)
    X, y = sample_subspaces(random_bases(dims, 5, rng), 150, rng)
    model = GPCAClustering(n_clusters=len(dims), random_state=0).fit(X)
    assert misclassification_rate(y, model.labels_) <= 0.02
    assert len(model.subspace_bases_) == len(dims)
    assert model.normals_.shape == (len(dims), 5)
    assert misclassification_rate(y, model.predict(X)) <= 0.02


def test_paper_settings_fail_on_two_planes():
    # the documented limitation of a single polynomial (section 2.2.4)
    rng = np.random.RandomState(0)
    X, y = sample_subspaces(random_bases([2, 2], 5, rng), 150, rng)
    model = GPCAClustering(n_clusters=2, random_state=0, **PAPER).fit(X)
    assert misclassification_rate(y, model.labels_) > 0.2


def test_local_codimension_estimated():
    rng = np.random.RandomState(0)
    X, _ = sample_subspaces(random_bases([2, 4], 5, rng), 150, rng)
    bases, codims = local_normal_bases(
        X / np.linalg.norm(X, axis=1, keepdims=True),
        sign_invariant_neighbors(X / np.linalg.norm(X, axis=1, keepdims=True), 10),
        0.05,
    )
    # points on the plane: at least two normal directions, mostly all three
    assert np.all(codims[:150] >= 2)
    assert np.mean(codims[:150] == 3) > 0.5
    assert np.mean(codims[150:] == 1) > 0.9
    assert bases.shape == (300, 5, 5)


@pytest.mark.parametrize("dependent", ["rotation", "translation"])
def test_partially_dependent_motions(dependent):
    X, y = make_motions(
        2, n_points=200, n_frames=10, dependent=dependent, random_state=0
    )
    pipe = make_pipeline(
        PowerFactorization(random_state=0), GPCAClustering(2, random_state=0)
    )
    assert misclassification_rate(y, pipe.fit_predict(X)) <= 0.05


def test_grid_search_picks_number_of_motions():
    rng = np.random.RandomState(0)
    for n_true in [2, 3]:
        X, _ = sample_subspaces(random_bases([4] * n_true, 5, rng), 150, rng)
        search = GridSearchCV(
            GPCAClustering(random_state=0),
            {"n_clusters": [1, 2, 3, 4]},
            cv=KFold(3, shuffle=True, random_state=0),
        ).fit(X)
        assert search.best_params_["n_clusters"] == n_true


def test_refinement_and_paper_settings_agree_on_clean_hyperplanes(three_hyperplanes):
    _, X, y, _, _, default = three_hyperplanes
    paper = GPCAClustering(3, random_state=0, **PAPER).fit(X)
    assert misclassification_rate(y, paper.labels_) <= 0.01
    assert paper.n_iter_ == 0
    # the two settings agree: the same segmentation (to 1 %) and normals
    assert misclassification_rate(paper.labels_, default.labels_) <= 0.01
    overlap = np.abs(paper.normals_ @ default.normals_.T).max(axis=1)
    assert_allclose(overlap, 1.0, atol=1e-4)


def test_power_needs_graph():
    X = np.random.RandomState(0).randn(40, 3)
    with pytest.raises(ValueError, match="affinity_power=4 needs a neighbour"):
        GPCAClustering(n_neighbors=None).fit(X)


@pytest.mark.parametrize("init", ["multi", "spectral"])
def test_init_candidates(init):
    """Both initialisations segment an unbalanced union of hyperplanes."""
    rng = np.random.RandomState(7)
    bases = random_bases([4, 4, 4], 5, rng)
    X = np.vstack(
        [rng.randn(n, 4) @ B.T for n, B in zip([30, 60, 200], bases, strict=True)]
    )
    X += NOISE * rng.randn(*X.shape)
    y = np.repeat(np.arange(3), [30, 60, 200])
    model = GPCAClustering(3, init=init, random_state=0).fit(X)
    assert misclassification_rate(y, model.labels_) < 0.02
    # three graphs (fine, coarse, product) x (n, n + 1 merged) clusters
    n_candidates = 6 if init == "multi" else 1
    assert model.init_scores_.shape == (n_candidates,)
    assert 0 <= model.init_chosen_ < n_candidates
    if init == "multi":
        residuals = model.init_residuals_
        admissible = residuals <= 3 * residuals.min()
        assert admissible[model.init_chosen_]
        assert (
            model.init_scores_[model.init_chosen_]
            == model.init_scores_[admissible].min()
        )


def test_fit_gate_rejects_merged_motions():
    """The normalised cut alone would merge two overlapping motions and split
    the third; that candidate's hyperplanes fit > 3 times worse and is gated."""
    X, y = make_motions(3, n_points=600, n_frames=10, random_state=6)
    Z = PowerFactorization(random_state=0).fit_transform(X)
    model = GPCAClustering(3, random_state=0).fit(Z)
    assert misclassification_rate(y, model.labels_) <= 0.05
    ungated = int(np.argmin(model.init_scores_))
    assert ungated != model.init_chosen_
    assert model.init_residuals_[ungated] > 3 * model.init_residuals_.min()
    assert misclassification_rate(y, model._candidate_labels[ungated]) > 0.1


def test_init_multi_without_coarse_scale():
    """With too few points for a coarser neighbourhood, two graphs remain."""
    rng = np.random.RandomState(3)
    bases = random_bases([4, 4], 5, rng)
    X = np.vstack([rng.randn(14, 4) @ B.T for B in bases])
    model = GPCAClustering(2, n_neighbors=30, random_state=0).fit(X)
    assert model.init_scores_.shape == (4,)
    assert misclassification_rate(np.repeat([0, 1], 14), model.labels_) == 0.0


def test_subsample_route_matches_full_route(three_hyperplanes):
    """Spectral steps on a subsample, extended to all points: same segmentation."""
    _, X, y, _, _, _ = three_hyperplanes
    full = GPCAClustering(3, max_spectral_samples=None, random_state=0)
    sub = GPCAClustering(3, max_spectral_samples=300, random_state=0)
    full.fit(X)
    sub.fit(X)
    assert full.n_spectral_samples_ == 600
    assert sub.n_spectral_samples_ == 300
    # two points of 600, near intersections, go the other way
    assert misclassification_rate(full.labels_, sub.labels_) <= 2 / 600 + 1e-12
    assert misclassification_rate(y, sub.labels_) <= 0.01
    assert sub.point_normals_.shape == X.shape
    assert_array_equal(sub.predict(X), sub.labels_)


def test_subsample_route_skipped_for_dense_kernel():
    rng = np.random.RandomState(0)
    X, _ = sample_subspaces(random_bases([4, 4], 5, rng), 100, rng)
    model = GPCAClustering(
        2, n_neighbors=None, affinity_power=1, max_spectral_samples=50
    ).fit(X)
    assert model.n_spectral_samples_ == 200
