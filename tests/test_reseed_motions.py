"""Tests for the re-seeding of motions a refinement empties."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest

from sklearn_gpca._motion_graph import motion_affinity
from sklearn_gpca._observed_subspaces import observed_entries
from sklearn_gpca._reseed_motions import reseed_empty_motions
from sklearn_gpca._segment import segment_motions
from sklearn_gpca._track_neighbors import track_neighbors
from sklearn_gpca.datasets import make_motions, make_tracks
from sklearn_gpca.metrics import misclassification_rate


def _two_objects():
    """A background and an object far apart in the image, 120 and 60 tracks."""
    X, y = make_motions(2, n_points=[120, 60], n_frames=12, noise=1.0, random_state=0)
    X = X + (400.0 * y)[:, None] * np.tile([1.0, 0.0], 12)
    X0, mask = observed_entries(X / 400.0)
    affinity = motion_affinity(X0, mask, track_neighbors(X0, mask, 10))
    return X0, mask, y, affinity


def _reseed(X0, mask, labels, affinity, n_motions=2, min_tracks=5):
    return reseed_empty_motions(
        X0,
        mask,
        labels,
        n_motions,
        affinity,
        1e-5,
        min_tracks=min_tracks,
        min_size=12,
        per_fragment=40,
        random_state=np.random.RandomState(0),
    )


def test_an_emptied_motion_takes_half_of_the_largest():
    X0, mask, y, affinity = _two_objects()
    merged = np.zeros_like(y)
    merged[:3] = 1  # three tracks cannot span a 4-D subspace
    labels = _reseed(X0, mask, merged, affinity)
    assert np.bincount(labels).min() >= 12
    # the fragments route splits the union along the true motions
    assert misclassification_rate(y, labels) < 0.05


def test_nothing_to_reseed_returns_none():
    X0, mask, y, affinity = _two_objects()
    assert _reseed(X0, mask, y, affinity) is None


def test_a_motion_too_small_to_split_returns_none():
    X0, mask, y, affinity = _two_objects()
    few = np.flatnonzero(y == 0)[:20]
    labels = np.full(y.size, -1)
    labels[few] = 0
    # the only motion holds 20 tracks: fewer than two halves of 12
    assert _reseed(X0, mask, labels, affinity) is None


@pytest.mark.parametrize("min_tracks", [5, 61])
def test_min_tracks_sets_what_counts_as_emptied(min_tracks):
    X0, mask, y, affinity = _two_objects()
    labels = _reseed(X0, mask, y, affinity, min_tracks=min_tracks)
    # the object's 60 tracks count as emptied only below 61
    assert (labels is None) == (min_tracks == 5)


def test_segment_motions_reseeds_the_motion_its_refinement_empties():
    """The gpca candidate of this lab draw leaves one of three motions with
    10 tracks, which the refinement empties; re-seeded, it finds all three."""
    X, y = make_tracks(
        scene="lab", n_motions=3, n_frames=30, missing=0.3, random_state=3
    )
    inliers = y >= 0
    X, y = X[inliers], y[inliers]
    _, info = segment_motions(
        X,
        3,
        init="gpca",
        screen_outliers=False,
        perspective_background=False,
        random_state=0,
        return_info=True,
    )
    assert np.bincount(info.refined[0], minlength=3).min() >= 12
    assert misclassification_rate(y, info.refined[0]) < 0.02
