"""PerspectiveClustering and its stages: hypotheses, votes, embedding, refinement."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose, assert_array_equal
from scipy import sparse
from sklearn import config_context
from sklearn.base import clone

from sklearn_gpca import PerspectiveClustering
from sklearn_gpca._perspective import (
    normalized_cut_votes,
    refine_normalized_cut,
    spectral_embedding_votes,
)
from sklearn_gpca._view_hypotheses import (
    _subspace_residuals,
    frame_pairs,
    local_samples,
    observed_frames,
    preference_votes,
    top_votes,
)
from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.metrics import misclassification_rate


@pytest.fixture(scope="module")
def driving():
    """Strong-perspective tracks (KT3DMoSeg-like), those seen in 5+ frames."""
    X, y = make_tracks(
        3, scene="driving", n_tracks=300, outlier_fraction=0, random_state=0
    )
    keep = np.isfinite(X[:, 0::2]).sum(axis=1) >= 5
    return X[keep], y[keep]


def test_observed_frames_need_both_coordinates():
    X = np.array([[0.0, 1.0, np.nan, 2.0, 3.0, np.nan], [1.0, 1.0, 2.0, 2.0, 3, 3]])
    assert_array_equal(observed_frames(X), [[True, False, False], [True] * 3])


def test_frame_pairs():
    assert_array_equal(frame_pairs(4, (1, 3)), [[0, 1], [1, 2], [2, 3], [0, 3]])
    assert frame_pairs(2, (2,)).shape == (0, 2)


def test_local_samples_are_distinct_neighbours_of_their_seed():
    rng = np.random.RandomState(0)
    positions = rng.uniform(size=(50, 2))
    samples = local_samples(positions, 4, 200, 6, rng)
    assert samples.shape == (200, 4)
    assert all(len(set(s)) == 4 for s in samples)
    distances = np.linalg.norm(positions[:, None] - positions[None], axis=-1)
    rank = np.argsort(np.argsort(distances, axis=1), axis=1)
    # Every other member is among the seed's 6 nearest (rank 0 is the seed).
    assert np.all(rank[samples[:, :1], samples[:, 1:]] <= 6)


def test_local_samples_with_duplicate_positions():
    positions = np.zeros((10, 2))
    samples = local_samples(positions, 8, 30, 3, np.random.RandomState(0))
    assert all(len(set(s)) == 8 for s in samples)


def test_top_votes_are_the_smallest_residuals():
    rng = np.random.RandomState(1)
    residuals = rng.uniform(size=(30, 40))
    chosen = top_votes(residuals, 0.1)
    assert chosen.shape == (30, 4)
    assert_array_equal(np.sort(chosen, axis=1), np.sort(np.argsort(residuals)[:, :4]))
    assert top_votes(residuals, 0.001).shape == (30, 1)
    assert top_votes(residuals, 1.0).shape == (30, 40)


@pytest.mark.parametrize("working_memory", [None, 1e-4])
def test_subspace_residuals_match_least_squares(working_memory):
    """Also in chunks of one track, when working_memory holds no more."""
    rng = np.random.RandomState(2)
    tracks = rng.normal(size=(12, 8))
    samples = np.array([[0, 1, 2, 3], [4, 5, 6, 7], [1, 5, 9, 11]])
    with config_context(working_memory=working_memory):
        residuals = _subspace_residuals(tracks, samples)
    for h, s in enumerate(samples):
        B = tracks[s].T
        fit = B @ np.linalg.lstsq(B, tracks.T, rcond=None)[0]
        assert_allclose(
            residuals[:, h], np.linalg.norm(tracks.T - fit, axis=0) / 2, atol=1e-12
        )
    assert_allclose(residuals[samples[0], 0], 0, atol=1e-12)


@pytest.mark.parametrize("model", ["fundamental", "homography", "subspace"])
def test_votes_come_only_from_tracks_observed_in_the_view(driving, model):
    X, _ = driving
    votes, n_views = preference_votes(
        X,
        model,
        n_hypotheses=20,
        top=0.1,
        gaps=(1, 2),
        window=4,
        n_neighbors=10,
        random_state=np.random.RandomState(0),
    )
    observed = observed_frames(X)
    views = (
        [np.arange(s, s + 4) for s in range(observed.shape[1] - 3)]
        if model == "subspace"
        else list(frame_pairs(observed.shape[1], (1, 2)))
    )
    size = {"fundamental": 8, "homography": 4, "subspace": 4}[model]
    usable = [v for v in views if observed[:, v].all(axis=1).sum() > size]
    assert n_views == len(usable) and votes.shape == (X.shape[0], 20 * n_views)
    dense = votes.toarray()
    for k, frames in enumerate(usable):
        block = dense[:, 20 * k : 20 * (k + 1)]
        seen = observed[:, frames].all(axis=1)
        assert_array_equal(block.sum(axis=1), np.where(seen, 2, 0))


def _block_votes(sizes, n_hyp=6, noise=0, seed=0):
    """Votes of groups for their own hypotheses (plus a few random ones)."""
    rng = np.random.RandomState(seed)
    labels = np.repeat(np.arange(len(sizes)), sizes)
    dense = (labels[:, None] == np.repeat(np.arange(len(sizes)), n_hyp)).astype(float)
    flips = rng.uniform(size=dense.shape) < noise
    dense[flips] = 1 - dense[flips]
    return sparse.csr_array(dense), labels


def test_embedding_separates_disjoint_voters():
    votes, labels = _block_votes([40, 10, 5])
    embedding = spectral_embedding_votes(votes, 3, np.random.RandomState(0))
    for k in range(3):
        rows = embedding[labels == k]
        assert_allclose(rows, np.broadcast_to(rows[0], rows.shape), atol=1e-6)
    assert_allclose(np.linalg.norm(embedding, axis=1), 1)


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 1000), noise=st.floats(0.0, 0.3))
def test_refinement_never_raises_the_normalized_cut(seed, noise):
    votes, _ = _block_votes([30, 15, 10], noise=noise, seed=seed)
    start = np.random.RandomState(seed).randint(3, size=votes.shape[0])
    start[:3] = [0, 1, 2]
    refined, n_iter = refine_normalized_cut(votes, start, 3, max_iter=50)
    if len(np.unique(refined)) == 3:
        assert (
            normalized_cut_votes(votes, refined, 3)
            <= normalized_cut_votes(votes, start, 3) + 1e-12
        )
    assert n_iter >= 1


def test_refinement_recovers_blocks_from_a_perturbed_start():
    votes, labels = _block_votes([30, 15, 10], noise=0.05)
    start = labels.copy()
    start[::4] = (start[::4] + 1) % 3
    refined, _ = refine_normalized_cut(votes, start, 3, max_iter=30)
    assert_array_equal(refined, labels)


def test_segments_strong_perspective_tracks(driving):
    X, y = driving
    labels = PerspectiveClustering(3, random_state=0).fit(X).labels_
    assert misclassification_rate(y, labels) < 0.2


def test_units_barely_change_the_labels(driving):
    """Ranks, Hartley normalisation and neighbours are scale-free; only the
    rounding of near-ties (a sample's own tracks fit it to ~1e-16) moves."""
    X, _ = driving
    model = PerspectiveClustering(3, random_state=0)
    labels = clone(model).fit(X).labels_
    assert misclassification_rate(labels, model.fit(640 * X).labels_) < 0.05


def test_masked_array_is_nan(driving):
    X, _ = driving
    X = X[:100]
    model = PerspectiveClustering(2, n_hypotheses=20, random_state=0)
    masked = np.ma.masked_invalid(X)
    assert_array_equal(clone(model).fit(X).labels_, model.fit(masked).labels_)
    assert model.n_hypotheses_ > 0 and model.n_iter_ >= 1


def test_one_cluster_and_reproducibility(driving):
    X, _ = driving
    X = X[:100]
    assert np.all(PerspectiveClustering(1).fit(X).labels_ == 0)
    a = PerspectiveClustering(3, n_hypotheses=20, random_state=3).fit(X).labels_
    b = PerspectiveClustering(3, n_hypotheses=20, random_state=3).fit(X).labels_
    assert_array_equal(a, b)


@pytest.mark.parametrize(
    "X, params, match",
    [
        (np.ones((10, 5)), {}, "odd number of features, 5"),
        (np.ones((3, 6)), {"n_clusters": 4}, "n_clusters=4 must be at most"),
        (np.ones((10, 6)), {"models": ("affine",)}, "models must be"),
        (np.ones((10, 6)), {"models": ()}, "models must be"),
        (np.ones((10, 6)), {"models": ("homography",) * 2}, "models must be"),
        (np.ones((10, 6)), {"gaps": (0,)}, "gaps must be"),
        (np.ones((10, 6)), {"gaps": (1.5,)}, "gaps must be"),
        (np.ones((10, 2)), {}, "at most the 0 tracks observed in two frames"),
        (np.ones((4, 6)), {}, "nothing to vote for"),
    ],
)
def test_bad_input_is_named(X, params, match):
    with pytest.raises(ValueError, match=match):
        PerspectiveClustering(**params).fit(X)


def test_tracks_seen_in_no_frame_are_named():
    X = np.random.RandomState(0).normal(size=(20, 8))
    X[[3, 7]] = np.nan
    X[5, 1::2] = np.nan
    with pytest.raises(ValueError, match=r"3 \(3, 5, 7\) rows have none"):
        PerspectiveClustering().fit(X)


def test_infinite_values_are_rejected():
    X = np.random.RandomState(0).normal(size=(20, 8))
    X[0, 0] = np.inf
    with pytest.raises(ValueError, match="infinity"):
        PerspectiveClustering().fit(X)


def test_tracks_without_votes_are_warned_about(driving):
    X, _ = driving
    X = X[:150].copy()
    lonely = np.full((2, X.shape[1]), np.nan)
    # Two tracks seen together in the last two frames only, where few are.
    lonely[:, -4:] = [[0.1, 0.2, 0.1, 0.2], [0.3, 0.1, 0.3, 0.1]]
    X[:, -4:] = np.nan
    with pytest.warns(UserWarning, match=r"2 \(150, 151\) tracks are observed only"):
        PerspectiveClustering(
            2, models=("homography",), n_hypotheses=20, random_state=0
        ).fit(np.vstack([X, lonely]))
