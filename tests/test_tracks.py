"""Tests for make_tracks, the generator of tracker-like data."""

# SPDX-License-Identifier: BSD-3-Clause

import re

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose, assert_array_equal
from sklearn.utils import Bunch

from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.datasets._track_geometry import visibility
from sklearn_gpca.datasets._track_lifetimes import (
    birth_probabilities,
    first_frame_share,
    geometric_lifetimes,
)
from sklearn_gpca.datasets._track_scenes import SCENES, make_scene

SMALL = {"driving": 120, "handheld": 150, "lab": 100}


def observed(X):
    return ~np.isnan(X[:, 0::2])


def residual_to_motion(x, M):
    """Least-squares residual of a track's observed entries to span(M)."""
    rows = ~np.isnan(x)
    A, b = M[rows], x[rows]
    coef, *_ = np.linalg.lstsq(A, b, rcond=None)
    return np.linalg.norm(A @ coef - b) / np.linalg.norm(b)


@pytest.mark.parametrize("scene", list(SCENES))
def test_shapes_dtype_and_labels(scene):
    n = SMALL[scene]
    X, y = make_tracks(scene=scene, n_tracks=n, random_state=0)
    F = SCENES[scene]["n_frames"]
    assert X.shape == (n, 2 * F)
    assert X.dtype == np.float64
    assert y.shape == (n,)
    assert np.issubdtype(y.dtype, np.integer)
    n_motions = SCENES[scene]["n_motions"]
    assert set(np.unique(y[y >= 0])) == set(range(n_motions))
    # Normalised units (Hopkins155's x): the image is [-1, 1] x [-1, 1].
    assert np.nanmax(np.abs(X)) < 1.2


def test_deterministic_given_random_state():
    kwargs = {"scene": "handheld", "n_tracks": 150, "n_frames": 40, "missing": 0.5}
    X1, y1 = make_tracks(random_state=3, **kwargs)
    X2, y2 = make_tracks(random_state=np.random.RandomState(3), **kwargs)
    assert_array_equal(X1, X2)
    assert_array_equal(y1, y2)
    X3, _ = make_tracks(random_state=4, **kwargs)
    assert not np.array_equal(np.isnan(X1), np.isnan(X3))


@pytest.mark.parametrize("scene", list(SCENES))
def test_tracks_are_observed_on_one_window(scene):
    X, _y, info = make_tracks(
        scene=scene, n_tracks=SMALL[scene], random_state=1, return_info=True
    )
    seen = observed(X)
    # x and y go missing together.
    assert_array_equal(seen, ~np.isnan(X[:, 1::2]))
    frames = np.arange(seen.shape[1])
    window = (frames >= info.birth[:, None]) & (frames < info.end[:, None])
    assert_array_equal(seen, window)
    assert np.all(info.end > info.birth)
    assert np.all(seen.sum(axis=1) >= 1)
    assert np.all(np.isfinite(X[np.repeat(seen, 2, axis=1)]))


@pytest.mark.parametrize(
    ("n_tracks", "outlier_fraction", "background_fraction"),
    [(200, 0.1, 0.75), (333, 0.05, 0.8), (150, 0.0, 0.7)],
)
def test_label_proportions(n_tracks, outlier_fraction, background_fraction):
    _X, y, info = make_tracks(
        4,
        scene="handheld",
        n_tracks=n_tracks,
        n_frames=40,
        outlier_fraction=outlier_fraction,
        background_fraction=background_fraction,
        random_state=0,
        return_info=True,
    )
    n_outliers = round(outlier_fraction * n_tracks)
    assert np.sum(y == -1) == n_outliers
    n_inliers = n_tracks - n_outliers
    assert np.sum(y == 0) == round(background_fraction * n_inliers)
    assert np.all(np.bincount(y[y > 0])[1:] >= 1)
    # -1 exactly for the outlier kinds.
    assert_array_equal(y == -1, info.kind != "inlier")
    assert set(info.kind[y == -1]) <= {"drift", "jump", "random_walk"}


@pytest.mark.parametrize(
    ("scene", "n_frames", "missing"),
    [
        ("handheld", 20, 0.3),
        ("handheld", 50, 0.5),
        ("handheld", 100, 0.7),
        ("lab", 30, 0.4),
        ("driving", 20, 0.65),
    ],
)
def test_missing_fraction_reaches_target(scene, n_frames, missing):
    X, _ = make_tracks(
        scene=scene, n_tracks=300, n_frames=n_frames, missing=missing, random_state=0
    )
    # The calibration promises 0.005; the bisection lands within a few entries.
    assert abs(np.isnan(X).mean() - missing) < 0.005


def test_zero_missing_gives_complete_tracks():
    X, y, info = make_tracks(
        scene="lab",
        n_tracks=120,
        outlier_fraction=0.1,
        random_state=0,
        return_info=True,
    )
    assert not np.isnan(X).any()
    assert np.all(info.end_reason == "sequence_end")
    assert np.sum(y == -1) == 12


def test_unreachable_missing_is_refused():
    msg = "missing=0.1 cannot be reached: tracks leaving the view"
    with pytest.raises(ValueError, match=re.escape(msg)):
        make_tracks(scene="driving", n_frames=40, missing=0.1, random_state=0)


@pytest.mark.parametrize("scene", list(SCENES))
def test_affine_camera_is_the_exact_subspace_model(scene):
    X, y, info = make_tracks(
        scene=scene,
        n_tracks=SMALL[scene],
        camera="affine",
        noise=0.0,
        random_state=2,
        return_info=True,
    )
    M = info.motion_matrices
    n_motions = SCENES[scene]["n_motions"]
    assert M.shape == (n_motions, X.shape[1], 4)
    inliers = y >= 0
    homogeneous = np.column_stack([info.points[inliers], np.ones(inliers.sum())])
    predicted = np.einsum("pij,pj->pi", M[y[inliers]], homogeneous)
    assert_allclose(predicted, info.X_complete[inliers], atol=1e-12)
    for k in range(n_motions):
        singular = np.linalg.svd(info.X_complete[y == k], compute_uv=False)
        assert singular[4:].max(initial=0) <= 1e-10 * singular[0]
    # Observed entries: inliers lie in their motion's subspace, outliers in none.
    assert_array_equal(X, info.X_clean)
    for x, label in zip(X, y, strict=True):
        residuals = [residual_to_motion(x, M[k]) for k in range(n_motions)]
        if label >= 0:
            assert residuals[label] < 1e-10
        else:
            assert min(residuals) > 1e-6


def test_perspective_camera_deviates_from_the_affine_model():
    def rank4_residual(W):
        s = np.linalg.svd(W, compute_uv=False)
        return np.sqrt(np.sum(s[4:] ** 2) / np.sum(s**2))

    residuals = {}
    for camera in ("affine", "perspective"):
        _, y, info = make_tracks(
            scene="handheld",
            n_tracks=200,
            n_frames=30,
            camera=camera,
            outlier_fraction=0.0,
            noise=0.0,
            random_state=0,
            return_info=True,
        )
        W = info.X_complete[y == 0]
        residuals[camera] = rank4_residual(W[np.isfinite(W).all(axis=1)])
    assert residuals["affine"] < 1e-12
    # A 56-degree field of view over 3-40 m depths: far from affine.
    assert residuals["perspective"] > 1e-3


def test_noise_is_in_pixels():
    X, _, info = make_tracks(
        scene="handheld",
        n_tracks=300,
        noise=2.0,
        units="pixels",
        random_state=0,
        return_info=True,
    )
    error = (X - info.X_clean)[~np.isnan(X)]
    # Standard error of a standard deviation over n draws: sigma / sqrt(2 n).
    assert abs(error.std() - 2.0) < 5 * 2.0 / np.sqrt(2 * error.size)
    _, _, normalised = make_tracks(
        scene="handheld", n_tracks=300, noise=2.0, random_state=0, return_info=True
    )
    assert_allclose(normalised.noise, (2.0 / 320, 2.0 / 240))


def test_units_differ_by_the_normalisation_matrix():
    kwargs = {"scene": "lab", "n_tracks": 60, "random_state": 5}
    X_px, _, info_px = make_tracks(units="pixels", return_info=True, **kwargs)
    X_n, _, info_n = make_tracks(return_info=True, **kwargs)
    assert_array_equal(info_px.K, np.eye(3))
    K = info_n.K
    assert_allclose(K, [[320, 0, 320], [0, 240, 240], [0, 0, 1]])
    assert_allclose(X_n[:, 0::2] * K[0, 0] + K[0, 2], X_px[:, 0::2], atol=1e-9)
    assert_allclose(X_n[:, 1::2] * K[1, 1] + K[1, 2], X_px[:, 1::2], atol=1e-9)


def test_lifetimes_are_geometric_with_the_stated_mean():
    """Per-frame death hazard of the tracks that die of old age.

    Deaths by leaving the view or by the end of the sequence censor the
    lifetimes independently, so the maximum-likelihood hazard is (deaths by
    lifetime) / (frames at risk) and must be 1 / mean_lifetime: a track alive
    in a frame dies of old age before the next with that probability.
    """
    mean = 15.0
    _, y, info = make_tracks(
        scene="handheld",
        n_tracks=3000,
        n_frames=60,
        mean_lifetime=mean,
        outlier_fraction=0.0,
        random_state=0,
        return_info=True,
    )
    deaths = np.sum(info.end_reason == "lifetime")
    # A track seen in frames birth .. end-1 was at risk of dying after each of
    # them but the last when it did not die of old age.
    at_risk = np.sum(info.end - info.birth) - np.sum(info.end_reason != "lifetime")
    hazard = deaths / at_risk
    # Binomial standard error of the hazard, 5 sigma.
    p = 1 / mean
    assert abs(hazard - p) < 5 * np.sqrt(p * (1 - p) / at_risk)
    # The drawn lifetimes themselves: mean within 5 standard errors.
    sd = np.sqrt(mean * (mean - 1))
    assert abs(info.lifetime.mean() - mean) < 5 * sd / np.sqrt(y.size)


@pytest.mark.parametrize("mean", [1.5, 8.0])
def test_geometric_lifetimes_match_the_distribution(mean):
    rng = np.random.RandomState(0)
    lifetimes = geometric_lifetimes(1.0 - rng.random_sample(20000), mean)
    assert lifetimes.min() == 1
    for k in (1, 2, 3, 5, 10, 20):
        expected = (1 - 1 / mean) ** (k - 1)
        freq = np.mean(lifetimes >= k)
        assert abs(freq - expected) <= 5 * np.sqrt(expected * (1 - expected) / 20000)


def test_first_frame_share_is_stationary():
    assert first_frame_share(30, missing=0.4) == pytest.approx(0.6)
    assert first_frame_share(30, mean_lifetime=10.0) == pytest.approx(10 / 39)
    probs = birth_probabilities(30, 0.6)
    assert probs[0] == pytest.approx(0.6)
    assert_allclose(probs[1:], 0.4 / 29)


def test_short_tracks_occur():
    X, _ = make_tracks(scene="driving", random_state=0)
    lengths = observed(X).sum(axis=1)
    assert np.mean(lengths <= 2) > 0.01


def test_info_describes_the_draw():
    X, y, info = make_tracks(
        scene="driving",
        n_tracks=150,
        outlier_fraction=0.1,
        random_state=0,
        return_info=True,
    )
    F = X.shape[1] // 2
    assert info.camera_rotations.shape == (F, 3, 3)
    assert info.object_centres.shape == (2, F, 3)
    assert info.motion_matrices is None
    assert np.all(np.isnan(info.points[y == -1]))
    assert np.all(np.isfinite(info.points[y >= 0]))
    switching = np.isin(info.kind, ["drift", "jump"])
    assert np.all(info.switch_frame[switching] >= info.birth[switching] + 1)
    assert np.all(info.switch_frame[switching] + 2 < info.end[switching])
    assert np.all(info.source_motions[switching] >= 0)
    assert set(info.end_reason) <= {"lifetime", "left_view", "occluded", "sequence_end"}
    assert info.params["n_frames"] == F
    # frame indices and counts are integers (they index the frames)
    for name in ("birth", "end", "lifetime", "switch_frame", "source_motions"):
        assert info[name].dtype == np.int64, name


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"scene": "city"}, "The 'scene' parameter of make_tracks must be a str among"),
        ({"n_motions": 0}, "The 'n_motions' parameter of make_tracks must be"),
        ({"n_frames": 2}, "The 'n_frames' parameter of make_tracks must be"),
        ({"missing": 1.0}, "The 'missing' parameter of make_tracks must be"),
        ({"camera": "fisheye"}, "The 'camera' parameter of make_tracks must be"),
        (
            {"missing": 0.5, "mean_lifetime": 10},
            "Give missing=0.5 or mean_lifetime=10, not both",
        ),
        ({"image_size": (640, -1)}, "image_size must be two positive numbers, got"),
        (
            {"depth_range": (1.0,)},
            "depth_range must be two positive numbers, got (1.0,)",
        ),
        (
            {"depth_range": (10, 5)},
            "depth_range must be (nearest, farthest) with nearest <= farthest, "
            "got (10.0, 5.0)",
        ),
        (
            {"n_motions": 5, "n_tracks": 10, "background_fraction": 0.9},
            "n_tracks=10 with outlier_fraction=0.05 and background_fraction=0.9 "
            "gives 9 background tracks and 1 tracks for the 4 moving objects",
        ),
    ],
)
def test_parameter_errors(kwargs, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        make_tracks(**kwargs)


@settings(
    max_examples=20,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)
@given(
    scene=st.sampled_from(sorted(SCENES)),
    n_motions=st.integers(1, 5),
    n_tracks=st.integers(40, 150),
    n_frames=st.integers(3, 40),
    outlier_fraction=st.floats(0, 0.2),
    lifetime=st.one_of(
        st.builds(lambda m: {"mean_lifetime": m}, st.floats(1, 100)),
        st.builds(lambda q: {"missing": q}, st.floats(0, 0.9)),
    ),
    camera=st.sampled_from(["perspective", "affine"]),
    seed=st.integers(0, 2**16),
)
def test_any_valid_parameters_give_consistent_data(
    scene, n_motions, n_tracks, n_frames, outlier_fraction, lifetime, camera, seed
):
    try:
        X, y, info = make_tracks(
            n_motions,
            scene=scene,
            n_tracks=n_tracks,
            n_frames=n_frames,
            outlier_fraction=outlier_fraction,
            background_fraction=0.7,
            camera=camera,
            random_state=seed,
            return_info=True,
            **lifetime,
        )
    except ValueError as error:
        # The one documented refusal: a missing target below the exits' floor.
        assert "cannot be reached" in str(error)
        return
    assert X.shape == (n_tracks, 2 * n_frames)
    assert y.shape == (n_tracks,)
    assert np.sum(y == -1) == round(outlier_fraction * n_tracks)
    assert set(np.unique(y[y >= 0])) == set(range(n_motions))
    seen = observed(X)
    assert_array_equal(seen, ~np.isnan(X[:, 1::2]))
    assert np.all(seen.sum(axis=1) >= 1)
    frames = np.arange(n_frames)
    assert_array_equal(
        seen, (frames >= info.birth[:, None]) & (frames < info.end[:, None])
    )
    assert np.all(np.isfinite(X[np.repeat(seen, 2, axis=1)]))
    if "missing" in lifetime:
        assert abs(np.isnan(X).mean() - lifetime["missing"]) <= 0.005
    if lifetime.get("missing") == 0:
        assert seen.all()


def test_frame_rate_resamples_the_same_motion():
    kwargs = {"scene": "driving", "n_tracks": 60, "random_state": 7}
    _, _, slow = make_tracks(n_frames=20, frame_rate=10, return_info=True, **kwargs)
    _, _, fast = make_tracks(n_frames=39, frame_rate=20, return_info=True, **kwargs)
    # The same native path (21 frames at 10 Hz), sampled twice as often.
    assert_allclose(fast.camera_centres[::2], slow.camera_centres, atol=1e-12)
    assert_allclose(fast.camera_rotations[::2], slow.camera_rotations, atol=1e-12)
    assert_allclose(fast.object_centres[:, ::2], slow.object_centres, atol=1e-12)
    # 8 m/s for 1.9 s along a gently turning road.
    travelled = np.linalg.norm(np.diff(fast.camera_centres, axis=0), axis=1).sum()
    assert 0.8 * 8 * 1.9 < travelled < 1.2 * 8 * 1.9


def test_switching_outliers_follow_their_two_motions():
    """Before the switch a drift or jump track follows its first motion exactly;
    after it, a jump follows the second motion's positions and a drift its
    displacements since the switch (continuous position)."""
    X, _y, info = make_tracks(
        scene="handheld",
        n_tracks=300,
        n_frames=40,
        outlier_fraction=0.2,
        camera="affine",
        noise=0.0,
        units="pixels",
        random_state=0,
        return_info=True,
    )
    M = info.motion_matrices.reshape(len(info.motion_matrices), -1, 2, 4)
    checked = {"drift": 0, "jump": 0}
    for p in np.flatnonzero(np.isin(info.kind, ["drift", "jump"])):
        first, second = info.source_motions[p]
        s, birth, end = info.switch_frame[p], info.birth[p], info.end[p]
        track = X[p].reshape(-1, 2)
        before = M[first, birth : s + 1].reshape(-1, 4)
        assert residual_to_motion(track[birth : s + 1].ravel(), before) < 1e-9
        after = M[second, s + 1 : end]
        if info.kind[p] == "drift":
            displacement = (track[s + 1 : end] - track[s]).ravel()
            basis = (after - M[second, s]).reshape(-1, 4)
            assert residual_to_motion(displacement, basis) < 1e-9
            # ... which the positions do not follow (generically; 2 frames,
            # 4 entries, fit any 4-dimensional subspace).
            if end - s - 1 >= 3:
                positions = track[s + 1 : end].ravel()
                assert residual_to_motion(positions, after.reshape(-1, 4)) > 1e-6
        else:
            assert (
                residual_to_motion(track[s + 1 : end].ravel(), after.reshape(-1, 4))
                < 1e-9
            )
        checked[info.kind[p]] += 1
    assert min(checked.values()) >= 5


def _largest_turn(rotations):
    """Largest rotation angle (rad) between consecutive frames."""
    rel = np.swapaxes(rotations[..., :-1, :, :], -1, -2) @ rotations[..., 1:, :, :]
    cos = np.clip((np.trace(rel, axis1=-2, axis2=-1) - 1) / 2, -1, 1)
    return float(np.arccos(cos).max())


@pytest.mark.parametrize("scene", list(SCENES))
@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize("n_objects", [0, 3])
def test_cameras_and_objects_turn_smoothly(scene, seed, n_objects):
    """The footage is at 10-30 Hz (KITTI, FBMS, Hopkins155): a camera pan or
    an object's yaw of 0.1 rad per frame (57 to 170 degrees a second) is no
    longer the scene's motion. The draws stay well below (at most ~0.04).
    Without objects the hand-held camera pans at its own rate."""
    p = SCENES[scene]
    world = make_scene(
        scene,
        60,
        n_objects,
        p["forward_speed"],
        p["focal_length"],
        p["image_size"],
        p.get("depth_range"),
        p["frame_rate"],
        np.random.default_rng(seed),
    )
    assert _largest_turn(world.camera_rotations) < 0.1
    if n_objects:
        assert _largest_turn(world.object_rotations) < 0.1


@pytest.mark.parametrize("last", [1, 4, 8])
def test_birth_probabilities_stop_after_the_last_frame(last):
    """Frames 0 .. last may be birth frames: frame 0 gets the first share, the
    others equal parts of the rest (renormalised), later frames nothing."""
    probs = birth_probabilities(10, 0.3, last=last)
    expected = np.zeros(10)
    expected[0] = 0.3
    expected[1 : last + 1] = 0.7 / 9
    assert_allclose(probs, expected / expected.sum())


@pytest.mark.parametrize("mean_lifetime", [0.5, 1.0, 3.0, np.inf])
def test_geometric_lifetimes_are_integers(mean_lifetime):
    """Lifetimes count frames: int64 on every branch (a mean of at most one
    frame gives lifetimes of exactly one frame)."""
    lifetimes = geometric_lifetimes(np.array([0.1, 0.5, 1.0]), mean_lifetime)
    assert lifetimes.dtype == np.int64
    if mean_lifetime <= 1:
        assert_array_equal(lifetimes, [1, 1, 1])


@pytest.mark.parametrize("n_frames", [3, 4, 5, 6])
@pytest.mark.parametrize("missing", [0.0, 0.2])
def test_switching_outliers_are_seen_two_frames_each_side(n_frames, missing):
    """Documented: drift and jump tracks are seen at least two frames each side
    of their switch (so never on 3 frames), random walks at least three."""
    _X, _y, info = make_tracks(
        scene="handheld",
        n_tracks=200,
        n_frames=n_frames,
        outlier_fraction=0.3,
        missing=missing,
        random_state=0,
        return_info=True,
    )
    switching = np.isin(info.kind, ["drift", "jump"])
    s, birth, end = info.switch_frame, info.birth, info.end
    assert np.all(s[switching] - birth[switching] + 1 >= 2)
    assert np.all(end[switching] - s[switching] - 1 >= 2)
    walks = info.kind == "random_walk"
    assert np.all(end[walks] - birth[walks] >= 3)
    if n_frames == 3:
        assert not switching.any()


def _yaw(rotations):
    """Yaw angles of rotations about the vertical (y) axis."""
    return np.arctan2(rotations[..., 0, 2], rotations[..., 2, 2])


@pytest.mark.parametrize("seed", range(6))
def test_driving_scene_puts_cars_in_lanes(seed):
    """The driving scene's layout at frame 0 (camera at the origin, heading
    +z): three lanes 3.5 m apart (a road lane's width); oncoming traffic in the
    left lane (x = -3.5 m, +-0.4 m), 15-45 m ahead, heading at the camera (yaw
    pi, spread 0.02 rad); the other cars 8-30 m ahead along the camera's
    heading. Their lateral and depth positions carry smooth noise of 0.1 m and
    0.3 m (bounds below at 5 standard deviations)."""
    p = SCENES["driving"]
    world = make_scene(
        "driving",
        5,
        5,
        p["forward_speed"],
        p["focal_length"],
        p["image_size"],
        p.get("depth_range"),
        p["frame_rate"],
        np.random.default_rng(seed),
    )
    assert_allclose(world.camera_centres[0, [0, 2]], 0.0, atol=1e-12)
    assert_allclose(_yaw(world.camera_rotations[0]), 0.0, atol=1e-12)
    x, z = world.object_centres[:, 0, 0], world.object_centres[:, 0, 2]
    yaw = _yaw(world.object_rotations[:, 0])
    oncoming = np.cos(yaw) < 0
    turn = np.angle(np.exp(1j * (yaw - np.pi)))
    assert np.all(np.abs(turn[oncoming]) < 0.1)
    assert np.all((x[oncoming] >= -3.9) & (x[oncoming] <= -3.1))
    assert np.all((z[oncoming] >= 15) & (z[oncoming] <= 45))
    ahead = ~oncoming
    assert np.all(np.abs(yaw[ahead]) < 0.02)
    lane_offset = np.min(np.abs(x[ahead, None] - [-3.5, 0.0, 3.5]), axis=1)
    assert np.all(lane_offset <= 0.4 + 0.5)
    assert np.all((z[ahead] >= 8 - 1.5) & (z[ahead] <= 30 + 1.5))


def test_visibility_hides_points_behind_the_other_motions_occluders():
    """A point is in view when in front of the near plane and inside the
    image; it is visible unless another motion's occluder (a convex pixel
    region at a depth) covers its pixel from in front. A motion's own
    occluder never hides its points."""
    camera = Bunch(width=100, height=50, near=0.5)
    # pixels (x, y) and depths of five points in one frame
    pixels = np.array([[15, 15], [15, 15], [40, 15], [150, 15], [15, 15]], float)
    depth = np.array([10.0, 3.0, 10.0, 10.0, -1.0])
    cam_points = np.column_stack([pixels, depth])[:, None, :]
    pixels = pixels[:, None, :]
    # the square 10 <= x, y <= 20 at depth 5: rows a, b, c of a x + b y + c <= 0
    square = np.array([[-1, 0, 10], [1, 0, -20], [0, -1, 10], [0, 1, -20]], float)
    occluders = [[(square, 5.0)], [None]]
    in_view, visible = visibility(cam_points, pixels, None, 2, occluders, camera, None)
    assert_array_equal(in_view[:, 0], [True, True, True, False, False])
    assert_array_equal(visible[:, 0], [False, True, True, False, False])
    in_view, visible = visibility(cam_points, pixels, None, 1, occluders, camera, None)
    assert_array_equal(visible[:, 0], [True, True, True, False, False])


@pytest.mark.parametrize("scene", ["driving", "handheld"])
@pytest.mark.parametrize("seed", [1, 2])
def test_outlier_kinds_follow_the_documented_mix(scene, seed):
    """Documented: half the outliers drift, a quarter jump, a quarter are
    random walks (multinomial counts; bounds at 4 standard deviations). On 30
    frames a drift or jump track finds its two frames each side of the switch,
    so few fall back to random walks."""
    n_outliers = 200
    _X, y, info = make_tracks(
        scene=scene,
        n_tracks=400,
        n_frames=30,
        outlier_fraction=n_outliers / 400,
        random_state=seed,
        return_info=True,
    )
    kinds = info.kind[y == -1]
    assert kinds.size == n_outliers
    for kind, share in [("drift", 0.5), ("jump", 0.25), ("random_walk", 0.25)]:
        sd = np.sqrt(n_outliers * share * (1 - share))
        assert abs(np.sum(kinds == kind) - n_outliers * share) <= 4 * sd, kind


def test_unreachable_missing_message_gives_the_floor_and_the_remedies():
    msg = (
        r"missing=0.1 cannot be reached: tracks leaving the view or being "
        r"occluded already miss 0\.\d{3} of the entries with endless lifetimes\. "
        r"Ask for more missing data, fewer frames, a higher frame_rate or a "
        r"slower camera \(forward_speed\)\.$"
    )
    with pytest.raises(ValueError, match=msg):
        make_tracks(scene="driving", n_frames=40, missing=0.1, random_state=0)


def test_first_frame_share_is_one_minus_missing_when_reachable():
    """A tracker replacing every lost track starts ``1 - missing`` of its tracks
    in frame 0 (Notes); a hand-held pan loses few tracks from the view, so
    that share reaches 50 % missing. Binomial births, bounds at 5 standard
    deviations."""
    for seed in range(3):
        X, _y, info = make_tracks(
            scene="handheld",
            n_tracks=400,
            n_frames=30,
            missing=0.5,
            random_state=seed,
            return_info=True,
        )
        assert info.first_frame_share == 0.5
        assert abs(np.mean(info.birth == 0) - 0.5) < 5 * np.sqrt(0.25 / 400)
        assert abs(np.isnan(X).mean() - 0.5) <= 0.005


def test_first_frame_share_rises_where_the_view_loses_tracks():
    """Driving forward, tracks leave the view fast: 50 % missing on 20 frames
    needs a share ``q`` of births in frame 0 above ``1 - missing``, halfway
    to 1 or 1 (Notes), and is still reached (within 0.005)."""
    shares = []
    for seed in range(3):
        X, _y, info = make_tracks(
            scene="driving",
            n_tracks=100,
            n_frames=20,
            missing=0.5,
            random_state=seed,
            return_info=True,
        )
        assert info.first_frame_share in (0.5, 0.75, 1.0)
        assert abs(np.isnan(X).mean() - 0.5) <= 0.005
        shares.append(info.first_frame_share)
    assert max(shares) > 0.5
