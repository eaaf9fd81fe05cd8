"""Tests for the numpy repetition of scikit-learn's KMeans."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_array_equal
from sklearn.cluster import KMeans
from sklearn.exceptions import ConvergenceWarning

from sklearn_gpca import _kmeans
from sklearn_gpca._kmeans import kmeans_labels


def blobs(seed, n_samples, n_features, n_clusters, spread=1.0):
    """Points around ``n_clusters`` centres, on the unit sphere as in the
    spectral stage."""
    rng = np.random.RandomState(seed)
    centres = rng.normal(scale=2.0, size=(n_clusters, n_features))
    X = centres[rng.randint(n_clusters, size=n_samples)]
    X = X + rng.normal(scale=spread, size=X.shape)
    return X / np.linalg.norm(X, axis=1, keepdims=True)


def sklearn_labels(X, n_clusters, n_init, random_state):
    kmeans = KMeans(n_clusters=n_clusters, n_init=n_init, random_state=random_state)
    return kmeans.fit_predict(X)


@pytest.mark.filterwarnings("ignore:Number of distinct clusters")
@settings(deadline=None, max_examples=60)
@given(
    seed=st.integers(0, 2**31 - 1),
    n_samples=st.integers(8, 300),
    n_features=st.integers(1, 4),
    n_clusters=st.integers(2, 5),
    n_init=st.integers(1, 10),
    spread=st.sampled_from([0.05, 0.5, 3.0]),
)
def test_same_labels_and_draws_as_sklearn(
    seed, n_samples, n_features, n_clusters, n_init, spread
):
    X = blobs(seed, n_samples, n_features, n_clusters, spread)
    ours, theirs = np.random.RandomState(seed), np.random.RandomState(seed)
    labels = kmeans_labels(X, n_clusters, n_init=n_init, random_state=ours)
    assert labels.dtype == np.intp
    assert_array_equal(labels, sklearn_labels(X, n_clusters, n_init, theirs))
    # the generator is advanced exactly as KMeans advances it
    assert_array_equal(ours.random_sample(3), theirs.random_sample(3))


@pytest.mark.parametrize("random_state", [0, 7, None])
def test_integer_and_missing_seeds(random_state):
    X = blobs(1, 120, 2, 3)
    labels = kmeans_labels(X, 3, n_init=10, random_state=random_state)
    if random_state is None:
        assert np.unique(labels).size == 3
    else:
        assert_array_equal(labels, sklearn_labels(X, 3, 10, random_state))


def test_the_lowest_inertia_run_wins(monkeypatch):
    # one run of four (seed 3 draws such starts) ends in a poorer local
    # minimum; kmeans_labels keeps the run KMeans keeps
    X = blobs(3, 60, 2, 4, spread=0.3)
    runs = []
    lloyd = _kmeans._lloyd

    def record(X, centers, tol):
        labels, inertia = lloyd(X, centers, tol)
        runs.append(inertia)
        return labels, inertia

    monkeypatch.setattr(_kmeans, "_lloyd", record)
    labels = kmeans_labels(X, 4, n_init=4, random_state=3)
    assert_array_equal(labels, sklearn_labels(X, 4, 4, 3))
    inertia = np.sum((X - X.mean(axis=0)) ** 2)
    centred = X - X.mean(axis=0)
    for k in range(4):
        members = centred[labels == k]
        inertia -= len(members) * np.sum(members.mean(axis=0) ** 2)
    assert np.isclose(inertia, runs[0].min())


def test_duplicate_points_are_handed_to_sklearn():
    # fewer distinct points than clusters: KMeans itself runs, and warns
    X = np.repeat([[1.0, 0.0], [0.0, 1.0]], 10, axis=0)
    ours, theirs = np.random.RandomState(0), np.random.RandomState(0)
    with pytest.warns(ConvergenceWarning, match="distinct clusters"):
        expected = sklearn_labels(X, 3, 10, theirs)
    with pytest.warns(ConvergenceWarning, match="distinct clusters"):
        labels = kmeans_labels(X, 3, n_init=10, random_state=ours)
    assert_array_equal(labels, expected)
    assert_array_equal(ours.random_sample(3), theirs.random_sample(3))


def test_fewer_points_than_clusters_raise_sklearns_error():
    with pytest.raises(ValueError, match="n_samples=2 should be >= n_clusters=3"):
        kmeans_labels(np.eye(2), 3, n_init=10, random_state=0)
