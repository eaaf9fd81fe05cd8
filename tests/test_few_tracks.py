"""segment_motions and MotionSegmentation on fewer tracks than a subspace needs.

A motion's subspace has 4 dimensions; with 3 or 4 tracks no group can hold
one, and refinement used to draw 5 tracks out of 3 and crash inside numpy.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest

from sklearn_gpca import MotionSegmentation, segment_motions
from sklearn_gpca.datasets import make_motions


def _tracks(n_tracks, missing):
    X = make_motions(2, n_points=60, random_state=0)[0][:n_tracks].copy()
    if missing:
        X[::3, :6] = np.nan
    return X


@pytest.mark.filterwarnings("ignore:.* motions are empty:UserWarning")
@pytest.mark.parametrize("n_tracks", [3, 4])
@pytest.mark.parametrize("missing", [False, True])
def test_fewer_tracks_than_a_subspace_needs(n_tracks, missing):
    X = _tracks(n_tracks, missing)
    labels = segment_motions(X, 2, random_state=0)
    assert labels.shape == (n_tracks,)
    assert set(np.unique(labels)) <= {0, 1}
    estimator = MotionSegmentation(2, random_state=0).fit(X)
    np.testing.assert_array_equal(estimator.labels_, labels)


def test_one_motion_per_track_is_kept():
    X = _tracks(3, missing=False)
    assert sorted(segment_motions(X, 3, random_state=0)) == [0, 1, 2]
