"""make_tracks' internals against hand-computed values: the camera, the
projection, the calibration of the lifetimes, the failure messages, and what
``info`` says about each track.

Small hand-built scenes (a camera at the world origin looking along z, boxes
at known depths) give every expected number by hand; draws of ``make_tracks``
are checked against relations that hold exactly for every track.
"""

# SPDX-License-Identifier: BSD-3-Clause

import re
import warnings

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal
from sklearn.utils import Bunch

from sklearn_gpca.datasets import _track_draw, make_tracks
from sklearn_gpca.datasets._track_draw import _typical_step
from sklearn_gpca.datasets._track_geometry import (
    UnseenMotionError,
    _background_candidates,
    _object_candidates,
    in_image,
    make_camera,
    make_occluders,
    sample_points,
    track_geometry,
    visible_share,
)
from sklearn_gpca.datasets._track_lifetimes import (
    birth_probabilities,
    calibrate_lifetime,
    first_frame_share,
    track_lengths,
)
from sklearn_gpca.datasets._track_outliers import _random_walks
from sklearn_gpca.datasets._track_scenes import SCENES, make_scene
from sklearn_gpca.datasets._tracks import _resolve, _track_counts


def _still_scene(object_centres, n_frames=2):
    """A camera at the origin looking along z in every frame, unit boxes with
    the given centres (n_objects, n_frames, 3), never turning."""
    object_centres = np.asarray(object_centres, dtype=float).reshape(-1, n_frames, 3)
    n_objects = object_centres.shape[0]
    return Bunch(
        camera_rotations=np.broadcast_to(np.eye(3), (n_frames, 3, 3)).copy(),
        camera_centres=np.zeros((n_frames, 3)),
        object_sizes=np.ones((n_objects, 3)),
        object_rotations=np.broadcast_to(np.eye(3), (n_objects, n_frames, 3, 3)).copy(),
        object_centres=object_centres,
        ground_height=None,
        walls=None,
    )


# two boxes straight ahead: 5 then 6 m away, and 1 m right at 10 then 12 m
SCENE = _still_scene([[[0, 0, 5], [0, 0, 6]], [[1, 0, 10], [1, 0, 12]]])


def test_camera_near_plane_principal_point_and_reference_depths():
    """Points nearer than ``depth_range[0] / 4`` are lost (make_tracks'
    docstring), the principal point is the image centre, and the affine
    camera scales each object by its centre's depth in each frame, the
    background by the geometric mean of ``depth_range``."""
    camera = make_camera("affine", 100.0, (200, 100), (4.0, 16.0), SCENE)
    assert camera.near == 1.0
    assert_array_equal(camera.centre, [100.0, 50.0])
    assert_allclose(camera.zref, [[8.0, 8.0], [5.0, 6.0], [10.0, 12.0]])


def test_perspective_projection_and_the_near_plane():
    """A background point (x, y, z) seen from the origin projects to
    ``f (x, y) / z + centre``; it is in view only in front of the near plane
    (``depth_range[0] / 4`` = 1 m) and inside the image."""
    camera = make_camera("perspective", 100.0, (200, 100), (4.0, 16.0), SCENE)
    points = np.array([[1.0, 0.5, 5.0], [0.0, 0.0, 0.9], [0.0, 0.0, 1.1]])
    geometry = track_geometry(points, None, 0, [], camera, SCENE)
    assert_allclose(geometry.pixels[0], [[120.0, 60.0], [120.0, 60.0]])
    assert np.all(np.isnan(geometry.pixels[1]))
    assert_allclose(geometry.pixels[2], [[100.0, 50.0], [100.0, 50.0]])
    assert_array_equal(geometry.in_view, [[True, True], [False, False], [True, True]])


def test_affine_silhouette_is_the_box_scaled_by_its_own_depth():
    """Under the affine camera the first box (1 m wide, centre 5 m away in
    frame 0) projects with the scale 100 / 5: a 20-pixel square about the
    image centre. Its silhouette covers (109, 50), not (111, 50)."""
    camera = make_camera("affine", 100.0, (200, 100), (4.0, 16.0), SCENE)
    occluders = make_occluders(SCENE, camera)
    equations, depth = occluders[0][0]
    assert depth == 5.0
    sides = np.array([[109.0, 50.0], [111.0, 50.0], [91.0, 41.0]])
    inside = np.all(sides @ equations[:, :2].T + equations[:, 2] <= 1e-9, axis=1)
    assert_array_equal(inside, [True, False, True])


@pytest.mark.parametrize(
    ("complete", "where"),
    [
        (
            True,
            r"in every frame: .* \(complete tracks, missing=0, suit scene='lab'\)\.",
        ),
        (False, r"at the frames it is in view: .* another random_state\."),
    ],
)
def test_a_motion_never_seen_is_named(complete, where):
    """A box behind the camera has no visible point: the strict sampler names
    the motion, the number of points, and what to change; the lenient one
    marks the points as not found."""
    scene = _still_scene([[[0, 0, -5], [0, 0, -5]]])
    camera = make_camera("perspective", 100.0, (200, 100), (4.0, 16.0), scene)
    occluders = make_occluders(scene, camera)
    births = np.zeros(3, dtype=np.int64)
    rng = np.random.RandomState(0)
    message = "^Motion 1 could not be given 3 visible points " + where + "$"
    with pytest.raises(UnseenMotionError, match=message) as error:
        sample_points(1, births, complete, occluders, camera, scene, (4, 16), rng)
    assert "too little of it is seen. Use fewer frames" in str(error.value)
    lenient = sample_points(
        1, births, complete, occluders, camera, scene, (4, 16), rng, strict=False
    )
    assert_array_equal(lenient.found, [False, False, False])


@pytest.mark.parametrize(
    ("scene", "kwargs", "reason"),
    [
        ("lab", {}, "object 1 is almost never seen throughout."),
        ("handheld", {"missing": 0.3}, "object 1 is almost never in view."),
    ],
)
def test_scene_whose_object_is_never_seen_is_refused_after_20_draws(
    monkeypatch, scene, kwargs, reason
):
    """Where an object shows (almost) none of its surface, the scene is drawn
    again, 20 times, then refused with the last reason."""
    calls = []

    def nothing_visible(motion, occluders, camera, world, rng, n_probes=256):
        calls.append(motion)
        return np.zeros(world.camera_rotations.shape[0]), 0.0

    monkeypatch.setattr(_track_draw, "visible_share", nothing_visible)
    message = (
        f"No draw of the '{scene}' scene in 20 attempts showed every motion "
        f"enough: {reason}"
    )
    with pytest.raises(ValueError, match="^" + re.escape(message) + "$"):
        make_tracks(2, scene=scene, n_tracks=20, n_frames=4, random_state=0, **kwargs)
    assert len(calls) >= 20


def test_typical_step_is_the_median_step_between_consecutive_visible_frames():
    """Steps count only between two consecutive frames where the track is
    visible: the first track's one 3-pixel step (frames 0-1) and the
    second's two 2-pixel steps (frames 1-3; it is hidden in frame 0)."""
    x = np.array([[0.0, 3.0, 50.0, 90.0], [7.0, 100.0, 102.0, 104.0]])
    pixels = np.stack([x, np.zeros_like(x)], axis=-1)
    visible = np.array([[True, True, False, False], [False, True, True, True]])
    assert _typical_step(pixels, visible) == 2.0
    # a slow scene: 0.8 pixel a frame
    assert _typical_step(pixels * 0.4, visible) == pytest.approx(0.8)
    # a still scene: the random walks still move, half a pixel a frame
    assert _typical_step(pixels * 0.0, visible) == 0.5


def test_typical_step_without_two_consecutive_visible_frames_is_one_pixel():
    pixels = np.zeros((2, 3, 2))
    visible = np.array([[True, False, True], [False, True, False]])
    assert _typical_step(pixels, visible) == 1.0


# One track seen in at most 10 frames, u = 0.5: its length is
# 1 + floor(log 0.5 / log(1 - 1/m)) frames (at most 10), so the missing
# fractions it can give are 0, 0.1, ..., 0.9.
ONE_TRACK = (np.array([0.5]), np.array([1]), np.array([10]), 10)


def _missing_at(mean, uniform, min_length, max_length, n_frames):
    lengths = track_lengths(uniform, mean, min_length, max_length)
    return 1 - lengths.sum() / (uniform.size * n_frames)


@pytest.mark.parametrize(
    ("missing", "reached"), [(0.52, 0.5), (0.58, 0.6), (0.12, 0.1), (0.88, 0.9)]
)
def test_calibrated_lifetime_gives_the_nearest_reachable_missing_fraction(
    missing, reached
):
    """Of the missing fractions one track can give, the calibrated mean
    lifetime gives the one nearest the target (from either side; 0.9 needs a
    mean below 2, the track then living one frame)."""
    mean = calibrate_lifetime(*ONE_TRACK, missing)
    assert _missing_at(mean, *ONE_TRACK) == pytest.approx(reached)


def test_calibration_accepts_targets_within_half_a_percent_of_its_limits():
    """Targets up to 0.005 beyond the floor (every track seen until it leaves
    the view) or the ceiling (every track living one frame) are accepted and
    give the limit; further is refused, with the limit in the message."""
    uniform, min_length = np.full(10, 0.5), np.ones(10, dtype=np.int64)
    max_length = np.full(10, 9)  # floor: 1 - 90 / 100 = 0.1
    mean = calibrate_lifetime(uniform, min_length, max_length, 10, 0.096)
    assert _missing_at(mean, uniform, min_length, max_length, 10) == pytest.approx(0.1)
    with pytest.raises(
        ValueError, match=r"^missing=0.094 cannot be reached: .* 0\.100"
    ):
        calibrate_lifetime(uniform, min_length, max_length, 10, 0.094)
    mean = calibrate_lifetime(*ONE_TRACK, 0.904)  # ceiling: 0.9
    assert _missing_at(mean, *ONE_TRACK) == pytest.approx(0.9)
    message = (
        r"^missing=0.95 cannot be reached: tracks living a single frame \(their "
        r"shortest\) miss only 0\.900 of the entries\.$"
    )
    with pytest.raises(ValueError, match=message):
        calibrate_lifetime(*ONE_TRACK, 0.95)


@pytest.fixture(scope="module")
def driving_draw():
    """A driving draw in pixels, with every outlier kind."""
    return make_tracks(
        scene="driving",
        n_tracks=200,
        n_frames=15,
        outlier_fraction=0.2,
        units="pixels",
        noise=0.0,
        random_state=3,
        return_info=True,
    )


def test_switch_frame_and_sources_are_minus_one_except_for_switching_outliers(
    driving_draw,
):
    """``switch_frame`` and ``source_motions`` are -1 for inliers and random
    walks (docstring: "-1 otherwise"); a drift or jump outlier switches inside
    the sequence between two different motions."""
    _X, y, info = driving_draw
    F = info.params["n_frames"]
    switching = np.isin(info.kind, ["drift", "jump"])
    assert np.sum(info.kind == "random_walk") > 0 and np.sum(y >= 0) > 0
    assert np.all(info.switch_frame[~switching] == -1)
    assert np.all(info.source_motions[~switching] == -1)
    assert np.all(
        (info.switch_frame[switching] >= 0) & (info.switch_frame[switching] < F)
    )
    first, second = info.source_motions[switching].T
    assert np.all(first != second)


@pytest.mark.parametrize(("scene", "seed"), [("driving", 0), ("handheld", 2)])
def test_end_reasons_say_why_each_track_ends(scene, seed):
    """A track ends with its lifetime, or where it leaves the view (its pixel
    outside the image, or no pixel: behind the camera), or where it is hidden
    (its pixel inside the image), or with the sequence."""
    _X, y, info = make_tracks(
        scene=scene,
        n_tracks=300,
        n_frames=15,
        mean_lifetime=12.0,
        outlier_fraction=0.3,
        units="pixels",
        noise=0.0,
        random_state=seed,
        return_info=True,
    )
    F = info.params["n_frames"]
    width, height = info.image_size
    reason, end, length = info.end_reason, info.end, info.end - info.birth
    assert_array_equal(reason == "sequence_end", end == F)
    inlier = y >= 0
    # inliers (shortest length 1) that lived their lifetime
    assert_array_equal(
        length[inlier & (reason == "lifetime")],
        info.lifetime[inlier & (reason == "lifetime")],
    )
    lost = np.isin(reason, ["left_view", "occluded"])
    assert np.all(length[lost & inlier] <= info.lifetime[lost & inlier])
    rows = np.flatnonzero(lost)
    xy = info.X_complete.reshape(len(y), F, 2)[rows, end[rows]]
    with np.errstate(invalid="ignore"):
        inside = (
            (xy[:, 0] >= 0) & (xy[:, 0] < width) & (xy[:, 1] >= 0) & (xy[:, 1] < height)
        )
    assert_array_equal(reason[rows] == "occluded", inside)
    assert np.sum(reason == "left_view") > 5 and np.sum(reason == "occluded") > 0


def _pinhole(info, y):
    """Pixels (P, F, 2) of each inlier's point through the pinhole camera of
    ``info``: NaN at or behind the near plane."""
    F = info.params["n_frames"]
    Rc, C = info.camera_rotations, info.camera_centres
    pixels = np.full((len(y), F, 2), np.nan)
    for k in range(info.params["n_motions"]):
        rows = y == k
        points = info.points[rows]
        if k == 0:
            world = np.broadcast_to(points[:, None], (len(points), F, 3))
        else:
            Ro, To = info.object_rotations[k - 1], info.object_centres[k - 1]
            world = np.einsum("fij,nj->nfi", Ro, points) + To
        cam = np.einsum("fji,nfj->nfi", Rc, world - C)
        with np.errstate(divide="ignore", invalid="ignore"):
            uv = info.focal_length * cam[..., :2] / cam[..., 2:]
        uv[cam[..., 2] <= info.params["depth_range"][0] / 4] = np.nan
        pixels[rows] = uv + np.asarray(info.image_size) / 2
    return pixels


@pytest.mark.parametrize(
    ("scene", "kwargs"),
    [
        ("lab", {}),  # complete tracks
        ("driving", {}),  # a mean lifetime
        ("handheld", {"missing": 0.5}),  # a missing target
        ("driving", {"missing": 0.5, "random_state": 1}),  # q raised to 1
    ],
)
def test_perspective_tracks_are_the_pinhole_projections_of_their_points(scene, kwargs):
    """``X_complete`` of every inlier is the pinhole projection of its 3-D
    point, moved by its motion and seen from the camera's pose, whatever the
    route the draw took (complete tracks, a lifetime, a missing target)."""
    kwargs = {"n_tracks": 120, "n_frames": 20, "random_state": 0, **kwargs}
    _X, y, info = make_tracks(
        scene=scene, units="pixels", noise=0.0, return_info=True, **kwargs
    )
    inlier = y >= 0
    F = info.params["n_frames"]
    expected = _pinhole(info, y)[inlier]
    got = info.X_complete[inlier].reshape(-1, F, 2)
    assert_array_equal(np.isnan(got), np.isnan(expected))
    assert_allclose(got, expected, rtol=1e-9, atol=1e-6)
    if kwargs.get("random_state") == 1:
        assert info.first_frame_share == 1.0


def _switching_outliers(info):
    return np.isin(info.kind, ["drift", "jump"])


@pytest.mark.parametrize(("n_frames", "switching"), [(4, False), (5, True)])
def test_drift_and_jump_outliers_need_five_frames(n_frames, switching):
    """Two frames each side of the switch fit in 5 frames (Notes); with fewer
    every outlier is a random walk."""
    _X, y, info = make_tracks(
        scene="driving",
        n_tracks=100,
        n_frames=n_frames,
        outlier_fraction=0.3,
        random_state=0,
        return_info=True,
    )
    assert np.any(_switching_outliers(info)) == switching
    assert np.sum(y == -1) == 30


def test_a_lone_outlier_can_drift_or_jump():
    """One outlier follows the same mix as many: over 8 draws of a single
    outlier, some drift or jump (all 8 random walks: probability 0.25^8)."""
    kinds = [
        make_tracks(
            scene="driving",
            n_tracks=10,
            outlier_fraction=0.1,
            random_state=seed,
            return_info=True,
        )[2].kind
        for seed in range(8)
    ]
    assert any(np.isin(kind, ["drift", "jump"]).any() for kind in kinds)


@pytest.mark.parametrize("n_motions", [1, 2])
def test_outliers_switch_motions_whenever_there_are_two(n_motions):
    """A drift or jump outlier switches to another motion when there is one
    (module docstring: "a and b points of two different motions"); with the
    background alone, from one background point to another (both source
    motions 0), with no warning."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _X, _y, info = make_tracks(
            n_motions,
            scene="driving",
            n_tracks=100,
            outlier_fraction=0.2,
            random_state=0,
            return_info=True,
        )
    switching = _switching_outliers(info)
    assert switching.sum() > 5
    first, second = info.source_motions[switching].T
    if n_motions == 1:
        assert np.all(first == 0) and np.all(second == 0)
    else:
        assert_array_equal(
            np.sort(info.source_motions[switching], axis=1), [[0, 1]] * len(first)
        )


def test_switching_outliers_are_lost_like_any_track():
    """With endless lifetimes a drift or jump track ends where it leaves the
    view or with the sequence; driving forward, some leave the view, and the
    shortest are seen exactly two frames after their switch frame ``s``
    (frames ``s + 1`` and ``s + 2``: the track ends at ``s + 3``)."""
    _X, _y, info = make_tracks(
        scene="driving",
        n_tracks=300,
        n_frames=15,
        mean_lifetime=1e6,
        outlier_fraction=0.3,
        random_state=0,
        return_info=True,
    )
    switching = _switching_outliers(info)
    reasons = info.end_reason[switching]
    assert set(reasons) <= {"left_view", "occluded", "sequence_end"}
    assert np.sum(reasons == "left_view") > 5
    after = info.end[switching] - info.switch_frame[switching]
    assert after.min() == 3


def test_complete_switching_outliers_switch_in_different_frames():
    """Switch frames are drawn for each outlier: complete tracks (all born in
    frame 0) switch in several different frames."""
    _X, _y, info = make_tracks(
        scene="lab",
        n_tracks=200,
        outlier_fraction=0.2,
        random_state=0,
        return_info=True,
    )
    switching = _switching_outliers(info)
    assert switching.sum() > 10
    assert np.all(info.birth[switching] == 0)
    assert np.unique(info.switch_frame[switching]).size > 5


def test_switches_that_cannot_be_placed_become_random_walks():
    """Driving at 30 m/s filmed at 1 frame a second, tracks leave the view
    within a frame or two: many switches cannot be seen two frames each
    side. Those outliers become random walks: seen in at least 3 frames,
    inside the image, with no switch frame or sources."""
    X, y, info = make_tracks(
        scene="driving",
        n_tracks=100,
        n_frames=8,
        outlier_fraction=0.3,
        mean_lifetime=100.0,
        frame_rate=1.0,
        forward_speed=30.0,
        units="pixels",
        noise=0.0,
        random_state=1,
        return_info=True,
    )
    kinds = info.kind[y == -1]
    assert set(kinds) <= {"drift", "jump", "random_walk"}
    walks = info.kind == "random_walk"
    # the documented mix gives a quarter of random walks: here most are
    assert walks.sum() > 0.5 * kinds.size
    assert np.all(info.switch_frame[walks] == -1)
    assert np.all(info.source_motions[walks] == -1)
    assert np.all(info.end[walks] - info.birth[walks] >= 3)
    seen = X[walks].reshape(walks.sum(), -1, 2)
    width, height = info.image_size
    inside = (seen[..., 0] >= 0) & (seen[..., 0] < width)
    inside &= (seen[..., 1] >= 0) & (seen[..., 1] < height)
    assert_array_equal(inside, ~np.isnan(seen[..., 0]))


def _replay_target_steps(tried, missing):
    """Replay the Notes' steps on the recorded draws ``(q, floor)``: the share
    q the draw kept, or None if every scene was rejected; and the number of
    scenes drawn."""
    q = 1 - missing
    steps, scenes = iter(tried), 0
    for share, floor in steps:
        assert share == 1.0
        scenes += 1
        if floor > missing:
            continue
        for candidate in (q, (1 + q) / 2):
            share, floor = next(steps)
            assert share == pytest.approx(candidate)
            if floor <= missing:
                assert next(steps, None) is None
                return candidate, scenes
        assert next(steps, None) is None
        return 1.0, scenes
    assert scenes == 5
    return None, scenes


@pytest.mark.parametrize("missing", [0.5, 0.4])
def test_missing_target_raises_q_then_draws_another_scene(monkeypatch, missing):
    """Notes: each scene is first drawn with every track born in frame 0
    (q = 1, the least it can miss); a scene that misses more than the target
    even so is drawn again (up to 5 scenes, then refused); otherwise q = 1 -
    missing is tried, then halfway to 1, and the first that misses at most
    the target is kept, else q = 1. Every draw's missing fraction with
    endless lifetimes is recorded and the steps replayed on three draws.
    Driving forward loses tracks fast: these draws need the later steps."""
    draw = _track_draw._draw
    tried = []

    def spy(scene, camera, p, counts, n_outliers, share, complete, rng):
        d = draw(scene, camera, p, counts, n_outliers, share, complete, rng)
        tried.append((share, _track_draw._missing_floor(d, p["n_frames"])))
        return d

    monkeypatch.setattr(_track_draw, "_draw", spy)
    kept, scenes = [], []
    for seed in range(3):
        tried.clear()
        try:
            X, _y, info = make_tracks(
                scene="driving",
                n_tracks=100,
                n_frames=20,
                missing=missing,
                random_state=seed,
                return_info=True,
            )
        except ValueError as error:
            assert "cannot be reached" in str(error)
            share, n_scenes = _replay_target_steps(tried, missing)
            assert share is None
        else:
            share, n_scenes = _replay_target_steps(tried, missing)
            assert info.first_frame_share == pytest.approx(share)
            assert abs(np.isnan(X).mean() - missing) <= 0.005
        kept.append(share)
        scenes.append(n_scenes)
    # the later steps are exercised: q halfway to 1, or another scene
    assert 0.75 in kept if missing == 0.5 else max(scenes) > 1


@pytest.mark.parametrize(
    ("scene", "kwargs", "share"),
    [
        ("lab", {}, 1.0),  # complete: every track born in frame 0
        ("driving", {"mean_lifetime": 40.0}, 40.0 / (40.0 + 19)),  # m / (m + F - 1)
    ],
)
def test_first_frame_share_without_a_missing_target(scene, kwargs, share):
    """Notes: with a mean lifetime ``m`` a tracker starts ``m / (m + F - 1)``
    of its tracks in frame 0; complete tracks all."""
    _X, _y, info = make_tracks(
        scene=scene,
        n_tracks=60,
        n_frames=20,
        random_state=0,
        return_info=True,
        **kwargs,
    )
    assert info.first_frame_share == pytest.approx(share)


def test_occluders_exist_in_every_frame_the_box_is_in_front():
    """A box's silhouette is None exactly in the frames where a corner is at
    or behind the near plane (here frame 2 of 5), a convex hull elsewhere."""
    centres = [[[0, 0, 5], [0, 0, 5], [0, 0, -5], [0, 0, 6], [0, 0, 7]]]
    scene = _still_scene(centres, n_frames=5)
    camera = make_camera("perspective", 100.0, (200, 100), (4.0, 16.0), scene)
    (per_frame,) = make_occluders(scene, camera)
    assert [occluder is None for occluder in per_frame] == [
        False,
        False,
        True,
        False,
        False,
    ]
    assert [occluder[1] for occluder in per_frame if occluder] == [5, 5, 6, 7]


def test_object_points_are_uniform_on_the_box_surface():
    """Points uniformly on the surface of a 1 x 2 x 3 box: a pair of faces
    holds its share of the area (x faces 6/11, y 3/11, z 2/11), each point
    on the face its outward normal names, uniform across the face."""
    points, normals = _object_candidates(
        (1.0, 2.0, 3.0), 40_000, np.random.RandomState(0)
    )
    size = np.array([1.0, 2.0, 3.0])
    assert_array_equal(np.abs(normals).sum(axis=1), 1)
    rows, axis = np.nonzero(normals)
    assert_array_equal(rows, np.arange(len(points)))
    assert_array_equal(points[rows, axis], normals[rows, axis] * size[axis] / 2)
    shares = np.bincount(axis, minlength=3) / len(axis)
    assert_allclose(shares, np.array([6.0, 3.0, 2.0]) / 11, atol=0.01)
    assert np.mean(normals.sum(axis=1) > 0) == pytest.approx(0.5, abs=0.01)
    # across a face, each coordinate uniform on its side
    for k in range(3):
        free = points[axis != k, k] / size[k]
        assert np.all(np.abs(free) <= 0.5)
        assert np.mean(free > 0) == pytest.approx(0.5, abs=0.02)
        assert free.std() == pytest.approx(np.sqrt(1 / 12), rel=0.03)


@pytest.fixture(scope="module")
def street():
    """A driving scene (facades, a road 1.65 m below the camera) and 20,000
    background candidates born in its 10 frames, for both cameras."""
    p = SCENES["driving"]
    world = make_scene(
        "driving",
        10,
        0,
        p["forward_speed"],
        p["focal_length"],
        p["image_size"],
        p["depth_range"],
        p["frame_rate"],
        np.random.RandomState(0),
    )
    rng = np.random.RandomState(1)
    births = rng.randint(0, 10, size=20_000)
    draws = {}
    for kind in ("perspective", "affine"):
        camera = make_camera(
            kind, p["focal_length"], p["image_size"], p["depth_range"], world
        )
        points, keep = _background_candidates(
            births, camera, world, p["depth_range"], rng
        )
        Rc, C = world.camera_rotations[births], world.camera_centres[births]
        cam = np.einsum("nji,nj->ni", Rc, points - C)
        draws[kind] = Bunch(camera=camera, points=points, keep=keep, cam=cam)
    return world, births, draws


@pytest.mark.parametrize("kind", ["perspective", "affine"])
def test_background_points_are_seen_at_uniform_pixels(street, kind):
    """A background candidate projects, in its birth frame, to a pixel uniform
    on the image (Notes: "background points at a uniform pixel"), through the
    pinhole or the affine camera (scale: the background's reference depth),
    in front of the camera and no farther than ``depth_range[1]``."""
    _world, births, draws = street
    d = draws[kind]
    width, height = SCENES["driving"]["image_size"]
    f = SCENES["driving"]["focal_length"]
    depth = d.cam[:, 2] if kind == "perspective" else d.camera.zref[0, births]
    pixels = f * d.cam[:, :2] / depth[:, None] + [width / 2, height / 2]
    u = pixels / [width, height]
    assert np.all((u >= 0) & (u < 1))
    for axis in range(2):
        counts = np.histogram(u[:, axis], bins=4, range=(0, 1))[0] / len(u)
        assert_allclose(counts, 0.25, atol=0.015)
    assert np.all(
        (d.cam[:, 2] > 0) & (d.cam[:, 2] <= SCENES["driving"]["depth_range"][1])
    )


def test_background_points_stop_on_the_road_and_the_facades(street):
    """Nothing lies below the road (1.65 m below the camera at frame 0, y
    down) or beyond the facades (at the scene's distances left and right of
    the camera, in its birth frame); rays that reach the road stop on it,
    and a tracker keeps 30 % of the road's points (little texture), and
    every point in the open (on neither the road nor a facade)."""
    world, _births, draws = street
    d = draws["perspective"]
    ground = world.ground_height
    assert ground == 1.65
    assert np.all(d.points[:, 1] <= ground + 1e-9)
    on_road = np.isclose(d.points[:, 1], ground)
    assert 0.1 < on_road.mean() < 0.9
    left, right = world.walls
    assert np.all((d.cam[:, 0] >= -left - 1e-9) & (d.cam[:, 0] <= right + 1e-9))
    on_wall = np.isclose(d.cam[:, 0], -left) | np.isclose(d.cam[:, 0], right)
    assert 0.1 < on_wall.mean() < 0.9
    assert np.all(d.keep[~on_road & ~on_wall])
    assert d.keep[on_road].mean() == pytest.approx(0.3, abs=0.03)


def test_only_faces_turned_to_the_camera_are_visible():
    """Seen head-on from 5 m, a box shows only its front face: a point on it
    is visible, one on the back face is not (its own silhouette never hides
    it), and the visible share of the surface is the front face's area share,
    1/6 of a unit cube; a 1 x 1 x 4 box 5 m to the right also shows its left
    side: (1 + 4) / 18 of its surface (4,000 probes)."""
    scene = _still_scene([[[0, 0, 5], [0, 0, 5]], [[5, 0, 30], [5, 0, 30]]])
    scene.object_sizes = np.array([[1.0, 1.0, 1.0], [1.0, 1.0, 4.0]])
    camera = make_camera("perspective", 100.0, (200, 100), (4.0, 16.0), scene)
    occluders = make_occluders(scene, camera)
    points = np.array([[0.1, 0.1, -0.5], [0.1, 0.1, 0.5]])
    normals = np.array([[0.0, 0.0, -1.0], [0.0, 0.0, 1.0]])
    geometry = track_geometry(points, normals, 1, occluders, camera, scene)
    assert_array_equal(geometry.in_view, [[True, True], [True, True]])
    assert_array_equal(geometry.visible, [[True, True], [False, False]])
    rng = np.random.RandomState(0)
    for motion, share in [(1, 1 / 6), (2, 5 / 18)]:
        per_frame, throughout = visible_share(
            motion, occluders, camera, scene, rng, n_probes=4000
        )
        assert_allclose(per_frame, share, atol=0.025)
        assert throughout == pytest.approx(share, abs=0.025)


def test_the_image_is_the_half_open_pixel_rectangle():
    """A pixel is in the image on ``[0, width) x [0, height)``: its first row
    and column included, the borders at ``width`` and ``height`` excluded,
    NaN (behind the camera) excluded."""
    camera = Bunch(width=200.0, height=100.0)
    pixels = np.array(
        [
            [0.0, 0.0],
            [0.5, 0.5],
            [199.9, 99.9],
            [200.0, 50.0],
            [50.0, 100.0],
            [-0.1, 50.0],
            [50.0, -0.1],
            [np.nan, 50.0],
        ]
    )
    assert_array_equal(
        in_image(pixels, camera), [True, True, True, False, False, False, False, False]
    )


def test_with_one_frame_lifetimes_every_track_is_seen_its_shortest():
    """Lifetimes of one frame (``mean_lifetime=1``) leave each track its
    shortest length: an inlier 1 frame, a random walk 3 (Notes: "at least
    three frames"), a drift or jump track until two frames after its switch
    frame ``s`` (it ends at ``s + 3``)."""
    _X, y, info = make_tracks(
        scene="handheld",
        n_tracks=200,
        n_frames=20,
        mean_lifetime=1.0,
        outlier_fraction=0.3,
        random_state=0,
        return_info=True,
    )
    length = info.end - info.birth
    switching = _switching_outliers(info)
    assert switching.sum() > 10 and np.sum(info.kind == "random_walk") > 5
    assert np.all(length[y >= 0] == 1)
    assert np.all(length[info.kind == "random_walk"] == 3)
    assert_array_equal(info.end[switching], info.switch_frame[switching] + 3)


def test_occluders_hide_what_is_behind_them_in_every_frame_they_exist():
    """Box 2 (5 m ahead) hides a point of box 1 (12 m ahead) in the frames
    where it stands in front of it: not in frame 0 (box 2 behind the camera:
    no silhouette), nor in frame 1 (box 2 at 20 m, behind the point), in
    frame 2. A background point 0.5 pixel outside box 2's silhouette stays
    visible, one 0.5 pixel inside is hidden (the silhouette's half-planes are
    in pixels)."""
    scene = _still_scene(
        [
            [[0, 0, 12], [0, 0, 12], [0, 0, 12]],
            [[0, 0, -5], [0, 0, 20], [0, 0, 5]],
        ],
        n_frames=3,
    )
    camera = make_camera("perspective", 100.0, (200, 100), (4.0, 16.0), scene)
    occluders = make_occluders(scene, camera)
    front = track_geometry(
        np.array([[0.1, 0.1, -0.5]]),
        np.array([[0.0, 0.0, -1.0]]),
        1,
        occluders,
        camera,
        scene,
    )
    assert_array_equal(front.in_view, [[True, True, True]])
    assert_array_equal(front.visible, [[True, True, False]])
    # box 2's front face, 4.5 m away in frame 2, ends at 100 + 100 * 0.5 / 4.5
    edge = 100 * 0.5 / 4.5
    x = np.array([edge + 0.5, edge - 0.5]) * 10 / 100
    background = track_geometry(
        np.column_stack([x, [0.0, 0.0], [10.0, 10.0]]),
        None,
        0,
        occluders,
        camera,
        scene,
    )
    assert_array_equal(background.visible[:, 2], [True, False])


def test_random_walks_reflect_at_the_borders_and_stay_uniform():
    """A random walk starts at a uniform pixel and is reflected at the image's
    borders (module docstring): reflection keeps the uniform law, so in every
    frame the walks of a small image (10 x 6 pixels, steps of 3) are uniform
    on it, none stuck on a border."""
    camera = Bunch(width=10.0, height=6.0)
    n, n_frames = 6000, 8
    births = np.zeros(n, dtype=np.int64)
    pixels, _, _ = _random_walks(
        births, 3.0, camera, n_frames, np.random.default_rng(0)
    )
    u = pixels / [10.0, 6.0]
    assert np.all((u >= 0) & (u < 1))
    for f in range(n_frames):
        for axis in range(2):
            counts = np.histogram(u[:, f, axis], bins=5, range=(0, 1))[0] / n
            assert_allclose(counts, 0.2, atol=0.03)


def test_birth_probabilities_give_frame_zero_its_share():
    """Frame 0 gets ``first_share``, the later frames the rest in equal parts,
    with two frames too; one frame gets everything; ``last`` cuts the law
    after its frame (renormalised)."""
    assert_allclose(birth_probabilities(2, 0.7), [0.7, 0.3])
    assert_allclose(birth_probabilities(1, 0.7), [1.0])
    assert_allclose(birth_probabilities(5, 0.6), [0.6, 0.1, 0.1, 0.1, 0.1])
    assert_allclose(birth_probabilities(5, 0.6, last=2), [0.75, 0.125, 0.125, 0, 0])
    # Notes: 1 - missing, or m / (m + F - 1), whose limit is 1 without deaths
    assert first_frame_share(10, missing=0.3) == pytest.approx(0.7)
    assert first_frame_share(10, mean_lifetime=9.0) == pytest.approx(0.5)
    assert first_frame_share(10, mean_lifetime=np.inf) == 1.0


class _Shares:
    """An rng whose Dirichlet draw is given."""

    def __init__(self, shares):
        self.shares = np.asarray(shares)

    def dirichlet(self, alpha):
        assert len(alpha) == len(self.shares)
        return self.shares


def test_track_counts_round_the_shares_by_largest_remainder():
    """Each object gets one track, then the ``extra`` others in proportion to
    its share, rounded so that the largest fractional parts get the leftover
    tracks: shares (0.48, 0.17, 0.35) of 10 extra tracks are 4.8, 1.7, 3.5,
    so 5, 2, 3. One background track is enough; none is refused."""
    counts, n_outliers = _track_counts(26, 4, 0.5, 0.0, _Shares([0.48, 0.17, 0.35]))
    assert n_outliers == 0
    assert_array_equal(counts, [13, 6, 3, 4])
    counts, _ = _track_counts(20, 2, 0.05, 0.0, _Shares([1.0]))
    assert_array_equal(counts, [1, 19])
    with pytest.raises(ValueError, match="gives 0 background tracks"):
        _track_counts(20, 2, 0.02, 0.0, _Shares([1.0]))


def _given(**changes):
    names = [
        "n_motions",
        "n_tracks",
        "n_frames",
        "background_fraction",
        "outlier_fraction",
        "missing",
        "mean_lifetime",
        "focal_length",
        "image_size",
        "depth_range",
        "forward_speed",
        "frame_rate",
        "noise",
    ]
    return dict(dict.fromkeys(names), **changes)


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        (
            {"missing": 0.5, "mean_lifetime": 10},
            "Give missing=0.5 or mean_lifetime=10, not both: the mean lifetime is "
            "calibrated to reach the missing fraction.",
        ),
        ({"image_size": "big"}, "image_size must be two positive numbers, got 'big'."),
        (
            {"image_size": (0, 480)},
            "image_size must be two positive numbers, got (0, 480).",
        ),
        (
            {"depth_range": [None, 3]},
            "depth_range must be two positive numbers, got [None, 3].",
        ),
    ],
)
def test_resolve_names_the_bad_parameter(changes, message):
    """The whole message, anchored: not numpy's own error on the way."""
    with pytest.raises(ValueError, match="^" + re.escape(message) + "$"):
        _resolve("lab", **_given(**changes))


def test_resolve_accepts_small_and_equal_depths():
    """Any two positive numbers with nearest <= farthest: 0.5 m to 0.5 m is a
    valid (flat) depth range; the scene's defaults fill the rest."""
    params = _resolve("lab", **_given(depth_range=(0.5, 0.5), image_size=[64, 48]))
    assert params["depth_range"] == (0.5, 0.5)
    assert params["image_size"] == (64.0, 48.0)
    assert params["n_frames"] == SCENES["lab"]["n_frames"]


def test_a_frame_rate_below_the_native_one_spans_the_same_time():
    """At 10 frames a second a hand-held scene (native 30) takes every third
    native pose: its 10 frames span 0.9 s, so the camera, without a subject
    to pan after, walks about ``0.9 * forward_speed`` ahead (20 % smooth speed
    noise)."""
    p = SCENES["handheld"]
    walked = []
    for seed in range(10):
        world = make_scene(
            "handheld",
            10,
            0,
            p["forward_speed"],
            p["focal_length"],
            p["image_size"],
            p["depth_range"],
            10.0,
            np.random.default_rng(seed),
        )
        assert world.camera_centres.shape == (10, 3)
        assert world.object_centres.shape == (0, 10, 3)
        walked.append(
            np.linalg.norm(world.camera_centres[-1] - world.camera_centres[0])
        )
    assert np.mean(walked) == pytest.approx(0.9 * p["forward_speed"], rel=0.15)
