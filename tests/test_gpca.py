"""Tests for GPCAClustering."""

# SPDX-License-Identifier: BSD-3-Clause

import ast
import inspect
import textwrap

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose, assert_array_equal
from scipy.optimize import linear_sum_assignment
from sklearn.metrics import adjusted_rand_score
from sklearn.model_selection import GridSearchCV
from sklearn.pipeline import make_pipeline

from sklearn_gpca import PowerFactorization, gpca, k_subspaces
from sklearn_gpca._affinity import sign_invariant_neighbors
from sklearn_gpca._gpca import GPCAClustering, _warn_empty_clusters
from sklearn_gpca._normals import local_normal_bases
from sklearn_gpca._selection import select_candidate
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


# Beyond the paper: low-dimensional, dependent subspaces, number of motions.

PAPER = dict(
    normalize=False,
    point_normals="one_polynomial",
    affinity="all_pairs",
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
    unit = X / np.linalg.norm(X, axis=1, keepdims=True)
    bases, codims = local_normal_bases(unit, sign_invariant_neighbors(unit, 10), 0.05)
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


@pytest.mark.parametrize("n_true", [2, 3])
def test_grid_search_agrees_with_auto(n_true):
    """GridSearchCV by ``score`` and n_clusters="auto" use one criterion: on
    the training data they choose the same, true number of hyperplanes."""
    rng = np.random.RandomState(0)
    X, _ = sample_subspaces(random_bases([4] * n_true, 5, rng), 150, rng)
    everything = [(np.arange(X.shape[0]), np.arange(X.shape[0]))]
    search = GridSearchCV(
        GPCAClustering(random_state=0), {"n_clusters": [1, 2, 3, 4]}, cv=everything
    ).fit(X)
    auto = GPCAClustering("auto", max_clusters=4, random_state=0).fit(X)
    assert search.best_params_["n_clusters"] == auto.n_clusters_ == n_true
    # score segments by predict, which gives labels_ on the training points
    costs = -search.cv_results_["mean_test_score"] * X.shape[0]
    assert_allclose(costs, auto.n_clusters_costs_, rtol=1e-3)


def test_refinement_and_paper_settings_agree_on_clean_hyperplanes(three_hyperplanes):
    """The paper's settings and the defaults both give every unambiguous point
    its nearest true hyperplane, so they agree with each other there."""
    bases, X, _, _, _, default = three_hyperplanes
    truth, margin = nearest_true_subspace(X, bases)
    clear = margin > 10 * NOISE
    paper = GPCAClustering(3, random_state=0, **PAPER).fit(X)
    assert paper.n_iter_ == 0 and default.n_iter_ > 0
    assert_same_segmentation(paper.labels_[clear], truth[clear])
    assert_same_segmentation(default.labels_[clear], paper.labels_[clear])
    # and the same normals
    overlap = np.abs(paper.normals_ @ default.normals_.T).max(axis=1)
    assert_allclose(overlap, 1.0, atol=1e-4)


def test_power_needs_graph():
    X = np.random.RandomState(0).randn(40, 3)
    with pytest.raises(ValueError, match="affinity_power=4 needs affinity="):
        GPCAClustering(affinity="all_pairs").fit(X)


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
    assert model.candidate_ncuts_.shape == (n_candidates,)
    assert model.candidate_residuals_.shape == (n_candidates,)
    assert 0 <= model.chosen_candidate_ < n_candidates
    if init == "multi":
        residuals = model.candidate_residuals_
        admissible = residuals <= 3 * residuals.min()
        assert admissible[model.chosen_candidate_]
        # the normalised cuts on the kNN graph and on the vote graph
        score = model.candidate_ncuts_ + model.candidate_vote_cuts_
        assert score[model.chosen_candidate_] == score[admissible].min()


def test_fit_gate_rejects_merged_motions():
    """A candidate that merges two subspaces and splits a third can have the
    smallest cut; its subspaces fit far worse, and the gate rejects it."""
    rng = np.random.RandomState(0)
    bases = random_bases([4, 4, 4], 5, rng)
    X, y = sample_subspaces(bases, 40, rng, noise=0.0)
    unit = X / np.linalg.norm(X, axis=1, keepdims=True)
    merged = np.where(y == 1, 0, np.where(np.arange(120) % 2 == 0, 1, 2))
    # a graph on which the merged labelling cuts nothing and the truth cuts
    graph = sp.csr_matrix((merged[:, None] == merged[None, :]).astype(float))
    chosen, cuts, residuals = select_candidate(
        unit, [merged, y], 3, graph=graph, subspace_dim=4, subspace_dim_tol=0.05
    )
    assert cuts[0] == 0.0 and cuts[1] > 0.0
    assert_allclose(residuals[1], 0.0, atol=1e-10)
    assert residuals[0] > 3 * residuals[1]
    assert chosen == 1
    # without the gate the cut alone takes the merged candidate
    assert (
        select_candidate(
            unit,
            [merged, y],
            3,
            graph=graph,
            subspace_dim=4,
            subspace_dim_tol=0.05,
            fit_gate=np.inf,
        )[0]
        == 0
    )


def test_init_multi_without_coarse_scale():
    """With too few points for a coarser neighbourhood, two graphs remain."""
    rng = np.random.RandomState(3)
    bases = random_bases([4, 4], 5, rng)
    X = np.vstack([rng.randn(14, 4) @ B.T for B in bases])
    model = GPCAClustering(2, n_neighbors=30, random_state=0).fit(X)
    assert model.candidate_ncuts_.shape == (4,)
    assert misclassification_rate(np.repeat([0, 1], 14), model.labels_) == 0.0


def nearest_true_subspace(X, bases):
    """Labels by the nearest true subspace, and the margin of that choice.

    The margin is the gap between the two smallest sine distances: points
    with a margin far above the noise have one right answer.
    """
    unit = X / np.linalg.norm(X, axis=1, keepdims=True)
    sines = np.sqrt(
        np.column_stack([1 - np.sum((unit @ B) ** 2, axis=1) for B in bases]).clip(0)
    )
    ordered = np.sort(sines, axis=1)
    return np.argmin(sines, axis=1), ordered[:, 1] - ordered[:, 0]


def assert_same_segmentation(labels, reference):
    """Equal up to a renaming of the groups."""
    assert adjusted_rand_score(reference, labels) == 1.0


def test_subsample_route_matches_full_route(three_hyperplanes):
    """Spectral steps on a subsample, extended to all points: both routes label
    every unambiguous point by its nearest true hyperplane."""
    bases, X, _, _, _, _ = three_hyperplanes
    truth, margin = nearest_true_subspace(X, bases)
    clear = margin > 10 * NOISE
    full = GPCAClustering(3, max_spectral_samples=None, random_state=0).fit(X)
    sub = GPCAClustering(3, max_spectral_samples=300, random_state=0).fit(X)
    assert full.n_spectral_samples_ == 600
    assert sub.n_spectral_samples_ == 300
    assert np.mean(clear) > 0.95
    assert_same_segmentation(full.labels_[clear], truth[clear])
    assert_same_segmentation(sub.labels_[clear], truth[clear])
    assert sub.point_normals_.shape == X.shape


def test_subsample_route_skipped_for_dense_kernel():
    rng = np.random.RandomState(0)
    X, _ = sample_subspaces(random_bases([4, 4], 5, rng), 100, rng)
    model = GPCAClustering(
        2, affinity="all_pairs", affinity_power=1, max_spectral_samples=50
    ).fit(X)
    assert model.n_spectral_samples_ == 200


# The function beside the estimator, and the shape of the estimator.


def test_function_and_estimator_agree(three_hyperplanes):
    _, X, _, _, _, model = three_hyperplanes
    result = gpca(X, 3, random_state=0)
    assert_array_equal(result.labels, model.labels_)
    assert_allclose(result.normals, model.normals_)
    assert_allclose(result.point_normals, model.point_normals_)
    assert_allclose(result.polynomials[0], model.coef_)
    assert result.chosen_candidate == model.chosen_candidate_
    assert result.candidate_labels.shape == (6, 600)
    assert_array_equal(result.candidate_labels[result.chosen_candidate], result.labels)


def test_function_and_estimator_share_defaults():
    function = inspect.signature(gpca).parameters
    estimator = inspect.signature(GPCAClustering).parameters
    shared = set(function) - {"X"}
    wrapper_only = {
        "max_clusters",
        "criterion",
        "segmentation_dim",
        "input_subspace_dim",
    }
    assert shared == set(estimator) - wrapper_only
    for name in shared:
        assert function[name].default == estimator[name].default, name
    for name, parameter in inspect.signature(k_subspaces).parameters.items():
        if parameter.kind == parameter.KEYWORD_ONLY and name in function:
            assert parameter.default == function[name].default, name


def test_function_validates_its_parameters():
    X = np.random.RandomState(0).randn(30, 3)
    with pytest.raises(ValueError, match="'point_normals' parameter of gpca"):
        gpca(X, 2, point_normals="polynomial")
    with pytest.raises(ValueError, match=r"NaN \(3 missing.*PowerFactorization"):
        gpca(np.where(np.eye(30, 3) > 0.5, np.nan, X), 2)


def _methods(cls):
    source = textwrap.dedent(inspect.getsource(cls))
    tree = ast.parse(source).body[0]
    return [node for node in tree.body if isinstance(node, ast.FunctionDef)]


def test_fit_is_a_short_orchestration():
    """fit under 40 lines, no method over 60 (issue 15)."""
    lengths = {m.name: m.end_lineno - m.lineno + 1 for m in _methods(GPCAClustering)}
    assert lengths["fit"] < 40
    assert max(lengths.values()) <= 60, lengths


def test_fitted_attributes_are_set_in_fit_only():
    for method in _methods(GPCAClustering):
        assigned = {
            target.attr
            for node in ast.walk(method)
            if isinstance(node, ast.Assign | ast.AugAssign)
            for target in getattr(node, "targets", [getattr(node, "target", None)])
            if isinstance(target, ast.Attribute)
            and isinstance(target.value, ast.Name)
            and target.value.id == "self"
        }
        if method.name not in ("__init__", "fit"):
            assert not assigned, (method.name, assigned)


# Reliability: no silent wrong answer (issue 13).


@pytest.mark.parametrize("normalize", [False, True])
@pytest.mark.parametrize("scale", [1e-300, 1e-150, 1e150, 1e300])
def test_labels_do_not_depend_on_a_global_scale(normalize, scale):
    rng = np.random.RandomState(0)
    X, _ = sample_subspaces(random_bases([4, 4, 4], 5, rng), 60, rng)
    reference = GPCAClustering(3, normalize=normalize, random_state=0).fit(X)
    scaled = GPCAClustering(3, normalize=normalize, random_state=0).fit(scale * X)
    # equal up to the names of the groups (scaling by 1e150 rounds the last bit)
    assert_same_segmentation(scaled.labels_, reference.labels_)
    assert_allclose(scaled.point_normals_, reference.point_normals_, atol=1e-8)
    assert_same_segmentation(scaled.predict(scale * X), reference.predict(X))


@pytest.mark.parametrize(
    "name", ["n_clusters", "max_clusters", "n_neighbors", "affinity_power", "n_init"]
)
def test_boolean_counts_are_rejected(name):
    X = np.random.RandomState(0).randn(30, 3)
    with pytest.raises(ValueError, match=f"'{name}' parameter .* Got True"):
        GPCAClustering(**{name: True}).fit(X)


def test_close_hyperplanes_get_one_cluster_each():
    """Three exact hyperplanes of R^5, two of them with normals 32 degrees
    apart: spectral clustering leaves a small third cluster, which the
    refinement used to empty (sizes 67, 113, 0) and now refills."""
    rs = np.random.RandomState(0)
    X = np.vstack(
        [
            rs.standard_normal((60, 4)) @ np.linalg.qr(rs.standard_normal((5, 4)))[0].T
            for _ in range(3)
        ]
    )
    model = GPCAClustering(3, random_state=0).fit(X)
    assert_array_equal(np.bincount(model.labels_, minlength=3), [60, 60, 60])
    assert misclassification_rate(np.repeat([0, 1, 2], 60), model.labels_) == 0
    assert np.all(np.isfinite(model.candidate_ncuts_))


@pytest.mark.parametrize("seed", range(6))
def test_more_clusters_than_motions_fills_every_cluster(seed):
    X, _ = make_motions(2, n_points=80, random_state=seed)
    Z = PowerFactorization(random_state=0).fit_transform(X)
    labels = GPCAClustering(4, random_state=0).fit(Z).labels_
    assert np.all(np.bincount(labels, minlength=4) > 0)


def test_empty_clusters_are_announced_with_the_reason():
    unit = np.eye(3)[[0, 0, 1, 1, 2]].astype(float)
    with pytest.warns(UserWarning, match=r"1 of the n_clusters=4 .* only 3 distinct"):
        _warn_empty_clusters(np.array([0, 0, 1, 1, 2]), 4, unit)
    unit = np.random.RandomState(0).randn(8, 3)
    with pytest.warns(UserWarning, match=r"2 of the n_clusters=4 .*n_clusters=2"):
        _warn_empty_clusters(np.repeat([0, 3], 4), 4, unit)


@pytest.mark.parametrize("copies", [11, "mixed"])
def test_copies_of_a_point_do_not_change_the_segmentation(three_hyperplanes, copies):
    """A point repeated (a tracker re-detecting a feature), scaled or flipped
    lies on the same line: the fit uses the line once and labels every copy."""
    _, X, _, _, _, model = three_hyperplanes
    rng = np.random.RandomState(0)
    counts = np.full(len(X), 11) if copies == 11 else rng.randint(1, 20, len(X))
    owner = np.repeat(np.arange(len(X)), counts)
    factors = (
        np.ones(len(owner))
        if copies == 11
        else rng.choice([-3.0, 1.0, 2.0], len(owner))
    )
    factors[np.r_[0, np.cumsum(counts)[:-1]]] = 1.0  # first copy as in X
    repeated = GPCAClustering(3, random_state=0).fit(X[owner] * factors[:, None])
    assert_array_equal(repeated.labels_, model.labels_[owner])
    assert_allclose(np.abs(repeated.normals_), np.abs(model.normals_))
    assert repeated.n_spectral_samples_ == len(X)


def test_too_few_distinct_lines():
    X = np.repeat(np.random.RandomState(0).randn(20, 5), 10, axis=0)
    with pytest.raises(ValueError, match=r"n_samples=200 \(180 on the line of an"):
        GPCAClustering(n_clusters=3).fit(X)


@pytest.mark.parametrize("max_spectral_samples", [5000, 120])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_predict_on_the_training_points_gives_labels(seed, max_spectral_samples):
    """predict applies the refinement's smoothed rule with the fit's
    neighbourhoods, so on the training points it reproduces labels_."""
    X, _ = make_motions(3, n_points=[100] * 3, n_frames=10, random_state=seed)
    pipe = make_pipeline(
        PowerFactorization(random_state=0),
        GPCAClustering(3, max_spectral_samples=max_spectral_samples, random_state=0),
    ).fit(X)
    assert np.mean(pipe.predict(X) == pipe[-1].labels_) >= 0.99


def test_predict_without_refinement_is_the_nearest_subspace(three_hyperplanes):
    _, X, _, _, _, _ = three_hyperplanes
    model = GPCAClustering(3, random_state=0, **PAPER).fit(X)
    assert model.reference_points_.shape == (0, 5)
    unit = X / np.linalg.norm(X, axis=1, keepdims=True)
    sines = [1 - np.sum((unit @ B) ** 2, axis=1) for B in model.subspace_bases_]
    assert_array_equal(model.predict(X), np.argmin(sines, axis=0))
