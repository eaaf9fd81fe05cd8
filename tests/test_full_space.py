"""Tests of the full-space K-subspaces step (``_full_space.py``)."""

import numpy as np
import pytest

from sklearn_gpca import PowerFactorization
from sklearn_gpca.datasets import make_motions
from sklearn_gpca.metrics import misclassification_rate, oracle_labels
from sklearn_gpca.stages import refine_full_space


@pytest.fixture(scope="module")
def motions():
    # generic motions far apart in R^20: the full space separates them
    X, y = make_motions(
        3, n_points=900, n_frames=10, missing=0.1, min_angle=45, random_state=1
    )
    Z = PowerFactorization(random_state=0).fit_transform(X)
    return X, y, Z


def _corrupt(y, fraction, seed=0):
    """Labels with ``fraction`` of the tracks moved to another motion."""
    rng = np.random.RandomState(seed)
    wrong = rng.rand(y.size) < fraction
    return np.where(wrong, (y + 1 + rng.randint(2, size=y.size)) % 3, y)


@pytest.mark.parametrize("max_fit_samples", [None, 300])
def test_recovers_motions_from_a_noisy_start(motions, max_fit_samples):
    X, y, Z = motions
    start = _corrupt(y, 0.15)
    labels, bases, n_iter, converged = refine_full_space(
        X, start, Z, max_fit_samples=max_fit_samples, random_state=0
    )
    # derived truth: no worse than the nearest true subspace, plus 1 point
    floor = misclassification_rate(y, oracle_labels(X, y))
    assert misclassification_rate(y, labels) <= floor + 0.01
    assert misclassification_rate(y, start) > 0.1
    assert converged and n_iter >= 1
    assert len(bases) == 3
    for basis in bases:
        assert basis.shape == (20, 4)
        np.testing.assert_allclose(basis.T @ basis, np.eye(4), atol=1e-10)


def test_outliers_keep_their_label(motions):
    X, y, Z = motions
    start = y.copy()
    start[:50] = -1
    labels, *_ = refine_full_space(X, start, Z, random_state=0)
    assert np.all(labels[:50] == -1)
    assert set(np.unique(labels[50:])) <= {0, 1, 2}


def test_subspace_dim_is_clipped_to_the_width():
    rng = np.random.RandomState(0)
    X = rng.randn(40, 4)
    _, bases, *_ = refine_full_space(
        X, np.repeat([0, 1], 20), X, subspace_dim=8, random_state=0
    )
    assert [b.shape for b in bases] == [(4, 3), (4, 3)]


@pytest.mark.parametrize(
    "labels, match",
    [
        (np.zeros(5, dtype=int), "shape"),
        (np.zeros(40), "integers"),
        (np.full(40, -2), "-1"),
    ],
)
def test_bad_labels(labels, match):
    X = np.random.RandomState(0).randn(40, 6)
    with pytest.raises(ValueError, match=match):
        refine_full_space(X, labels, X)


def test_points_of_other_tracks():
    X = np.random.RandomState(0).randn(40, 6)
    with pytest.raises(ValueError, match="same tracks"):
        refine_full_space(X, np.zeros(40, dtype=int), X[:30])


def test_reassign_without_anchor_from_the_truth_is_the_oracle(motions, monkeypatch):
    from sklearn_gpca.metrics import _oracle
    from sklearn_gpca.stages import reassign_full_space

    X, y, _ = motions
    # derived truth: subspaces fitted to the true groups, nearest per degree of
    # freedom on the observed entries (one common scale: the argmin is the same)
    labels, bases = reassign_full_space(
        X, y, anchor=0.0, n_trim=0, max_fit_samples=None, random_state=0
    )
    assert len(bases) == 3
    # the oracle fits to convergence, the stage by 30 alternations
    assert np.mean(labels != oracle_labels(X, y)) < 0.01
    fit = _oracle.fit_observed_subspace
    monkeypatch.setattr(
        _oracle,
        "fit_observed_subspace",
        lambda *args, **kwargs: fit(*args, **{**kwargs, "polish": False}),
    )
    np.testing.assert_array_equal(labels, oracle_labels(X, y))


def test_reassign_with_a_large_anchor_keeps_the_start(motions):
    from sklearn_gpca.stages import reassign_full_space

    X, y, _ = motions
    start = _corrupt(y, 0.05)
    labels, _ = reassign_full_space(X, start, anchor=1e9, random_state=0)
    np.testing.assert_array_equal(labels, start)
    moved, _ = reassign_full_space(X, start, anchor=0.0, random_state=0)
    assert np.any(moved != start)


def test_reassign_keeps_outliers_and_checks_parameters(motions):
    from sklearn_gpca.stages import reassign_full_space

    X, y, _ = motions
    start = y.copy()
    start[:40] = -1
    labels, _ = reassign_full_space(X, start, max_fit_samples=300, random_state=0)
    assert np.all(labels[:40] == -1)
    assert set(np.unique(labels[40:])) <= {0, 1, 2}
    with pytest.raises(ValueError, match="anchor"):
        reassign_full_space(X, y, anchor=-1.0)
    with pytest.raises(ValueError, match="n_trim"):
        reassign_full_space(X, y, n_trim=-1)
    with pytest.raises(ValueError, match="trim_fraction"):
        reassign_full_space(X, y, trim_fraction=1.0)
    with pytest.raises(ValueError, match="labels"):
        reassign_full_space(X, y[:-1])
    infinite = X.copy()
    infinite[0, 0] = np.inf
    with pytest.raises(ValueError, match="infinity"):
        reassign_full_space(infinite, y)


def test_reassignment_is_not_bent_by_a_few_tracks_of_another_motion():
    # make_motions draw 2 of 600 tracks: the R^5 segmentation puts 3 tracks of
    # one motion among the 200 of another, whose weakest direction a
    # least-squares fit turns towards them (58 degrees): refitted only on the
    # tracks it finds nearest, it then moves 48 of its own tracks away
    from sklearn_gpca import GPCAClustering
    from sklearn_gpca.stages import reassign_full_space

    X, y = make_motions(
        3, n_points=600, n_frames=10, noise=1.0, missing=0.1, random_state=2
    )
    start = GPCAClustering(3, segmentation_dim=5, random_state=0).fit(X).labels_
    trimmed, _ = reassign_full_space(X, start, random_state=0)
    untrimmed, _ = reassign_full_space(
        X, start, n_trim=1, trim_fraction=0.0, random_state=0
    )
    before = misclassification_rate(y, start)
    assert misclassification_rate(y, trimmed) <= before
    assert misclassification_rate(y, untrimmed) > before + 0.05


def test_a_group_too_small_to_fit_keeps_its_tracks_and_takes_none(motions):
    from sklearn_gpca.stages import reassign_full_space

    X, y, _ = motions
    start = y.copy()
    start[np.flatnonzero(y == 2)[:3]] = 3  # three tracks: no 4-D subspace
    labels, bases = reassign_full_space(X, start, random_state=0)
    assert bases[3] is None
    np.testing.assert_array_equal(
        np.flatnonzero(labels == 3), np.flatnonzero(start == 3)
    )
    assert misclassification_rate(y, np.minimum(labels, 2)) < 0.02
