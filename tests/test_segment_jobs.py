"""segment_motions in parallel processes; the cameras of its pooled candidates."""

# SPDX-License-Identifier: BSD-3-Clause

import inspect

import numpy as np
import pytest
from numpy.testing import assert_allclose

from sklearn_gpca import MotionSegmentation, segment_motions
from sklearn_gpca._outliers import _pooled_candidates
from sklearn_gpca._projective_motion import rescaled_cameras
from sklearn_gpca._segment import _segment_tracks

#: segment_motions' defaults of the keywords of _segment_tracks
SEGMENT_DEFAULTS = {
    name: parameter.default
    for name, parameter in inspect.signature(segment_motions).parameters.items()
    if name in inspect.signature(_segment_tracks).parameters
    and parameter.default is not inspect.Parameter.empty
    and name not in ("random_state", "n_jobs")
}


def test_labels_do_not_depend_on_n_jobs(lab_scene):
    X, _ = lab_scene
    one, info = segment_motions(X, 2, random_state=0, return_info=True)
    assert info.outliers.any()  # the pooled candidates are judged
    two, info_two = segment_motions(X, 2, random_state=0, return_info=True, n_jobs=2)
    np.testing.assert_array_equal(one, two)
    assert info.candidates == info_two.candidates
    for a, b in zip(info.refined, info_two.refined, strict=True):
        np.testing.assert_array_equal(a, b)
    assert_allclose(info.residuals, info_two.residuals)


def test_estimator_passes_n_jobs(lab_scene):
    X, _ = lab_scene
    expected = segment_motions(X, 2, random_state=0)
    model = MotionSegmentation(2, random_state=0, n_jobs=2).fit(X)
    np.testing.assert_array_equal(model.labels_, expected)


@pytest.mark.parametrize("n_jobs", [1.5, "two"])
def test_bad_n_jobs_is_refused(lab_scene, n_jobs):
    X, _ = lab_scene
    with pytest.raises(ValueError, match="'n_jobs' parameter"):
        segment_motions(X, 2, n_jobs=n_jobs)


def test_pooled_candidates_carry_cameras_in_the_units_of_the_tracks(lab_scene):
    X, _ = lab_scene
    X = X[:120]
    kept = np.arange(X.shape[0]) % 10 != 0
    runs = [
        _pooled_candidates(
            _segment_tracks, X * factor, kept, 2, random_state=0, **SEGMENT_DEFAULTS
        )
        for factor in (1.0, 8.0)
    ]
    # the segmentation is scale-free: the same candidates, each with the
    # background cameras of its coordinates (times 8 in the second run)
    first, second = (run["extra_candidates"] for run in runs)
    assert [name for name, _, _ in first] == [name for name, _, _ in second]
    for (_, labels, a), (_, labels_8, b) in zip(first, second, strict=True):
        assert labels.shape == (kept.sum(),)
        np.testing.assert_array_equal(labels, labels_8)
        assert a is not None
        assert_allclose(rescaled_cameras(a, 8.0), b, rtol=1e-6, atol=1e-9)
    # the kept tracks' own refined candidates come along, to be judged
    assert runs[0]["candidates"].X0.shape[0] == kept.sum()
