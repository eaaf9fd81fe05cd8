"""Tests for the Veronese embedding and polynomial gradients."""

# SPDX-License-Identifier: BSD-3-Clause

from math import comb

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from sklearn_gpca._veronese import (
    n_monomials,
    polynomial_gradients,
    veronese_exponents,
    veronese_map,
)


def veronese_jacobian(X, degree):
    """Brute-force Jacobian ``d nu_n(x)_m / d x_k = e_mk x^(e_m - u_k)``."""
    exponents = veronese_exponents(X.shape[1], degree)
    jacobian = np.zeros((X.shape[0], exponents.shape[0], X.shape[1]))
    for k in range(X.shape[1]):
        lowered = exponents.copy()
        lowered[:, k] -= 1
        has_k = exponents[:, k] > 0
        powers = np.prod(X[:, None, :] ** np.maximum(lowered, 0), axis=2)
        jacobian[:, :, k] = exponents[:, k] * powers * has_k
    return jacobian


@pytest.mark.parametrize("n_features", [1, 2, 3, 5])
@pytest.mark.parametrize("degree", [0, 1, 2, 3, 4])
def test_monomial_count_and_exponents(n_features, degree):
    exponents = veronese_exponents(n_features, degree)
    expected = comb(degree + n_features - 1, degree)
    assert exponents.shape == (expected, n_features)
    assert n_monomials(n_features, degree) == expected
    assert_array_equal(exponents.sum(axis=1), degree)
    # every monomial appears exactly once
    assert len({tuple(row) for row in exponents}) == expected


@pytest.mark.parametrize("n_features", [2, 3, 5])
@pytest.mark.parametrize("degree", [1, 2, 3])
def test_veronese_map_matches_brute_force(n_features, degree):
    rng = np.random.RandomState(0)
    X = rng.randn(7, n_features)
    exponents = veronese_exponents(n_features, degree)
    brute = np.array([[np.prod(x**e) for e in exponents] for x in X])
    assert_allclose(veronese_map(X, degree), brute, rtol=1e-12, atol=1e-12)


def test_degree_one_is_identity():
    X = np.random.RandomState(1).randn(4, 3)
    assert_allclose(veronese_map(X, 1), X)


@pytest.mark.parametrize("n_features", [2, 3, 5])
@pytest.mark.parametrize("degree", [1, 2, 3, 4])
def test_gradients_match_finite_differences(n_features, degree):
    rng = np.random.RandomState(2)
    X = rng.randn(6, n_features)
    coef = rng.randn(n_monomials(n_features, degree))
    step = 1e-6
    finite = np.stack(
        [
            (
                veronese_map(X + step * unit, degree) @ coef
                - veronese_map(X - step * unit, degree) @ coef
            )
            / (2 * step)
            for unit in np.eye(n_features)
        ],
        axis=1,
    )
    # central differences have O(step^2) truncation and O(eps/step) rounding error
    assert_allclose(polynomial_gradients(X, coef, degree), finite, atol=1e-6)


@pytest.mark.parametrize("degree", [1, 2, 3, 4])
def test_euler_identity(degree):
    # for a homogeneous p of degree n: x . grad p(x) = n p(x)
    rng = np.random.RandomState(3)
    X = rng.randn(10, 4)
    coef = rng.randn(n_monomials(4, degree))
    gradients = polynomial_gradients(X, coef, degree)
    assert_allclose(
        np.sum(X * gradients, axis=1), degree * veronese_map(X, degree) @ coef
    )


def test_several_polynomials_and_jacobian_agree():
    rng = np.random.RandomState(4)
    X = rng.randn(8, 3)
    coef = rng.randn(n_monomials(3, 3), 2)
    gradients = polynomial_gradients(X, coef, 3)
    assert gradients.shape == (8, 2, 3)
    for column in range(2):
        assert_allclose(
            gradients[:, column], polynomial_gradients(X, coef[:, column], 3)
        )
    jacobian = veronese_jacobian(X, 3)
    assert jacobian.shape == (8, 10, 3)
    assert_allclose(np.einsum("pmk,ml->plk", jacobian, coef), gradients)


def test_gradient_of_product_of_linear_forms_is_normal():
    # p(x) = (b1 . x)(b2 . x) has grad p(x) = (b2 . x) b1 on the plane b1 . x = 0
    b1, b2 = np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 1.0])
    exponents = veronese_exponents(3, 2)
    # coefficients of the product: c_e = sum over ordered pairs giving e
    coef = np.array(
        [
            sum(
                b1[i] * b2[j]
                for i in range(3)
                for j in range(3)
                if np.array_equal(np.bincount([i, j], minlength=3), e)
            )
            for e in exponents
        ]
    )
    x = np.array([[0.0, 2.0, -1.0]])
    assert_allclose(polynomial_gradients(x, coef, 2), (b2 @ x[0]) * b1[None])


def test_derivative_needs_positive_degree():
    with pytest.raises(ValueError, match="degree >= 1, got degree=0"):
        polynomial_gradients(np.ones((2, 2)), np.ones(1), 0)
