"""Tests for the vanishing polynomials of section 2.2.4 (several polynomials)."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
from numpy.testing import assert_allclose

from sklearn_gpca._gpca import GPCAClustering
from sklearn_gpca._polynomials import (
    embedded_spectrum,
    null_space_dimension,
    polynomial_normal_bases,
)
from sklearn_gpca._veronese import veronese_map
from sklearn_gpca.metrics import misclassification_rate

NOISE = 1e-3


def union_of_subspaces(dims, n_per_subspace, seed, noise=NOISE):
    rng = np.random.RandomState(seed)
    bases = [np.linalg.qr(rng.randn(5, d))[0] for d in dims]
    X = np.vstack([rng.randn(n_per_subspace, B.shape[1]) @ B.T for B in bases])
    X += noise * rng.randn(*X.shape)
    X /= np.linalg.norm(X, axis=1, keepdims=True)
    return X, np.repeat(np.arange(len(dims)), n_per_subspace), bases


def test_spectrum_matches_svd_of_embedding():
    X, _, _ = union_of_subspaces([2, 3], 40, 0)
    values, vectors = embedded_spectrum(X, 2)
    expected = np.linalg.svd(veronese_map(X, 2), compute_uv=False)[::-1]
    assert_allclose(values, expected, rtol=1e-6, atol=1e-10)
    assert_allclose(vectors.T @ vectors, np.eye(15), atol=1e-10)


# Dimension of the degree-n part of the vanishing ideal of generic subspaces
# of R^5: hyperplanes 1; two planes: products l1 l2 with l_k vanishing on
# plane k, 3 x 3 = 9; a plane and a 3-D subspace: 3 x 2 = 6; two 3-D: 2 x 2 = 4.
@pytest.mark.parametrize(
    "dims, degree, expected",
    [((4, 4), 2, 1), ((4, 4, 4), 3, 1), ((2, 2), 2, 9), ((2, 3), 2, 6), ((3, 3), 2, 4)],
)
def test_null_space_dimension_of_generic_subspaces(dims, degree, expected):
    X, _, _ = union_of_subspaces(dims, 100, 0)
    values, _ = embedded_spectrum(X, degree)
    assert null_space_dimension(values) == expected


def test_null_space_dimension_edge_cases():
    assert null_space_dimension(np.array([1.0])) == 1
    # exact zeros are floored, not log(0)
    assert null_space_dimension(np.array([0.0, 0.0, 1.0, 2.0])) == 2


def test_normal_bases_span_the_orthogonal_complement():
    X, y, bases = union_of_subspaces([2, 3], 60, 1, noise=0.0)
    values, vectors = embedded_spectrum(X, 2)
    m = null_space_dimension(values)
    normal_bases, codims = polynomial_normal_bases(X, vectors[:, :m], 2, 0.05)
    assert normal_bases.shape == (120, 5, 5)
    assert np.all(codims[y == 0] == 3)
    assert np.all(codims[y == 1] == 2)
    for i in [0, 70]:
        N = normal_bases[i][:, : codims[i]]
        # orthonormal and orthogonal to the point's own subspace
        assert_allclose(N.T @ N, np.eye(codims[i]), atol=1e-8)
        assert_allclose(bases[y[i]].T @ N, 0.0, atol=1e-6)
        assert_allclose(normal_bases[i][:, codims[i] :], 0.0)


@pytest.mark.parametrize("dims", [(2, 2), (3, 3), (2, 2, 4), (2, 2, 2)])
def test_all_polynomials_normals_segment_low_dimensional_subspaces(dims):
    # the paper's single polynomial fails on these (test_gpca); the null space
    # of several polynomials does, even on the dense kernel without refinement
    X, y, _ = union_of_subspaces(dims, 150, 0, noise=0.01)
    model = GPCAClustering(
        len(dims),
        point_normals="all_polynomials",
        affinity="all_pairs",
        affinity_power=1,
        refine=False,
        random_state=0,
    ).fit(X)
    assert misclassification_rate(y, model.labels_) <= 0.02
    assert model.n_polynomials_ > 1
    assert model.polynomials_.shape[0] == model.n_polynomials_
    assert_allclose(model.polynomials_[0], model.coef_)


def test_hyperplanes_have_one_polynomial():
    X, y, _ = union_of_subspaces([4, 4, 4], 100, 2)
    model = GPCAClustering(3, point_normals="all_polynomials", random_state=0).fit(X)
    assert model.n_polynomials_ == 1
    assert misclassification_rate(y, model.labels_) <= 0.02
