import numpy as np
import pytest
from numpy.testing import assert_allclose
from sklearn.metrics import adjusted_rand_score

from sklearn_gpca import ShapeInteractionClustering, shape_interaction_matrix


def independent_motions(seed=0):
    rng = np.random.RandomState(seed)
    blocks = [
        rng.standard_normal((n, 4)) @ rng.standard_normal((4, 20)) for n in (30, 40)
    ]
    return np.vstack(blocks), np.repeat([0, 1], [30, 40])


def test_interaction_is_zero_across_independent_motions():
    X, y = independent_motions()
    Q = shape_interaction_matrix(X, rank=8)
    assert_allclose(Q[np.ix_(y == 0, y == 1)], 0.0, atol=1e-10)
    assert_allclose(Q @ Q, Q, atol=1e-10)  # an orthogonal projector


def test_clusters_independent_motions():
    X, y = independent_motions()
    labels = ShapeInteractionClustering(2, random_state=0).fit_predict(X)
    assert adjusted_rand_score(y, labels) == 1.0


def test_bad_rank():
    X, _ = independent_motions()
    with pytest.raises(ValueError, match=r"rank=30 must be between 1 and .*=20"):
        shape_interaction_matrix(X, rank=30)


def test_rejects_missing_entries():
    X, _ = independent_motions()
    X[0, 0] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        ShapeInteractionClustering(2).fit(X)


def test_boolean_n_clusters_is_rejected():
    X, _ = independent_motions()
    with pytest.raises(ValueError, match=r"'n_clusters' parameter .* Got True"):
        ShapeInteractionClustering(True).fit(X)
