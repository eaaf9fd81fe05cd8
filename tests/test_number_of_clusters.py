"""Tests for n_clusters="auto" and the coding length that drives it."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
from numpy.testing import assert_array_equal
from sklearn.pipeline import make_pipeline

from sklearn_gpca import GPCAClustering, PowerFactorization
from sklearn_gpca._coding_length import coding_length
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


@pytest.mark.parametrize("n_motions", [1, 2, 3])
@pytest.mark.parametrize("seed", [0, 1])
def test_auto_finds_number_of_motions(n_motions, seed):
    X, y = make_motions(
        n_motions, n_points=100 * n_motions, missing=0.2, random_state=seed
    )
    pipe = make_pipeline(
        PowerFactorization(random_state=0),
        GPCAClustering("auto", random_state=0),
    ).fit(X)
    model = pipe[-1]
    assert model.n_clusters_ == n_motions
    assert model.coding_lengths_.shape == (5,)
    assert np.argmin(model.coding_lengths_) == n_motions - 1
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
    model = GPCAClustering("auto", max_clusters=5, random_state=0).fit(X)
    assert np.all(np.isfinite(model.coding_lengths_[:3]))
    assert np.all(np.isinf(model.coding_lengths_[3:]))
    assert 1 <= model.n_clusters_ <= 3


def test_auto_with_too_few_points_for_one_subspace():
    with pytest.raises(ValueError, match="n_samples=3 is too few"):
        GPCAClustering("auto").fit(np.random.RandomState(0).randn(3, 5))


def test_auto_respects_max_clusters():
    X, _ = make_motions(3, n_points=300, random_state=0)
    Z = PowerFactorization(random_state=0).fit_transform(X)
    model = GPCAClustering("auto", max_clusters=2, random_state=0).fit(Z)
    assert model.coding_lengths_.shape == (2,)
    assert model.n_clusters_ <= 2


def test_fixed_n_clusters_sets_n_clusters_():
    X, _ = make_motions(2, n_points=100, random_state=0)
    Z = PowerFactorization(random_state=0).fit_transform(X)
    model = GPCAClustering(2, random_state=0).fit(Z)
    assert model.n_clusters_ == 2
    assert not hasattr(model, "coding_lengths_")


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
