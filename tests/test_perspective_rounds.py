"""Guided, balanced rounds of hypotheses (PerspectiveClustering(n_rounds=...))."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_array_equal
from scipy import sparse

from sklearn_gpca import PerspectiveClustering
from sklearn_gpca._perspective import MERGES, merge_segments
from sklearn_gpca._view_hypotheses import guided_samples
from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.metrics import misclassification_rate


def _preferences(rng, n_points=60, n_columns=40):
    return sparse.csr_array(
        (rng.uniform(size=(n_points, n_columns)) < 0.2).astype(float)
    )


def test_guided_samples_are_the_seeds_most_alike_tracks():
    rng = np.random.RandomState(0)
    preferences = _preferences(rng)
    samples = guided_samples(preferences, 4, 300, 7, rng)
    assert samples.shape == (300, 4)
    assert all(len(set(s)) == 4 for s in samples)
    similarity = (preferences @ preferences.T).toarray()
    for seed, others in zip(samples[:, 0], samples[:, 1:], strict=True):
        alike = np.delete(similarity[seed], seed)
        # every partner is at least as alike as the seed's 7th most alike track
        threshold = np.sort(alike)[::-1][6]
        assert np.all(similarity[seed, others] >= threshold)


def test_guided_seeds_follow_the_weights():
    rng = np.random.RandomState(1)
    preferences = _preferences(rng, n_points=30)
    weights = np.zeros(30)
    weights[:10] = 1.0
    weights[10:15] = 3.0
    samples = guided_samples(preferences, 3, 4000, 5, rng, seed_weights=weights)
    counts = np.bincount(samples[:, 0], minlength=30)
    assert counts[15:].sum() == 0
    # 5 tracks of weight 3 against 10 of weight 1: 60 % of the seeds
    assert abs(counts[10:15].sum() / 4000 - 0.6) < 0.03


def test_one_point_samples_are_their_seeds():
    rng = np.random.RandomState(2)
    samples = guided_samples(_preferences(rng), 1, 50, 5, rng)
    assert samples.shape == (50, 1)


def test_n_rounds_is_validated():
    with pytest.raises(ValueError, match="n_rounds"):
        PerspectiveClustering(n_rounds=0).fit(np.ones((10, 6)))


def _votes_of_groups(sizes, n_hyp=6, noise=0.05, seed=0):
    """Each group votes for its own hypotheses, a few votes flipped."""
    rng = np.random.RandomState(seed)
    labels = np.repeat(np.arange(len(sizes)), sizes)
    dense = (labels[:, None] == np.repeat(np.arange(len(sizes)), n_hyp)).astype(float)
    flips = rng.uniform(size=dense.shape) < noise
    dense[flips] = 1 - dense[flips]
    return sparse.csr_array(dense), labels


@pytest.mark.parametrize("rule", MERGES)
def test_pieces_of_a_dominant_group_merge_back(rule):
    votes, labels = _votes_of_groups([60, 12, 8])
    segments = labels.copy()
    # the dominant group cut in three pieces, as the spectral step cuts it
    segments[labels == 0] = np.repeat([0, 3, 4], 20)
    merged = merge_segments(votes, segments, 3, rule=rule)
    assert_array_equal(merged, labels)


def _background_beside_small_motions(seed=0):
    """Segments 0-2: pieces of a background (20 tracks each) that share 4
    hypotheses; segment 3: a small motion (10 tracks) that votes for each of
    those with probability 0.75; segments 4 and 5: halves of another small
    motion (6 tracks each) whose second half votes for the first half's 4
    hypotheses with probability 0.25. Every segment also has 4 of its own."""
    rng = np.random.RandomState(seed)
    segments = np.repeat(np.arange(6), [20, 20, 20, 10, 6, 6])
    own = (segments[:, None] == np.repeat(np.arange(6), 4)).astype(float)
    shared = np.zeros((segments.size, 8))
    shared[segments < 3, :4] = 1.0
    shared[segments == 3, :4] = rng.uniform(size=(10, 4)) < 0.75
    shared[segments == 4, 4:] = 1.0
    shared[segments == 5, 4:] = rng.uniform(size=(6, 4)) < 0.25
    truth = np.array([0, 0, 0, 1, 2, 2])[segments]
    return sparse.csr_array(np.hstack([own, shared])), segments, truth


def test_average_linkage_keeps_a_small_motion_beside_a_cut_background():
    """Greedy association lets the grown background absorb the small motion
    that shares its votes (the association of a union adds up) before the
    two weakly linked halves of the other motion merge; average linkage
    joins the background's pieces, then the halves."""
    votes, segments, truth = _background_beside_small_motions()
    average = merge_segments(votes, segments, 3, rule="average")
    assert misclassification_rate(truth, average) == 0
    greedy = merge_segments(votes, segments, 3, rule="association")
    assert misclassification_rate(truth, greedy) > 0.1


@settings(max_examples=25, deadline=None)
@given(
    seed=st.integers(0, 1000),
    n_segments=st.integers(3, 8),
    rule=st.sampled_from(MERGES),
)
def test_merging_coarsens_the_segments(seed, n_segments, rule):
    votes, _ = _votes_of_groups([30, 15, 10], noise=0.2, seed=seed)
    rng = np.random.RandomState(seed)
    segments = rng.permutation(np.arange(votes.shape[0]) % n_segments)
    merged = merge_segments(votes, segments, 3, rule=rule)
    assert set(np.unique(merged)) == {0, 1, 2}
    # every segment ends in one cluster
    for s in range(n_segments):
        assert np.unique(merged[segments == s]).size == 1


def test_merge_is_validated():
    X = np.random.RandomState(0).normal(size=(10, 8))
    with pytest.raises(ValueError, match=r"'merge' parameter .* must be a str among"):
        PerspectiveClustering(3, n_segments=6, merge="single").fit(X)


def test_n_segments_is_validated():
    X = np.random.RandomState(0).normal(size=(10, 8))
    with pytest.raises(ValueError, match="n_segments=2 must be between"):
        PerspectiveClustering(3, n_segments=2).fit(X)
    with pytest.raises(ValueError, match="n_segments=11 must be between"):
        PerspectiveClustering(3, n_segments=11).fit(X)


def test_five_motions_with_a_dominant_background_are_recovered():
    """The draw of bench_perspective.py's 5-motion setting, seed 0: a
    background of 64 % of the tracks and objects of 10 to 39 tracks. The
    normalised cut of the fused kernel cuts the background in pieces (42 %
    of the tracks misassigned without merging); cut in 10 segments and merged
    back, the motions are found."""
    X, y = make_tracks(5, scene="driving", outlier_fraction=0, random_state=0)
    keep = np.isfinite(X[:, 0::2]).sum(axis=1) >= 5
    X, y = X[keep], y[keep]
    assert np.bincount(y).min() <= 10 and np.mean(y == 0) > 0.6
    labels = PerspectiveClustering(5, n_segments=10, random_state=0).fit(X).labels_
    assert misclassification_rate(y, labels) < 0.2
