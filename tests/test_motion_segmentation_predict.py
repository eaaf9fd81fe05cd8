"""Tests of MotionSegmentation.predict: new tracks to the fitted motions."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
from sklearn.exceptions import NotFittedError

from sklearn_gpca import MotionSegmentation
from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.metrics import misclassification_rate


@pytest.fixture(scope="module")
def fitted():
    """A lab draw (2 motions, 30 % missing) fitted on four fifths of its tracks."""
    X, y = make_tracks(scene="lab", n_tracks=300, missing=0.3, random_state=2)
    held = np.random.RandomState(0).rand(y.size) < 0.2
    model = MotionSegmentation(2, random_state=0).fit(X[~held])
    return model, X, y, held


def test_held_out_tracks_join_their_motion(fitted):
    model, X, y, held = fitted
    assert misclassification_rate(y[~held], model.labels_) < 0.02
    assert misclassification_rate(y[held], model.predict(X[held])) < 0.05
    # the fitted tracks keep their labels (no smoothing here: a few may move)
    assert np.mean(model.predict(X[~held]) == model.labels_) > 0.95
    np.testing.assert_array_equal(model.sizes_, np.bincount(model.labels_))


def test_masked_input_is_predicted_as_nan(fitted):
    model, X, _, held = fitted
    masked = np.ma.masked_invalid(X[held])
    np.testing.assert_array_equal(model.predict(masked), model.predict(X[held]))


def test_untestable_track_goes_to_the_largest_motion(fitted):
    model, X, _, _ = fitted
    track = np.full((1, X.shape[1]), np.nan)
    # seen in two frames: a 4-D subspace fits it exactly, no evidence
    track[0, :4] = [100.0, 50.0, 101.0, 51.0]
    # on this draw the largest motion is not motion 0
    assert np.argmax(model.sizes_) == 1
    assert model.predict(track)[0] == 1


def test_predict_checks_its_input(fitted):
    model, X, _, _ = fitted
    with pytest.raises(ValueError, match="X has 58 features, but MotionSegmentation"):
        model.predict(X[:, :-2])
    with pytest.raises(NotFittedError):
        MotionSegmentation(2).predict(X)
