"""Tests for the observed-entry subspace primitives."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose

from sklearn_gpca._observed_subspaces import (
    comoment_matrix,
    fit_observed_subspace,
    observed_entries,
    row_fits,
    subspace_residuals,
)


def _low_rank(n_samples, n_features, rank, seed):
    rng = np.random.RandomState(seed)
    basis, _ = np.linalg.qr(rng.standard_normal((n_features, rank)))
    return rng.standard_normal((n_samples, rank)) @ basis.T, basis


def _principal_sines(U, V):
    cosines = np.linalg.svd(U.T @ V, compute_uv=False)
    return np.sqrt(np.maximum(1 - cosines**2, 0))


def test_observed_entries():
    X = np.array([[1.0, np.nan], [np.nan, 2.0]])
    X0, mask = observed_entries(X)
    assert_allclose(X0, [[1.0, 0.0], [0.0, 2.0]])
    assert mask.tolist() == [[True, False], [False, True]]


def test_row_fits_match_lstsq_per_row():
    rng = np.random.RandomState(0)
    X = rng.standard_normal((30, 12))
    mask = rng.rand(30, 12) > 0.3
    basis = rng.standard_normal((12, 3))
    coefs, residuals, counts = row_fits(np.where(mask, X, 0), mask, basis)
    for p in range(30):
        observed = mask[p]
        z, *_ = np.linalg.lstsq(basis[observed], X[p, observed], rcond=None)
        r = X[p, observed] - basis[observed] @ z
        assert_allclose(coefs[p], z, rtol=1e-6, atol=1e-8)
        assert_allclose(residuals[p], r @ r, rtol=1e-6, atol=1e-9)
        assert counts[p] == observed.sum()


def test_support_drops_coordinates():
    rng = np.random.RandomState(1)
    X = rng.standard_normal((5, 6))
    mask = np.ones((5, 6), dtype=bool)
    basis = rng.standard_normal((6, 2))
    support = np.array([True, True, True, True, False, False])
    _, restricted, counts = row_fits(X, mask, basis, support)
    _, direct, _ = row_fits(X[:, :4], mask[:, :4], basis[:4])
    assert_allclose(restricted, direct)
    assert np.all(counts == 4)


def test_residuals_and_dofs():
    X, basis = _low_rank(40, 10, 3, seed=2)
    rng = np.random.RandomState(2)
    mask = rng.rand(*X.shape) > 0.4
    mask[0] = False
    mask[0, :2] = True  # 2 coordinates <= d: no evidence
    other, _ = np.linalg.qr(rng.standard_normal((10, 3)))
    residuals, dofs = subspace_residuals(np.where(mask, X, 0), mask, [basis, other])
    assert_allclose(residuals[:, 0], 0.0, atol=1e-8)
    assert np.all(residuals[dofs[:, 1] > 0, 1] > 1e-6)
    assert_allclose(dofs[:, 0], np.maximum(mask.sum(1) - 3, 0))
    assert dofs[0, 0] == 0 and dofs[0, 1] == 0


@pytest.mark.parametrize("missing", [0.0, 0.3, 0.6])
def test_fit_recovers_subspace(missing):
    X, basis = _low_rank(200, 20, 4, seed=3)
    rng = np.random.RandomState(3)
    mask = rng.rand(*X.shape) >= missing
    X = X + 1e-6 * rng.standard_normal(X.shape)
    fitted, support = fit_observed_subspace(np.where(mask, X, 0), mask, 4)
    assert support.all()
    assert_allclose(fitted.T @ fitted, np.eye(4), atol=1e-10)
    assert _principal_sines(fitted, basis).max() < 1e-4


def test_fit_with_weights_ignores_zero_weight_rows():
    X, basis = _low_rank(60, 12, 2, seed=4)
    rng = np.random.RandomState(4)
    junk = rng.standard_normal((30, 12)) * 10
    data = np.vstack([X, junk])
    weights = np.r_[np.ones(60), np.zeros(30)]
    mask = rng.rand(*data.shape) > 0.2
    fitted, _ = fit_observed_subspace(np.where(mask, data, 0), mask, 2, weights=weights)
    assert _principal_sines(fitted, basis).max() < 1e-6


def test_fit_support_excludes_unseen_coordinates():
    X, _ = _low_rank(50, 8, 2, seed=5)
    mask = np.ones_like(X, dtype=bool)
    mask[:, 6:] = False
    mask[0, 6] = True  # seen by 1 < d rows
    fitted, support = fit_observed_subspace(np.where(mask, X, 0), mask, 2)
    assert support.tolist() == [True] * 6 + [False, False]
    assert_allclose(fitted[~support], 0.0)


def test_comoment_matrix_ignores_missing_entries():
    X = np.array([[1.0, 2.0], [3.0, np.nan]])
    X0, mask = observed_entries(X)
    moments, pairs = comoment_matrix(X0, mask)
    assert_allclose(pairs, [[2, 1], [1, 1]])
    assert_allclose(moments, [[5.0, 2.0], [2.0, 4.0]])


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 2**16), scale=st.floats(1e-3, 1e3))
def test_residuals_scale_quadratically_and_follow_row_order(seed, scale):
    rng = np.random.RandomState(seed)
    X = rng.standard_normal((15, 8))
    mask = rng.rand(15, 8) > 0.3
    basis, _ = np.linalg.qr(rng.standard_normal((8, 2)))
    X0 = np.where(mask, X, 0)
    residuals, dofs = subspace_residuals(X0, mask, [basis])
    scaled, _ = subspace_residuals(scale * X0, mask, [basis])
    assert_allclose(scaled, scale**2 * residuals, rtol=1e-6, atol=1e-12 * scale**2)
    order = rng.permutation(15)
    permuted, permuted_dofs = subspace_residuals(X0[order], mask[order], [basis])
    assert_allclose(permuted, residuals[order], rtol=1e-9, atol=1e-12)
    assert np.array_equal(permuted_dofs, dofs[order])


def test_fit_with_fewer_supported_coordinates_than_dimensions():
    # a cluster whose tracks share 3 coordinates, one entry missing: the
    # support is smaller than the asked dimension; the fit spans the support
    # (exact fit of every row) instead of failing in numpy
    rng = np.random.default_rng(0)
    X = rng.normal(size=(6, 10))
    mask = np.zeros((6, 10), dtype=bool)
    mask[:, :3] = True
    mask[0, 0] = False
    basis, support = fit_observed_subspace(np.where(mask, X, 0), mask, 4)
    assert support.sum() == 3
    assert basis.shape == (10, 4)
    gram = basis.T @ basis
    np.testing.assert_allclose(np.diag(gram), [1, 1, 1, 0], atol=1e-10)
    _, residuals, _ = row_fits(np.where(mask, X, 0), mask, basis, support)
    np.testing.assert_allclose(residuals, 0, atol=1e-10)


def _own_residual(X0, mask, fit):
    basis, support = fit
    return subspace_residuals(X0, mask, [basis], [support])[0].sum()


def test_polish_reaches_the_optimum_the_alternations_creep_towards():
    # the background of a driving draw: 62 % missing, perspective bends it
    # out of 4 dimensions; alternating least squares creeps for thousands of
    # iterations where variable projection converges
    from sklearn_gpca.datasets import make_tracks

    X, y = make_tracks(scene="driving", random_state=0)[:2]
    X0, mask = observed_entries(X[y == 0])
    alternations = _own_residual(
        X0, mask, fit_observed_subspace(X0, mask, 4, max_iter=3000)
    )
    fit = fit_observed_subspace(X0, mask, 4, polish=True)
    polished = _own_residual(X0, mask, fit)
    assert polished < alternations / 2
    again = fit_observed_subspace(X0, mask, 4, init=fit[0], polish=True)
    assert _own_residual(X0, mask, again) == pytest.approx(polished, rel=1e-4)


def test_polish_weighs_rows_as_repeats():
    X, _ = _low_rank(60, 16, 3, seed=5)
    rng = np.random.RandomState(6)
    X = X + 0.05 * rng.standard_normal(X.shape)
    X[rng.rand(*X.shape) < 0.4] = np.nan
    X0, mask = observed_entries(X)
    weights = np.where(np.arange(60) < 20, 2.0, 1.0)
    repeated = np.r_[np.arange(60), np.arange(20)]
    weighted = fit_observed_subspace(X0, mask, 3, weights=weights, polish=True)[0]
    repeats = fit_observed_subspace(X0[repeated], mask[repeated], 3, polish=True)[0]
    assert _principal_sines(weighted, repeats).max() < 1e-4
