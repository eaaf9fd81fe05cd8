"""Tests of the batched normal equations (``_least_squares.py``)."""

import numpy as np
import pytest

from sklearn_gpca._least_squares import (
    _cholesky_inverses,
    damp,
    inverse_row_grams,
    row_grams,
)


def test_row_grams_are_the_masked_products():
    rng = np.random.RandomState(0)
    mask = (rng.rand(30, 8) > 0.3).astype(float)
    basis = rng.randn(5, 8)
    # derived truth: basis diag(mask_i) basis^T, row by row
    expected = np.einsum("kj,ij,lj->ikl", basis, mask, basis)
    np.testing.assert_allclose(row_grams(mask, basis), expected, atol=1e-12)


@pytest.mark.parametrize("r", [1, 3, 5])
def test_inverse_row_grams_invert_the_damped_grams(r):
    rng = np.random.RandomState(r)
    mask = (rng.rand(200, 10) > 0.4).astype(float)
    # some rows observe fewer coordinates than r: only the ridge makes them
    # invertible
    mask[:5] = 0.0
    mask[:5, 0] = 1.0
    basis = rng.randn(r, 10)
    inverses = inverse_row_grams(mask, basis)
    grams = damp(row_grams(mask, basis))
    reference = np.linalg.inv(grams)
    assert np.all(np.isfinite(inverses))
    # derived truth on the well-posed rows: the inverse
    posed = np.linalg.cond(grams) < 1e6
    assert posed.sum() > 100 and (r == 1 or not posed[:5].any())
    np.testing.assert_allclose(inverses[posed], reference[posed], rtol=1e-8, atol=1e-10)
    # on all rows, also those the ridge regularises: the same least-squares fit
    X = rng.randn(200, 10) * mask
    rhs = X @ basis.T
    for inv in (inverses, reference):
        fits = np.einsum("pij,pj->pi", inv, rhs) @ basis
        residual = np.sum(((X - fits) * mask) ** 2, axis=1)
        if inv is inverses:
            ours = residual
    # (exact fits of the deficient rows: round-off of the data's scale, ~1)
    np.testing.assert_allclose(ours, residual, rtol=1e-6, atol=1e-6)


def test_cholesky_inverses_fall_back_where_not_positive_definite():
    rng = np.random.RandomState(0)
    a = rng.randn(4, 3, 3)
    gram = a @ a.transpose(0, 2, 1) + np.eye(3)
    gram[1] = np.diag([1.0, -2.0, 3.0])  # symmetric, indefinite: no Cholesky
    inverses = _cholesky_inverses(gram)
    np.testing.assert_allclose(
        inverses @ gram, np.broadcast_to(np.eye(3), gram.shape), atol=1e-10
    )


def test_fit_rows_are_the_least_squares_fits_on_observed_entries():
    from sklearn_gpca._least_squares import fit_rows

    rng = np.random.RandomState(0)
    mask = rng.rand(40, 12) > 0.2
    basis = rng.randn(5, 12)
    X0 = rng.randn(40, 12) * mask
    Z = fit_rows(X0, mask.astype(float), basis)
    # derived truth: each row's least squares on its own observed columns
    for i in range(40):
        seen = mask[i]
        expected = np.linalg.lstsq(basis[:, seen].T, X0[i, seen], rcond=None)[0]
        np.testing.assert_allclose(Z[i], expected, rtol=1e-8, atol=1e-10)


def test_cholesky_solve_falls_back_where_not_positive_definite():
    from sklearn_gpca._least_squares import _cholesky_solve

    rng = np.random.RandomState(1)
    a = rng.randn(6, 4, 4)
    gram = a @ a.transpose(0, 2, 1) + np.eye(4)
    gram[2] = np.diag([2.0, 1.0, -1.0, 3.0])
    rhs = rng.randn(6, 4)
    z = _cholesky_solve(gram, rhs)
    np.testing.assert_allclose(np.einsum("pij,pj->pi", gram, z), rhs, atol=1e-10)
