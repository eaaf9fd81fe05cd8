"""Tests for sklearn_gpca.metrics."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose
from sklearn.base import BaseEstimator, ClusterMixin
from sklearn.model_selection import GridSearchCV, cross_val_score

from sklearn_gpca.metrics import (
    get_scorer,
    get_scorer_names,
    misclassification_rate,
    misclassification_scorer,
)


@pytest.mark.parametrize(
    ("y_true", "y_pred", "expected"),
    [
        ([0, 0, 1, 1], [0, 0, 1, 1], 0.0),
        ([0, 0, 1, 1], [1, 1, 0, 0], 0.0),
        ([0, 0, 0, 1, 1, 1], [0, 0, 1, 1, 1, 1], 1 / 6),
        # every point its own cluster: only one point per true group matches
        ([0, 0, 1, 1], [0, 1, 2, 3], 2 / 4),
        # one predicted cluster for two groups: the smaller group is lost
        ([0, 0, 0, 1], [5, 5, 5, 5], 1 / 4),
        # more true groups than clusters: group 2 is unmatched
        ([0, 0, 1, 1, 2, 2], [0, 0, 1, 1, 1, 1], 2 / 6),
        # more clusters than groups: cluster 2 is unmatched
        ([0, 0, 0, 1, 1, 1], [0, 0, 2, 1, 1, 1], 1 / 6),
        # string labels and an outlier label -1
        (["a", "a", "b", "b"], ["x", "y", "y", "y"], 1 / 4),
        ([-1, 0, 0, 1, 1], [2, 0, 0, 1, 1], 0.0),
        ([3], [7], 0.0),
    ],
)
def test_hand_computed(y_true, y_pred, expected):
    rate = misclassification_rate(y_true, y_pred)
    assert isinstance(rate, float)
    assert_allclose(rate, expected, atol=1e-12)


def test_optimal_matching_beats_greedy():
    # Contingency [[3, 1], [3, 0]]: greedily taking a largest cell
    # (true 0 -> pred 0) leaves true 1 -> pred 1 with 0 points, 3 correct;
    # the optimal matching 0 -> 1, 1 -> 0 gets 1 + 3 = 4 correct.
    y_true = [0, 0, 0, 0, 1, 1, 1]
    y_pred = [0, 0, 0, 1, 0, 0, 0]
    assert_allclose(misclassification_rate(y_true, y_pred), 3 / 7)


@settings(max_examples=50, deadline=None)
@given(
    labels=st.lists(st.integers(0, 4), min_size=1, max_size=40),
    noise=st.lists(st.integers(0, 4), min_size=40, max_size=40),
    perm=st.permutations(range(5)),
    perm_true=st.permutations(range(5)),
)
def test_invariant_under_label_permutations(labels, noise, perm, perm_true):
    y_true = np.array(labels)
    y_pred = np.where(np.arange(len(labels)) % 3 == 0, noise[: len(labels)], labels)
    rate = misclassification_rate(y_true, y_pred)
    perm, perm_true = np.array(perm), np.array(perm_true)
    assert misclassification_rate(perm_true[y_true], perm[y_pred]) == rate
    assert misclassification_rate(y_pred, y_true) == rate
    assert 0.0 <= rate < 1.0


@settings(max_examples=30, deadline=None)
@given(labels=st.lists(st.integers(-1, 6), min_size=1, max_size=30))
def test_relabelled_copy_is_perfect(labels):
    y = np.array(labels)
    assert misclassification_rate(y, 10 * y + 3) == 0.0


@pytest.mark.parametrize(
    ("y_true", "y_pred", "match"),
    [
        ([0, 1, 1], [0, 1], "same length, got 3 and 2"),
        ([[0, 1], [1, 0]], [[0, 1], [1, 0]], "y_true must be 1-D"),
        ([0, 1], np.zeros((2, 1)), "y_pred must be 1-D"),
        ([], [], "empty"),
    ],
)
def test_errors(y_true, y_pred, match):
    with pytest.raises(ValueError, match=match):
        misclassification_rate(y_true, y_pred)


class _NearestCentreClusterer(ClusterMixin, BaseEstimator):
    """Tiny clusterer with ``predict``: first coordinate above ``threshold``."""

    def __init__(self, threshold=0.0):
        self.threshold = threshold

    def fit(self, X, y=None):
        self.labels_ = self.predict(X)
        return self

    def predict(self, X):
        return (np.asarray(X)[:, 0] > self.threshold).astype(int)


def test_scorer_in_grid_search():
    rng = np.random.RandomState(0)
    X = rng.uniform(-1, 1, size=(60, 2))
    y = (X[:, 0] > 0.3).astype(int)
    search = GridSearchCV(
        _NearestCentreClusterer(),
        {"threshold": [-0.5, 0.3, 0.8]},
        scoring=misclassification_scorer,
        cv=3,
    ).fit(X, y)
    assert search.best_params_ == {"threshold": 0.3}
    assert search.best_score_ == 0.0
    scores = cross_val_score(
        _NearestCentreClusterer(-0.5), X, y, scoring=misclassification_scorer, cv=3
    )
    assert np.all(scores < 0)


def test_get_scorer_by_name():
    scorer = get_scorer("neg_misclassification_rate")
    assert scorer is not misclassification_scorer
    rng = np.random.RandomState(1)
    X = rng.uniform(-1, 1, size=(20, 2))
    y = (X[:, 0] > 0.0).astype(int)
    est = _NearestCentreClusterer(0.5).fit(X)
    expected = -misclassification_rate(y, est.predict(X))
    assert_allclose(scorer(est, X, y), expected)
    search = GridSearchCV(
        _NearestCentreClusterer(),
        {"threshold": [0.0, 0.5]},
        scoring={"mis": get_scorer("neg_misclassification_rate")},
        refit="mis",
        cv=2,
    ).fit(X, y)
    assert search.best_params_ == {"threshold": 0.0}


def test_get_scorer_falls_back_to_sklearn():
    assert "neg_misclassification_rate" in get_scorer_names()
    assert "adjusted_rand_score" in get_scorer_names()
    assert get_scorer(None) is None
    with pytest.raises(ValueError, match="not a valid scoring value"):
        get_scorer("no_such_scorer")
