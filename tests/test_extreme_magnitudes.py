"""Coordinates of extreme magnitude, and segmentations with empty motions."""

import numpy as np
import pytest

from sklearn_gpca import MotionSegmentation, PerspectiveClustering, segment_motions
from sklearn_gpca._magnitude import SAFE_RANGE, in_safe_range
from sklearn_gpca.datasets import make_motions
from sklearn_gpca.metrics import oracle_labels

# 2^-700 and 2^700 (about 2e-211 and 5e210): squares under- and overflow.
EXTREMES = [-700, 700]


@pytest.fixture(scope="module")
def draw():
    return make_motions(
        2, n_points=60, n_frames=8, missing=0.2, noise=0.5, random_state=0
    )


@pytest.mark.parametrize("exponent", [*EXTREMES, -100, 0, 100])
def test_in_safe_range_is_exact(exponent):
    X = np.array([[1.5, np.nan, -3.25], [0.0, 7.0, 1e-300]]) * 2.0**exponent
    scaled, factor = in_safe_range(X)
    np.testing.assert_array_equal(scaled, X * factor)
    np.testing.assert_array_equal(np.isnan(scaled), np.isnan(X))
    if SAFE_RANGE[0] <= 7.0 * 2.0**exponent <= SAFE_RANGE[1]:
        assert factor == 1.0 and scaled is X
    else:
        assert 0.5 <= np.nanmax(np.abs(scaled)) < 1.0
        assert np.log2(factor) == round(np.log2(factor))


@pytest.mark.parametrize("exponent", EXTREMES)
def test_segment_motions_does_not_depend_on_extreme_units(draw, exponent):
    X, _ = draw
    labels, info = segment_motions(X, 2, random_state=0, return_info=True)
    with np.errstate(all="raise"):
        scaled, scaled_info = segment_motions(
            X * 2.0**exponent, 2, random_state=0, return_info=True
        )
    np.testing.assert_array_equal(scaled, labels)
    assert scaled_info.scale == pytest.approx(info.scale * 2.0**exponent)


@pytest.mark.parametrize("exponent", EXTREMES)
def test_segment_motions_outlier_route_reports_the_users_scale(draw, exponent):
    X, _ = draw
    _, info = segment_motions(
        X, 2, outlier_threshold=1e-3, random_state=0, return_info=True
    )
    _, scaled = segment_motions(
        X * 2.0**exponent, 2, outlier_threshold=1e-3, random_state=0, return_info=True
    )
    assert scaled.scale == pytest.approx(info.scale * 2.0**exponent)


@pytest.mark.parametrize("exponent", EXTREMES)
def test_perspective_clustering_does_not_depend_on_extreme_units(draw, exponent):
    X, _ = draw
    labels = PerspectiveClustering(2, random_state=0).fit(X).labels_
    scaled = PerspectiveClustering(2, random_state=0).fit(X * 2.0**exponent)
    np.testing.assert_array_equal(scaled.labels_, labels)


@pytest.mark.parametrize("exponent", EXTREMES)
def test_oracle_labels_do_not_depend_on_extreme_units(draw, exponent):
    X, y = draw
    np.testing.assert_array_equal(
        oracle_labels(X * 2.0**exponent, y), oracle_labels(X, y)
    )


def _identical_tracks(missing):
    X = np.tile(np.arange(1.0, 17.0), (40, 1))
    if missing:
        X[:, :4] = np.nan
    return X


@pytest.mark.parametrize(
    "fit, name, missing",
    [
        (lambda X: segment_motions(X, 2), "n_motions", True),
        (lambda X: MotionSegmentation(2).fit(X).labels_, "n_motions", True),
        (lambda X: PerspectiveClustering(2).fit(X).labels_, "n_clusters", False),
    ],
)
def test_identical_tracks_warn_of_the_empty_motion(fit, name, missing):
    message = (
        rf"1 of the {name}=2 motions are empty \(label [01]\): "
        "X has only 1 distinct tracks"
    )
    with pytest.warns(UserWarning, match=message):
        labels = fit(_identical_tracks(missing))
    assert np.unique(labels).size == 1


def test_separable_motions_do_not_warn(draw):
    X, _ = draw
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        labels = segment_motions(X, 2, random_state=0)
    assert np.unique(labels).size == 2
