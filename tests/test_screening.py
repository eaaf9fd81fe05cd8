"""segment_motions(screen_outliers=True): outlier tracks set aside, then assigned."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
from numpy.testing import assert_array_equal
from sklearn.utils._param_validation import InvalidParameterError

from sklearn_gpca import MotionSegmentation, segment_motions
from sklearn_gpca._segment import MISFIT_COST
from sklearn_gpca.datasets import make_motions, make_tracks
from sklearn_gpca.metrics import misclassification_rate


@pytest.fixture(scope="module")
def lab_with_outliers():
    # 16 of 200 tracks are random walks or drifts; without screening they
    # merge the two motions' candidates (34.8 % error on the inliers)
    return make_tracks(
        scene="lab", n_tracks=200, n_frames=20, outlier_fraction=0.08, random_state=1
    )


def test_screening_recovers_the_motions_outliers_break(lab_with_outliers):
    X, y = lab_with_outliers
    inliers = y >= 0
    n = np.unique(y[inliers]).size
    clean = segment_motions(X[inliers], n, random_state=0, screen_outliers=False)
    screened = segment_motions(X, n, random_state=0)
    plain = segment_motions(X, n, random_state=0, screen_outliers=False)
    error_clean = misclassification_rate(y[inliers], clean)
    assert misclassification_rate(y[inliers], screened[inliers]) <= error_clean + 0.01
    assert misclassification_rate(y[inliers], plain[inliers]) > error_clean + 0.1
    # every track keeps a motion label
    assert screened.min() == 0 and screened.max() == n - 1


def test_screened_tracks_take_the_nearest_motion(lab_with_outliers):
    X, y = lab_with_outliers
    n = np.unique(y[y >= 0]).size
    labels, info = segment_motions(
        X, n, random_state=0, return_info=True, screen_outliers="kept"
    )
    flagged = info.outliers
    assert flagged.any() and not flagged.all()
    kept = segment_motions(X[~flagged], n, random_state=0, screen_outliers=False)
    # the kept tracks are segmented as on their own
    assert_array_equal(labels[~flagged], kept)
    # with outlier_threshold the same tracks are labelled -1 instead
    marked = segment_motions(
        X, n, random_state=0, outlier_threshold=1e-3, screen_outliers="kept"
    )
    assert_array_equal(marked == -1, flagged)
    assert_array_equal(marked[~flagged], labels[~flagged])


def test_candidates_from_every_track_are_judged_on_the_kept_ones(lab_with_outliers):
    X, y = lab_with_outliers
    n = np.unique(y[y >= 0]).size
    labels, info = segment_motions(X, n, random_state=0, return_info=True)
    kept = ~info.outliers
    own = segment_motions(
        X, n, random_state=0, return_info=True, screen_outliers="kept"
    )[1]
    every = segment_motions(
        X, n, random_state=0, return_info=True, screen_outliers=False
    )[1]
    # the kept tracks' own candidates, then every track's, restricted to them
    assert info.candidates == own.candidates + [
        f"{name}, from every track" for name in every.candidates
    ]
    extra = info.refined[len(own.candidates) :]
    for pooled, whole in zip(extra, every.refined, strict=True):
        assert_array_equal(pooled, whole[kept])
    # all judged alike: the kept one has the least penalised fit
    penalised = info.residuals + MISFIT_COST * kept.sum() * info.inconsistency
    assert info.chosen == np.nanargmin(penalised)
    assert_array_equal(labels[kept], info.refined[info.chosen])


def test_outlier_threshold_pools_the_candidates_too(lab_with_outliers):
    X, y = lab_with_outliers
    n = np.unique(y[y >= 0]).size
    marked, info = segment_motions(
        X, n, random_state=0, outlier_threshold=1e-3, return_info=True
    )
    assert any(name.endswith("from every track") for name in info.candidates)
    assert_array_equal(marked == -1, info.outliers)
    assert_array_equal(marked[~info.outliers], info.refined[info.chosen])


def test_nothing_flagged_changes_nothing():
    X = make_motions(2, n_points=60, n_frames=8, random_state=0)[0]
    labels, info = segment_motions(X, 2, random_state=0, return_info=True)
    assert not info.outliers.any()
    assert_array_equal(
        labels, segment_motions(X, 2, random_state=0, screen_outliers=False)
    )


def test_estimator_passes_the_option(lab_with_outliers):
    X, y = lab_with_outliers
    n = np.unique(y[y >= 0]).size
    for screen in (True, "kept", False):
        estimator = MotionSegmentation(n, screen_outliers=screen, random_state=0)
        assert_array_equal(
            estimator.fit(X).labels_,
            segment_motions(X, n, screen_outliers=screen, random_state=0),
        )


def test_screen_outliers_must_be_boolean_or_kept():
    X = np.random.RandomState(0).normal(size=(20, 8))
    with pytest.raises(InvalidParameterError, match="screen_outliers"):
        segment_motions(X, 2, screen_outliers="yes")
    with pytest.raises(InvalidParameterError, match="screen_outliers"):
        MotionSegmentation(2, screen_outliers="all").fit(X)
