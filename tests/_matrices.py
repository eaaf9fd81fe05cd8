"""Matrices shared by the factorisation tests."""

import numpy as np


def low_rank(n_samples=300, n_features=30, rank=5, seed=0):
    """An exactly rank-``rank`` Gaussian matrix."""
    rng = np.random.RandomState(seed)
    return rng.standard_normal((n_samples, rank)) @ rng.standard_normal(
        (rank, n_features)
    )


def remove(X, fraction, seed=0):
    """A copy of ``X`` with a random ``fraction`` of its entries NaN."""
    X = X.copy()
    X[np.random.RandomState(seed).rand(*X.shape) < fraction] = np.nan
    return X
