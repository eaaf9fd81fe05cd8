"""PerspectiveClustering on tracks seen in one frame only (a tracker's output)."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
from numpy.testing import assert_array_equal

from sklearn_gpca import PerspectiveClustering
from sklearn_gpca._short_tracks import label_from_neighbors
from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.metrics import misclassification_rate


def _one_frame_copies(X, rows, rng):
    """Each row of ``rows`` cut down to one of its observed frames."""
    frames = np.isfinite(X[:, 0::2]) & np.isfinite(X[:, 1::2])
    short = np.full((rows.size, X.shape[1]), np.nan)
    for i, row in enumerate(rows):
        f = rng.choice(np.flatnonzero(frames[row]))
        short[i, 2 * f : 2 * f + 2] = X[row, 2 * f : 2 * f + 2]
    return short


def test_one_frame_tracks_take_their_neighbours_motion():
    X, y = make_tracks(2, scene="lab", n_tracks=200, n_frames=20, random_state=0)[:2]
    rng = np.random.RandomState(0)
    rows = rng.choice(X.shape[0], 40, replace=False)
    X_all = np.vstack([X, _one_frame_copies(X, rows, rng)])
    params = dict(n_hypotheses=40, random_state=0)
    labels = PerspectiveClustering(2, **params).fit(X).labels_
    with_short = PerspectiveClustering(2, **params).fit(X_all).labels_
    # the longer tracks are segmented as without the short ones
    assert_array_equal(with_short[: X.shape[0]], labels)
    # the short ones are labelled as well as the motions are separated
    error_long = misclassification_rate(y, labels)
    error_short = misclassification_rate(np.concatenate([y, y[rows]]), with_short)
    assert error_short <= error_long + 0.05


def test_label_from_neighbors_majority_and_orphans():
    nan = np.nan
    X = np.array(
        [
            [0.0, 0.0, 1.0, 1.0],
            [0.2, 0.0, 1.2, 1.0],
            [0.0, 0.2, 1.0, 1.2],
            [10.0, 10.0, 11.0, 11.0],
            [10.2, 10.0, 11.2, 11.0],
            [10.0, 10.2, 11.0, 11.2],
            [0.05, 0.05, nan, nan],  # nearest the first, near the next two
            [nan, nan, 10.9, 11.0],  # near the next three (label 1)
            [nan, nan, nan, nan],  # shares no frame: an orphan
        ]
    )
    labels = np.array([0, 0, 0, 1, 1, 1])
    labelled = np.arange(9) < 6
    full, orphans = label_from_neighbors(X, labels, labelled, n_neighbors=3)
    assert_array_equal(full, [0, 0, 0, 1, 1, 1, 0, 1, 0])
    assert_array_equal(orphans, [8])
    # the nearest neighbour has label 0, the next two label 1: the majority wins
    full, _ = label_from_neighbors(
        X, np.array([0, 1, 1, 1, 1, 1]), labelled, n_neighbors=3
    )
    assert full[6] == 1
    # one neighbour of each label: the nearer one wins
    full, _ = label_from_neighbors(
        X, np.array([1, 0, 0, 1, 1, 1]), labelled, n_neighbors=2
    )
    assert full[6] == 1


def test_one_frame_track_alone_in_its_frame_is_warned():
    X, _ = make_tracks(2, scene="lab", n_tracks=120, n_frames=12, random_state=1)[:2]
    alone = np.full((1, X.shape[1] + 2), np.nan)
    alone[0, -2:] = [0.5, 0.5]
    X_all = np.vstack([np.hstack([X, np.full((X.shape[0], 2), np.nan)]), alone])
    with pytest.warns(UserWarning, match=r"1 \(120\) tracks are seen in one frame"):
        PerspectiveClustering(2, n_hypotheses=20, random_state=0).fit(X_all)
