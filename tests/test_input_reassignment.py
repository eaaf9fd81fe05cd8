"""Tests of GPCAClustering's reassignment in the width of its input
(``input_subspace_dim``, ``_input_reassignment.py``) and of its input with
missing entries (``segmentation_dim`` with NaN)."""

import numpy as np
import pytest
from sklearn.pipeline import make_pipeline

from sklearn_gpca import GPCAClustering, PowerFactorization
from sklearn_gpca._subspaces import fit_subspace, sine_residuals
from sklearn_gpca.datasets import make_motions
from sklearn_gpca.metrics import misclassification_rate, oracle_labels
from sklearn_gpca.stages import reassign_full_space


@pytest.fixture(scope="module")
def scaling_draw():
    # the 10^4 draw of benchmarks/bench_scaling.py: three motions that
    # overlap in R^5 much more than in R^20
    X, y = make_motions(
        3,
        n_points=[3334, 3333, 3333],
        n_frames=10,
        noise=1.0,
        missing=0.1,
        random_state=0,
    )
    narrow = GPCAClustering(3, segmentation_dim=5, random_state=0).fit(X)
    wide = GPCAClustering(
        3, segmentation_dim=5, input_subspace_dim=4, random_state=0
    ).fit(X)
    return X, y, narrow, wide


def test_wide_route_recovers_what_r5_loses(scaling_draw):
    X, y, narrow, wide = scaling_draw
    # premise, from the truth: the R^5 projection loses information (the
    # nearest true hyperplane in R^5 errs far more than the nearest true
    # subspace in R^20 on the observed entries)
    Z = narrow.segmentation_projection_.transform(X)
    U = Z / np.linalg.norm(Z, axis=1, keepdims=True)
    hyperplanes = [fit_subspace(U[y == k], 4, 0.0) for k in range(3)]
    in_r5 = misclassification_rate(y, np.argmin(sine_residuals(U, hyperplanes), 1))
    in_r20 = misclassification_rate(y, oracle_labels(X, y))
    assert in_r5 > in_r20 + 0.02
    # the R^5 route misassigns; the reassignment in R^20 recovers to the
    # nearest true subspace (which has no smoothing: it can be beaten)
    error = misclassification_rate(y, wide.labels_)
    assert misclassification_rate(y, narrow.labels_) > error + 0.005
    assert error <= in_r20 + 0.005


def test_raw_tracks_are_the_default_pipeline_then_the_reassignment(scaling_draw):
    X, _, narrow, wide = scaling_draw
    default = make_pipeline(
        PowerFactorization(random_state=0), GPCAClustering(3, random_state=0)
    ).fit_predict(X)
    np.testing.assert_array_equal(narrow.labels_, default)
    expected, _ = reassign_full_space(X, default, random_state=0)
    np.testing.assert_array_equal(wide.labels_, expected)
    assert len(wide.input_bases_) == 3 and wide.input_bases_[0].shape == (20, 4)
    assert narrow.input_bases_ is None and narrow.input_residual_scale_ is None


def test_predict_gives_the_training_labels(scaling_draw):
    X, _, _, wide = scaling_draw
    predicted = wide.predict(X[:2000])
    assert np.mean(predicted == wide.labels_[:2000]) > 0.999


def _planes(seed=0, n=60, noise=0.01):
    """Two 2-D planes of R^6 meeting only at the origin, points on each."""
    rng = np.random.RandomState(seed)
    bases = np.linalg.qr(rng.randn(6, 4))[0].reshape(6, 2, 2).transpose(1, 0, 2)
    X = np.vstack([rng.randn(n, 2) @ basis.T for basis in bases])
    return X + noise * rng.randn(*X.shape), np.repeat([0, 1], n)


def test_complete_wide_input_reassigns_in_its_width():
    X, y = _planes()
    model = GPCAClustering(
        2, segmentation_dim=3, input_subspace_dim=2, random_state=0
    ).fit(X)
    assert misclassification_rate(y, model.labels_) == 0
    assert model.segmentation_projection_ is None
    np.testing.assert_array_equal(model.predict(X), model.labels_)
    # the fitted planes are the true ones: each holds its group's points
    for k, basis in enumerate(model.input_bases_):
        members = X[model.labels_ == k]
        off = members - (members @ basis) @ basis.T
        assert np.linalg.norm(off) / np.linalg.norm(members) < 0.02
    assert model.input_residual_scale_ < 0.01**2 * 2


@pytest.mark.parametrize(
    ("params", "match"),
    [
        (dict(input_subspace_dim=2), "needs segmentation_dim"),
        (dict(segmentation_dim=3, input_subspace_dim=6), "needs an input wider"),
        (dict(segmentation_dim=7), "exceeds"),
    ],
)
def test_bad_widths_are_named(params, match):
    X, _ = _planes()
    with pytest.raises(ValueError, match=match):
        GPCAClustering(2, **params).fit(X)


def test_missing_entries_need_segmentation_dim_and_a_fixed_n():
    X, _ = _planes()
    X[0, 0] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        GPCAClustering(2).fit(X)
    with pytest.raises(ValueError, match="n_clusters='auto' needs complete X"):
        GPCAClustering("auto", segmentation_dim=3).fit(X)
    model = GPCAClustering(2, segmentation_dim=3, random_state=0).fit(X)
    with pytest.raises(ValueError, match="NaN"):
        model.score(X)
    X[0, 0] = np.inf
    with pytest.raises(ValueError, match="infinity"):
        GPCAClustering(2, segmentation_dim=3).fit(X)
    assert GPCAClustering(segmentation_dim=3).__sklearn_tags__().input_tags.allow_nan
    assert not GPCAClustering().__sklearn_tags__().input_tags.allow_nan
