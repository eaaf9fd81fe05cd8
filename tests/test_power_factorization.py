import pickle

import numpy as np
import pytest
from _matrices import low_rank, remove
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose, assert_array_equal
from scipy.linalg import subspace_angles
from sklearn.exceptions import ConvergenceWarning

from sklearn_gpca import PowerFactorization, power_factorization


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("rank", [3, 5])
def test_exact_recovery_of_missing_entries(seed, rank):
    X = low_rank(rank=rank, seed=seed)
    X_missing = remove(X, 0.3, seed=seed)
    pf = PowerFactorization(rank, random_state=seed).fit(X_missing)
    X_completed = pf.inverse_transform(pf.transform(X_missing))
    assert np.linalg.norm(X_completed - X) / np.linalg.norm(X) < 1e-6
    assert pf.reconstruction_err_ < 1e-6


def test_complete_data_matches_truncated_svd():
    rng = np.random.RandomState(0)
    X = low_rank() + 0.05 * rng.standard_normal((300, 30))
    pf = PowerFactorization(5, random_state=0).fit(X)
    _, s, vt = np.linalg.svd(X, full_matrices=False)
    assert subspace_angles(pf.components_.T, vt[:5].T).max() < 1e-6
    assert_allclose(pf.singular_values_, s[:5], rtol=1e-6)
    expected_rms = np.sqrt(np.sum(s[5:] ** 2) / X.size)
    assert_allclose(pf.reconstruction_err_, expected_rms, rtol=1e-6)


def test_whitened_coordinates_are_the_paper_v():
    rng = np.random.RandomState(1)
    X = low_rank() + 0.05 * rng.standard_normal((300, 30))
    Z = PowerFactorization(5, random_state=0).fit_transform(X)
    u, _, _ = np.linalg.svd(X, full_matrices=False)
    # the rows of V^T of the paper are the columns of u here, up to sign
    assert_allclose(np.abs(Z), np.abs(u[:, :5]), atol=1e-6)
    assert_allclose(Z.T @ Z, np.eye(5), atol=1e-6)


def test_unwhitened_coordinates_are_projections():
    X = low_rank() + 0.05 * np.random.RandomState(2).standard_normal((300, 30))
    pf = PowerFactorization(5, whiten=False, random_state=0).fit(X)
    assert_allclose(pf.transform(X), X @ pf.components_.T, atol=1e-8)


def test_no_centring():
    # a rank-1 matrix far from the origin stays rank 1: no mean is removed
    X = np.outer(np.arange(1.0, 51.0), np.linspace(1.0, 2.0, 8))
    pf = PowerFactorization(1, random_state=0).fit(X)
    assert pf.reconstruction_err_ < 1e-10


def test_transform_new_incomplete_trajectories():
    X = low_rank(n_samples=400)
    pf = PowerFactorization(5, random_state=0).fit(remove(X[:300], 0.3))
    X_new = remove(X[300:], 0.4, seed=5)
    assert_allclose(pf.inverse_transform(pf.transform(X_new)), X[300:], atol=1e-6)


def test_fit_transform_consistent_with_fit_then_transform():
    X = remove(low_rank() + 0.01, 0.2)
    Z1 = PowerFactorization(5, random_state=3).fit_transform(X)
    Z2 = PowerFactorization(5, random_state=3).fit(X).transform(X)
    assert_allclose(Z1, Z2)


def test_masked_array_is_the_same_as_nan():
    X = low_rank()
    missing = np.random.RandomState(0).rand(*X.shape) < 0.25
    X_nan = np.where(missing, np.nan, X)
    X_masked = np.ma.MaskedArray(X, mask=missing)
    Z_nan = PowerFactorization(5, random_state=0).fit_transform(X_nan)
    Z_masked = PowerFactorization(5, random_state=0).fit_transform(X_masked)
    assert_allclose(Z_nan, Z_masked)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_dtype_preserved(dtype):
    X = remove(low_rank(), 0.2).astype(dtype)
    pf = PowerFactorization(5, random_state=0).fit(X)
    Z = pf.transform(X)
    assert Z.dtype == dtype
    assert pf.components_.dtype == dtype
    assert pf.inverse_transform(Z).dtype == dtype


def test_deterministic_and_pickles():
    X = remove(low_rank(), 0.3)
    pf = PowerFactorization(5, random_state=7).fit(X)
    again = PowerFactorization(5, random_state=7).fit(X)
    assert_array_equal(pf.components_, again.components_)
    restored = pickle.loads(pickle.dumps(pf))
    assert_array_equal(restored.transform(X), pf.transform(X))


def test_feature_names_and_pandas_output():
    pd = pytest.importorskip("pandas")
    X = low_rank(n_features=6)
    pf = PowerFactorization(3, random_state=0).set_output(transform="pandas")
    out = pf.fit_transform(pd.DataFrame(X, columns=[f"f{i}" for i in range(6)]))
    assert list(out.columns) == [
        "powerfactorization0",
        "powerfactorization1",
        "powerfactorization2",
    ]


def test_verbose_prints_prefixed_progress(capsys):
    PowerFactorization(2, verbose=1, random_state=0).fit(low_rank(rank=2))
    assert capsys.readouterr().out.startswith("[PowerFactorization] iteration 1")


def test_max_iter_warns():
    X = remove(low_rank() + np.random.RandomState(0).standard_normal((300, 30)), 0.5)
    with pytest.warns(ConvergenceWarning, match="did not converge in max_iter=2"):
        PowerFactorization(5, max_iter=2, tol=0, random_state=0).fit(X)


def test_too_many_components():
    with pytest.raises(ValueError, match="n_components=7 must be at most n_features=6"):
        PowerFactorization(7).fit(low_rank(n_features=6))
    with pytest.raises(ValueError, match="n_components=5 must be at most n_samples=4"):
        PowerFactorization(5).fit(low_rank(n_samples=4))


def test_infinity_is_rejected():
    X = low_rank()
    X[0, 0] = np.inf
    with pytest.raises(ValueError, match="infinity"):
        PowerFactorization(5).fit(X)


def test_inverse_transform_checks_coordinates():
    pf = PowerFactorization(5, random_state=0).fit(low_rank())
    with pytest.raises(ValueError, match="expects n_components=5 coordinates"):
        pf.inverse_transform(np.zeros((3, 4)))


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**16))
def test_permuting_rows_permutes_the_output(seed):
    X = remove(low_rank(n_samples=60, n_features=12, rank=3), 0.2)
    order = np.random.RandomState(seed).permutation(60)
    pf = PowerFactorization(3, random_state=0)
    Z = pf.fit_transform(X)
    Z_permuted = PowerFactorization(3, random_state=0).fit_transform(X[order])
    assert_allclose(Z_permuted, Z[order], atol=1e-6)


def test_subsampled_starts_polished_on_all_rows():
    """Starts on a subsample, ALS polish on all rows: the full-data optimum."""
    rng = np.random.RandomState(0)
    X = rng.standard_normal((3000, 4)) @ rng.standard_normal((4, 12))
    X += 1e-3 * rng.standard_normal(X.shape)
    X[rng.rand(*X.shape) < 0.2] = np.nan
    full = PowerFactorization(4, max_init_samples=None, random_state=0).fit(X)
    sub = PowerFactorization(4, max_init_samples=300, random_state=0).fit(X)
    assert full.n_polish_iter_ == 0
    assert sub.n_polish_iter_ >= 1
    assert_allclose(sub.reconstruction_err_, full.reconstruction_err_, rtol=1e-4)
    # same subspace
    overlap = np.linalg.svd(sub.components_ @ full.components_.T)[1]
    assert_allclose(overlap, 1.0, atol=1e-6)


def noisy_low_rank(missing, seed=0):
    rng = np.random.RandomState(seed)
    X = low_rank(n_samples=100, n_features=12, rank=3, seed=seed)
    return remove(X + 0.01 * rng.standard_normal(X.shape), missing, seed=seed)


@pytest.mark.parametrize("scale", [1e-200, 1e-155, 1e154, 1e200])
@pytest.mark.parametrize("missing", [0.0, 0.3])
def test_tiny_and_huge_units_give_the_same_fit(scale, missing):
    X = noisy_low_rank(missing)
    pf = PowerFactorization(3, random_state=0).fit(X)
    scaled = PowerFactorization(3, random_state=0).fit(X * scale)
    # whitened coordinates and components do not depend on the units
    assert_allclose(scaled.transform(X * scale), pf.transform(X), atol=1e-8)
    assert_allclose(scaled.components_, pf.components_, atol=1e-8)
    assert_allclose(scaled.singular_values_ / scale, pf.singular_values_, rtol=1e-8)
    assert_allclose(
        scaled.reconstruction_err_ / scale, pf.reconstruction_err_, rtol=1e-6
    )
    completed = scaled.inverse_transform(scaled.transform(X * scale)) / scale
    assert_allclose(completed, pf.inverse_transform(pf.transform(X)), atol=1e-8)
    # plain projections are in the units of X
    plain = PowerFactorization(3, whiten=False, random_state=0)
    reference = PowerFactorization(3, whiten=False, random_state=0).fit_transform(X)
    assert_allclose(plain.fit_transform(X * scale) / scale, reference, atol=1e-8)


@settings(max_examples=20, deadline=None)
@given(exponent=st.integers(-200, 200), missing=st.sampled_from([0.0, 0.25]))
def test_coordinates_are_invariant_to_the_units(exponent, missing):
    X = noisy_low_rank(missing, seed=1)
    reference = PowerFactorization(3, random_state=0).fit_transform(X)
    scale = 10.0**exponent
    Z = PowerFactorization(3, random_state=0).fit_transform(X * scale)
    assert_allclose(Z, reference, atol=1e-8)


@pytest.mark.parametrize(
    "name",
    ["n_components", "completion_rank", "n_init", "max_iter", "max_init_samples"],
)
@pytest.mark.parametrize("fit", ["estimator", "function"])
def test_boolean_counts_are_refused_not_read_as_one(name, fit):
    """``True`` is an int to Python; the ``Count`` constraint of the other
    estimators refuses it with scikit-learn's message."""
    message = f"'{name}' parameter of .* must be an int in the range.*Got True"
    with pytest.raises(ValueError, match=message):
        if fit == "estimator":
            PowerFactorization(**{name: True}).fit(low_rank())
        else:
            power_factorization(low_rank(), **{name: True})


@pytest.mark.parametrize("missing", [0.0, 0.2])
def test_completion_rank_beyond_the_data_is_an_error(missing):
    X = remove(low_rank(n_samples=300, n_features=20), missing)
    with pytest.raises(
        ValueError, match="completion_rank=100 must be at most n_features=20"
    ):
        PowerFactorization(5, completion_rank=100).fit(X)
    with pytest.raises(
        ValueError, match="completion_rank=18 must be at most n_samples=12"
    ):
        PowerFactorization(5, completion_rank=18).fit(X[:12])


def test_completion_rank_beyond_what_the_rows_support_is_lowered_with_a_warning():
    # every row observes 10 consecutive entries (cyclically), every column is
    # observed 60 times or more: no row informs a fit beyond rank 10
    X = low_rank(n_samples=200, n_features=30, rank=5)
    offset = (np.arange(30) - np.arange(200)[:, None] % 30) % 30
    X[offset >= 10] = np.nan
    assert (~np.isnan(X)).sum(axis=0).min() >= 60
    with pytest.warns(UserWarning, match="completion_rank=15 lowered to 10"):
        pf = PowerFactorization(5, completion_rank=15, random_state=0).fit(X)
    assert pf.completion_rank_ == 10
    assert np.all(np.isfinite(pf.components_))
