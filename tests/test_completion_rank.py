"""Every route of ``PowerFactorization(completion_rank=...)``, through the
public API: None, an int and "auto", on complete and incomplete data."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
from numpy.testing import assert_allclose

from sklearn_gpca import PowerFactorization


def low_rank(n_samples, n_features, rank, seed=0):
    """Rank ``rank`` with singular values falling by 30 % one to the next, so
    that every leading subspace is well separated from the next direction."""
    rng = np.random.RandomState(seed)
    U = np.linalg.qr(rng.standard_normal((n_samples, rank)))[0]
    V = np.linalg.qr(rng.standard_normal((n_features, rank)))[0]
    return (U * 100 * 0.7 ** np.arange(rank)) @ V.T


def remove_pairs(X, fraction, seed=0):
    """``X`` with a random ``fraction`` of its (x, y) pairs missing."""
    rng = np.random.RandomState(seed)
    pairs = rng.rand(X.shape[0], X.shape[1] // 2) < fraction
    X = X.copy()
    X[np.repeat(pairs, 2, axis=1)] = np.nan
    return X


def top_subspace(X, n_components):
    return np.linalg.svd(X, full_matrices=False)[2][:n_components]


def largest_angle(A, B):
    """Sine of the largest principal angle between row spaces ``A`` and ``B``."""
    cosines = np.linalg.svd(A @ B.T, compute_uv=False)
    return float(np.sqrt(max(0.0, 1.0 - cosines.min() ** 2)))


@pytest.fixture(scope="module")
def rank8():
    """300 x 30 of rank 8 (two rigid motions span 8), a fifth of pairs missing."""
    X_complete = low_rank(300, 30, 8)
    return X_complete, remove_pairs(X_complete, 0.2)


@pytest.mark.parametrize("completion_rank", [None, "auto", 8])
def test_complete_data_projection_is_exact_at_any_rank(rank8, completion_rank):
    X_complete, _ = rank8
    pf = PowerFactorization(5, completion_rank=completion_rank, random_state=0)
    pf.fit(X_complete)
    expected_rank = 8 if completion_rank == 8 else 5
    assert pf.completion_rank_ == expected_rank
    assert pf.completion_components_.shape == (expected_rank, 30)
    assert pf.completion_errors_ == {}
    # the power method stops at tol=1e-7 on the residual: angles of ~1e-5
    assert largest_angle(pf.components_, top_subspace(X_complete, 5)) < 1e-4


def test_none_fits_at_n_components(rank8):
    X_complete, X = rank8
    pf = PowerFactorization(5, completion_rank=None, random_state=0).fit(X)
    assert pf.completion_rank_ == 5
    assert pf.completion_errors_ == {}
    assert_allclose(pf.components_, pf.completion_components_)
    # A rank-5 fit of rank-8 data with gaps is not the complete data's
    # leading subspace: the reason completion_rank exists.
    assert largest_angle(pf.components_, top_subspace(X_complete, 5)) > 1e-2


def test_int_completes_at_that_rank_then_projects(rank8):
    X_complete, X = rank8
    pf = PowerFactorization(5, completion_rank=8, whiten=False, random_state=0)
    pf.fit(X)
    assert pf.completion_rank_ == 8
    assert pf.completion_errors_ == {}
    assert pf.completion_components_.shape == (8, 30)
    assert_allclose(pf.components_, pf.completion_components_[:5])
    # Completed at the true rank, the data are recovered exactly, and so is
    # their leading 5-dimensional subspace.
    assert largest_angle(pf.completion_components_, top_subspace(X_complete, 8)) < 1e-5
    assert largest_angle(pf.components_, top_subspace(X_complete, 5)) < 1e-5
    assert_allclose(
        pf.transform(X), X_complete @ pf.components_.T, atol=1e-6 * np.nanmax(np.abs(X))
    )


def test_int_below_n_components_is_n_components(rank8):
    _, X = rank8
    pf = PowerFactorization(5, completion_rank=3, random_state=0).fit(X)
    assert pf.completion_rank_ == 5


def test_auto_finds_the_rank_of_the_data(rank8):
    X_complete, X = rank8
    pf = PowerFactorization(5, completion_rank="auto", random_state=0).fit(X)
    assert pf.completion_rank_ == 8
    errors = pf.completion_errors_
    assert list(errors)[:4] == [5, 6, 7, 8]
    assert all(isinstance(e, float) and e >= 0 for e in errors.values())
    # Held-out error: large below the true rank, about zero at it.
    assert min(errors[5], errors[6], errors[7]) > 1e3 * errors[8]
    assert largest_angle(pf.components_, top_subspace(X_complete, 5)) < 1e-4


@pytest.mark.parametrize("true_rank", [5, 6, 11])
def test_auto_on_other_ranks(true_rank):
    X_complete = low_rank(300, 30, true_rank, seed=true_rank)
    X = remove_pairs(X_complete, 0.15, seed=1)
    pf = PowerFactorization(5, completion_rank="auto", random_state=0).fit(X)
    assert pf.completion_rank_ == true_rank
    assert min(pf.completion_errors_) == 5


def test_auto_stays_at_n_components_when_rows_are_too_few_to_hold_out():
    X = remove_pairs(low_rank(12, 30, 8), 0.2)
    pf = PowerFactorization(5, completion_rank="auto", random_state=0).fit(X)
    assert pf.completion_rank_ == 5
    assert pf.completion_errors_ == {}


def test_auto_searches_up_to_three_times_n_components():
    X_complete = low_rank(200, 20, 8)
    X = remove_pairs(X_complete, 0.1)
    pf = PowerFactorization(2, completion_rank="auto", random_state=0).fit(X)
    # the true rank 8 is beyond 3 * 2 = 6: the search stops there
    assert max(pf.completion_errors_) == 6
    assert pf.completion_rank_ == 6
