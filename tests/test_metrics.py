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
        # string labels
        (["a", "a", "b", "b"], ["x", "y", "y", "y"], 1 / 4),
        ([3], [7], 0.0),
        # the noise label -1 is never renamed: outliers are right only as -1
        ([-1, 0, 0, 1, 1], [-1, 0, 0, 1, 1], 0.0),
        ([-1, 0, 0, 1, 1], [-1, 5, 5, 6, 6], 0.0),
        ([-1, 0, 0, 1, 1], [2, 0, 0, 1, 1], 1 / 5),
        ([0, 0, 1, 1], [-1, 0, 1, 1], 1 / 4),
        # predicting -1 for a whole motion does not match it
        ([0, 0, 0, 1, 1, 1], [-1, -1, -1, 1, 1, 1], 3 / 6),
        ([-1, -1, 0, 0], [0, 0, -1, -1], 4 / 4),
        ([-1.0, 0.0, 1.0], [-1, 3, 4], 0.0),
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
    # motions renamed, the noise label -1 kept
    assert misclassification_rate(y, np.where(y >= 0, 10 * y + 3, -1)) == 0.0


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


@pytest.mark.parametrize(
    ("y_true", "y_pred", "expected"),
    [
        # outliers left out: 4 inliers, the one flagged -1 is an error
        ([-1, -1, 0, 0, 1, 1], [0, 1, 0, 0, 1, -1], 1 / 4),
        ([-1, 0, 0, 1, 1], [2, 0, 0, 1, 1], 0.0),
        ([0, 0, 1, 1], [-1, 0, 1, 1], 1 / 4),
    ],
)
def test_noise_ignore_scores_the_inliers(y_true, y_pred, expected):
    assert_allclose(
        misclassification_rate(y_true, y_pred, noise="ignore"), expected, atol=1e-12
    )


def test_noise_ignore_needs_an_inlier():
    with pytest.raises(ValueError, match="every point of y_true is noise"):
        misclassification_rate([-1, -1], [0, 1], noise="ignore")
    with pytest.raises(ValueError, match="noise"):
        misclassification_rate([0, 1], [0, 1], noise="drop")


@settings(max_examples=50, deadline=None)
@given(
    y_true=st.lists(st.integers(-1, 4), min_size=1, max_size=40),
    data=st.data(),
)
def test_noise_rule_against_a_brute_force_matching(y_true, data):
    """Best matching of the motions by brute force over permutations; -1 fixed."""
    import itertools

    y_true = np.array(y_true)
    y_pred = np.array(
        data.draw(
            st.lists(st.integers(-1, 3), min_size=len(y_true), max_size=len(y_true))
        )
    )
    best = 0
    for perm in itertools.permutations(range(5), 4):
        renamed = np.where(y_pred >= 0, np.array(perm)[np.maximum(y_pred, 0)], -1)
        best = max(best, np.sum(renamed == y_true))
    assert_allclose(misclassification_rate(y_true, y_pred), 1 - best / len(y_true))
    inliers = y_true >= 0
    if inliers.any():
        best = 0
        for perm in itertools.permutations(range(5), 4):
            renamed = np.where(y_pred >= 0, np.array(perm)[np.maximum(y_pred, 0)], -1)
            best = max(best, np.sum((renamed == y_true)[inliers]))
        assert_allclose(
            misclassification_rate(y_true, y_pred, noise="ignore"),
            1 - best / inliers.sum(),
        )


def test_scorer_with_noise_ignore():
    from sklearn.metrics import make_scorer

    scorer = make_scorer(
        misclassification_rate, greater_is_better=False, noise="ignore"
    )
    X = np.array([[-1.0], [0.5], [0.6], [1.5], [1.6]])
    y = np.array([-1, 0, 0, 1, 1])
    est = _NearestCentreClusterer(1.0).fit(X)  # predicts 0, 0, 0, 1, 1
    assert scorer(est, X, y) == 0.0
    assert_allclose(misclassification_scorer(est, X, y), -1 / 5)


# --- oracle_labels: what mutation testing found unchecked ------------------


def test_oracle_reads_masked_entries_as_missing():
    from sklearn_gpca.datasets import make_motions
    from sklearn_gpca.metrics import oracle_labels

    X, y = make_motions(2, n_points=[30, 30], n_frames=6, missing=0.3, random_state=0)
    masked = np.ma.masked_invalid(X)
    masked.data[masked.mask] = 1e6  # what lies under the mask must not count
    np.testing.assert_array_equal(oracle_labels(masked, y), oracle_labels(X, y))
    assert misclassification_rate(y, oracle_labels(masked, y)) == 0.0


@pytest.mark.parametrize(
    ("X", "y", "message"),
    [
        (
            np.zeros((5, 4)),
            np.zeros(4),
            r"^y_true must be 1-D with one label per row of X \(5\), got shape "
            r"\(4,\)\.$",
        ),
        (
            np.full((5, 4), np.inf),
            np.zeros(5),
            r"^X contains infinite values; use NaN for missing entries\.$",
        ),
    ],
)
def test_oracle_messages(X, y, message):
    from sklearn_gpca.metrics import oracle_labels

    with pytest.raises(ValueError, match=message):
        oracle_labels(X, y)
