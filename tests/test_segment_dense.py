"""Dense tracks: candidates drawn on random subsamples."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest

from sklearn_gpca import _segment
from sklearn_gpca._segment import segment_motions, subsample_candidates
from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.metrics import misclassification_rate


@pytest.fixture
def dense_at_80(monkeypatch):
    """Tracks count as dense above 120 seen per frame (subsamples of 80)."""
    monkeypatch.setattr(_segment, "MAX_TRACKS_PER_FRAME", 80)
    monkeypatch.setattr(_segment, "DENSE_FACTOR", 1.5)


def _draw(n_tracks=300):
    X, y = make_tracks(3, scene="lab", n_tracks=n_tracks, n_frames=20, random_state=0)
    return X[y >= 0], y[y >= 0]


def test_subsamples_are_disjoint_and_extended_to_every_track(dense_at_80):
    X, y = _draw()
    X0, mask, _ = _segment._scaled_tracks(X)
    per_frame = mask[:, ::2].sum(axis=0).mean()
    seen = []

    def truth_of_subsample(Xs, n_motions, random_state):
        # the rows of X that the subsample holds (tracks are distinct)
        rows = [np.flatnonzero((np.isnan(X) | (x == X)).all(axis=1))[0] for x in Xs]
        seen.append(np.array(rows))
        return y[seen[-1]]

    candidates = subsample_candidates(
        X, X0, mask, 3, truth_of_subsample, random_state=np.random.RandomState(0)
    )
    size = round(X.shape[0] * 80 / per_frame)
    assert len(candidates) == len(seen) == 3
    assert all(rows.size == size for rows in seen)
    assert np.unique(np.concatenate(seen)).size == len(seen) * size
    for rows, labels in zip(seen, candidates, strict=True):
        np.testing.assert_array_equal(labels[rows], y[rows])
        # the other tracks take the nearest subspace of the subsample's groups
        assert misclassification_rate(y, labels) < 0.05


def test_sparse_tracks_are_not_subsampled():
    X, _ = _draw()
    X0, mask, _ = _segment._scaled_tracks(X)
    assert mask[:, ::2].sum(axis=0).mean() < 1.5 * _segment.MAX_TRACKS_PER_FRAME

    def never(*args, **kwargs):
        raise AssertionError("a sparse scene was subsampled")

    rng = np.random.RandomState(0)
    assert subsample_candidates(X, X0, mask, 3, never, random_state=rng) == []
    _, info = segment_motions(X, 3, init="subsample", random_state=0, return_info=True)
    # sparse tracks take every route, as with init="all"
    _, every = segment_motions(X, 3, random_state=0, return_info=True)
    assert info.candidates == every.candidates
    assert not any(name.startswith("subsample") for name in info.candidates)


def test_dense_tracks_are_segmented_by_subsamples(dense_at_80):
    X, y = _draw()
    labels, info = segment_motions(
        X, 3, init="subsample", screen_outliers=False, random_state=0, return_info=True
    )
    own = [name for name in info.candidates if "perspective" not in name]
    assert own == ["subsample 0", "subsample 1", "subsample 2"]
    assert misclassification_rate(y, labels) < 0.03


def test_dense_tracks_keep_a_given_start(dense_at_80):
    X, y = _draw()
    labels, info = segment_motions(
        X, 3, init=y, screen_outliers=False, random_state=0, return_info=True
    )
    assert info.candidates[0] == "given"
    assert misclassification_rate(y, labels) == 0.0


def test_dense_tracks_are_not_drawn_again_from_every_track(dense_at_80):
    # the screening sets tracks aside: sparse tracks would also get the
    # candidates drawn from every track, dense ones only their subsamples'
    X, y = make_tracks(3, scene="lab", n_tracks=300, n_frames=20, random_state=0)
    labels, info = segment_motions(
        X, 3, init="subsample", random_state=0, return_info=True
    )
    assert info.outliers.any()
    assert not any("from every track" in name for name in info.candidates)
    inliers = y >= 0
    assert misclassification_rate(y[inliers], labels[inliers]) < 0.05


def test_the_default_adds_subsamples_to_the_routes(dense_at_80):
    X, y = _draw()
    labels, info = segment_motions(
        X, 3, screen_outliers=False, random_state=0, return_info=True
    )
    own = [name for name in info.candidates if "perspective" not in name]
    subsamples = ["subsample 0", "subsample 1", "subsample 2"]
    # the votes run inside each subsample's segmentation, not on every track
    assert own == [*subsamples, "gpca", "fragments"]
    assert misclassification_rate(y, labels) < 0.03


def test_sparse_tracks_keep_the_votes_on_every_track():
    X, _ = _draw()
    _, info = segment_motions(
        X, 3, screen_outliers=False, random_state=0, return_info=True
    )
    own = [
        name
        for name in info.candidates
        if "perspective" not in name and not name.startswith("re-segmented")
    ]
    assert own == ["gpca", "fragments", "votes"]


def test_subsample_candidates_do_not_depend_on_n_jobs(dense_at_80):
    X, _ = _draw()
    runs = [
        segment_motions(
            X,
            3,
            init="subsample",
            screen_outliers=False,
            random_state=0,
            return_info=True,
            n_jobs=n_jobs,
        )
        for n_jobs in (1, 2)
    ]
    (one, first), (two, second) = runs
    for start, again in zip(first.initial, second.initial, strict=True):
        np.testing.assert_array_equal(start, again)
    np.testing.assert_array_equal(one, two)
