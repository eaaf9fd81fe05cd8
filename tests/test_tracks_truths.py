"""The 3-D scenes behind make_tracks, checked against their stated design.

Each scene is drawn by ``make_scene`` at its native frame rate, so every pose
is a drawn one (no resampling), and compared with the ranges its docstring and
``make_tracks``' Notes state. Bounds are exact where the draw is uniform on a
range; spreads are checked on many draws (several seeds and objects), with
margins far outside what sampling noise gives.
"""

# SPDX-License-Identifier: BSD-3-Clause

import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation
from sklearn.utils import Bunch

from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.datasets._track_geometry import _box_corners
from sklearn_gpca.datasets._track_outliers import _random_walks
from sklearn_gpca.datasets._track_scenes import (
    SCENES,
    _in_view_at_start,
    _smooth_noise,
    make_scene,
)


def _draw(scene, n_frames, n_objects, seed, **changes):
    p = dict(SCENES[scene], **changes)
    return make_scene(
        scene,
        n_frames,
        n_objects,
        p["forward_speed"],
        p["focal_length"],
        p["image_size"],
        p["depth_range"],
        p["frame_rate"],
        np.random.default_rng(seed),
    )


def _angles(rotations):
    """Angle (rad) of each rotation matrix."""
    return np.linalg.norm(Rotation.from_matrix(rotations).as_rotvec(), axis=-1)


@pytest.fixture(scope="module")
def lab_worlds():
    """40 lab scenes of 9 objects (360 boxes), 4 frames each."""
    return [_draw("lab", 4, 9, seed, forward_speed=0.3) for seed in range(40)]


def test_lab_boxes_are_10_to_30_cm(lab_worlds):
    """Notes: "boxes of 10-30 cm"; each side uniform on [0.1, 0.3] m, so 1,080
    sides reach within 1 cm of both ends."""
    sides = np.concatenate([w.object_sizes.ravel() for w in lab_worlds])
    assert sides.min() >= 0.1 and sides.max() <= 0.3
    assert sides.min() < 0.11 and sides.max() > 0.29


def test_lab_boxes_start_in_the_central_half_of_the_view(lab_worlds):
    """An object starts at a depth uniform in ``depth_range`` (the Notes: "the
    objects stand in this range too") and at a point projecting uniformly on
    the central half of the image in x and in y, at least 0.4 m from the
    other objects (room for 9 boxes of at most 0.52 m across)."""
    p = SCENES["lab"]
    half = np.asarray(p["image_size"]) / 2 / p["focal_length"]
    starts = np.concatenate([w.object_centres[:, 0] for w in lab_worlds])
    depth = starts[:, 2]
    low, high = p["depth_range"]
    assert depth.min() >= low and depth.max() <= high
    assert depth.min() < low + 0.05 and depth.max() > high - 0.05
    u = starts[:, :2] / depth[:, None] / half  # in units of the half image
    assert np.all(np.abs(u) <= 0.5)
    assert np.all(np.abs(u).max(axis=0) > 0.48)
    # uniform on [-0.5, 0.5] in both axes: every quarter of the range is used
    for axis in range(2):
        counts = np.histogram(u[:, axis], bins=4, range=(-0.5, 0.5))[0]
        assert counts.min() > 0.6 * len(u) / 4
    for w in lab_worlds:
        gaps = np.linalg.norm(
            w.object_centres[:, None, 0] - w.object_centres[None, :, 0], axis=-1
        )
        assert gaps[np.triu_indices(len(gaps), 1)].min() >= 0.4


def test_lab_objects_slide_and_turn_slowly(lab_worlds):
    """Each object slides 3-15 mm a frame along a fixed direction (flattened
    in depth: its z share scaled by 0.3) and spins 0.01-0.04 rad a frame
    about a fixed axis."""
    steps = np.concatenate([np.diff(w.object_centres, axis=1) for w in lab_worlds])
    speed = np.linalg.norm(steps, axis=-1)
    assert np.all((speed >= 0.003 - 1e-12) & (speed <= 0.015 + 1e-12))
    assert speed.min() < 0.004 and speed.max() > 0.014
    np.testing.assert_allclose(speed, speed[:, :1] * np.ones_like(speed))
    # depth share of an isotropic direction averages 0.5, flattened ~0.2
    depth_share = np.abs(steps[:, 0, 2]) / speed[:, 0]
    assert 0.1 < depth_share.mean() < 0.3
    assert np.mean(steps[:, 0, 2] > 0) == pytest.approx(0.5, abs=0.1)
    Ro = np.concatenate([w.object_rotations for w in lab_worlds])
    relative = np.einsum("kfij,kflj->kfil", Ro[:, 1:], Ro[:, :-1])
    spin = _angles(relative)
    assert np.all((spin >= 0.01 - 1e-9) & (spin <= 0.04 + 1e-9))
    assert spin.min() < 0.012 and spin.max() > 0.038
    np.testing.assert_allclose(spin, spin[:, :1] * np.ones_like(spin), rtol=1e-6)
    # the starting orientations are random rotations: not the identity
    assert np.all(_angles(Ro[:, 0]) > 1e-3)


def test_lab_camera_moves_slowly(lab_worlds):
    """The camera starts at the world origin, slides 2-10 mm a frame in a
    fixed direction of its x-y plane, and moves forward ``forward_speed /
    30`` m a frame; it yaws and pitches at constant rates of at most 0.003 rad
    a frame (either sign) and rolls with a smooth noise of 0.002 rad."""
    rng_speed = 0.3 / SCENES["lab"]["frame_rate"]
    lateral, rates, rolls = [], [], []
    for w in lab_worlds:
        C = w.camera_centres
        np.testing.assert_allclose(C[0], 0.0, atol=1e-15)
        step = np.diff(C, axis=0)
        np.testing.assert_allclose(step, step[:1] * np.ones_like(step), atol=1e-12)
        np.testing.assert_allclose(step[:, 2], rng_speed, rtol=1e-9)
        lateral.append(np.linalg.norm(step[0, :2]))
        angles = Rotation.from_matrix(w.camera_rotations).as_euler("YXZ")
        np.testing.assert_allclose(angles[0, :2], 0.0, atol=1e-15)
        rate = np.diff(angles[:, :2], axis=0)
        np.testing.assert_allclose(rate, rate[:1] * np.ones_like(rate), atol=1e-12)
        rates.append(rate[0])
        rolls.append(angles[:, 2])
    lateral, rates, rolls = np.array(lateral), np.array(rates), np.array(rolls)
    assert np.all((lateral >= 0.002 - 1e-12) & (lateral <= 0.01 + 1e-12))
    assert lateral.min() < 0.003 and lateral.max() > 0.009
    assert np.all(np.abs(rates) <= 0.003)
    assert np.abs(rates).max(axis=0).min() > 0.0025
    assert np.all((rates > 0).mean(axis=0) > 0.25)
    assert np.all((rates < 0).mean(axis=0) > 0.25)
    assert 0.001 < rolls.std() < 0.003


def _handheld_steps(world):
    """Camera yaw per frame and each frame's step in the camera's heading frame
    (x right, y down, z forward), the velocity the hand-held camera drew."""
    yaw = Rotation.from_matrix(world.camera_rotations).as_euler("YXZ")[:, 0]
    step = np.diff(world.camera_centres, axis=0)
    heading = Rotation.from_euler("Y", yaw[:-1, None]).as_matrix()
    return yaw, np.einsum("fji,fj->fi", heading, step)


def test_handheld_camera_walks_forward_at_the_given_speed():
    """The hand-held camera moves ``forward_speed / 30`` m a frame along its
    heading, with a smooth (AR(1), memory 0.9) relative noise of 20 %, a
    constant sideways drift of at most 2 cm a frame with a 3 mm noise, and a
    2 mm vertical noise. Without a subject it pans at a constant rate of at
    most 0.005 rad a frame, with a 0.002 rad shake."""
    forward = SCENES["handheld"]["forward_speed"] / SCENES["handheld"]["frame_rate"]
    relative, sideways, vertical, pans, shakes = [], [], [], [], []
    for seed in range(30):
        world = _draw("handheld", 200, 0, seed)
        np.testing.assert_allclose(world.camera_centres[0], 0.0, atol=1e-15)
        yaw, velocity = _handheld_steps(world)
        assert yaw[0] == pytest.approx(0.0, abs=1e-15)
        relative.append(velocity[:, 2] / forward - 1)
        sideways.append(velocity[:, 0].mean())
        vertical.append(velocity[:, 1])
        turn = np.diff(yaw)
        pans.append(turn.mean())
        shakes.append(turn.std())
    relative = np.concatenate(relative)
    assert abs(relative.mean()) < 0.05
    assert 0.15 < relative.std() < 0.25
    sideways = np.array(sideways)
    assert np.all(np.abs(sideways) < 0.02 + 0.003)
    assert sideways.max() > 0.01 and sideways.min() < -0.01
    assert 0.0015 < np.concatenate(vertical).std() < 0.0025
    pans = np.array(pans)
    assert np.all(np.abs(pans) < 0.005 + 0.0005)
    assert pans.max() > 0.003 and pans.min() < -0.003
    assert 0.0017 < np.mean(shakes) < 0.0023


def _yaw(rotations):
    return Rotation.from_matrix(rotations.reshape(-1, 3, 3)).as_euler("YXZ")[:, 0]


@pytest.fixture(scope="module")
def driving_worlds():
    """45 driving scenes of 6 objects (270 vehicles), 40 frames each."""
    return [_draw("driving", 40, 6, seed) for seed in range(45)]


def test_driving_traffic_mix(driving_worlds):
    """15 % of the vehicles are cyclists (a 0.6 x 1.7 x 1.8 m box, jittered by
    up to 8 %), the others cars (1.8 x 1.5 x 4.2 m); 30 % are oncoming
    (heading at the camera). Binomial counts on 270 vehicles, bounds at about
    4 standard deviations. The street's facades stand 6-15 m to either side."""
    sizes = np.concatenate([w.object_sizes for w in driving_worlds])
    cyclist = sizes[:, 2] < 3.0
    assert np.all(np.abs(sizes[cyclist] / [0.6, 1.7, 1.8] - 1) <= 0.08 + 1e-12)
    assert np.all(np.abs(sizes[~cyclist] / [1.8, 1.5, 4.2] - 1) <= 0.08 + 1e-12)
    jitter = sizes[~cyclist] / [1.8, 1.5, 4.2]  # uniform on [0.92, 1.08]
    assert jitter.min() < 0.93 and jitter.max() > 1.07
    assert 0.15 - 0.09 < cyclist.mean() < 0.15 + 0.09
    yaw = np.concatenate([_yaw(w.object_rotations[:, 0]) for w in driving_worlds])
    oncoming = np.cos(yaw) < 0
    assert 0.3 - 0.11 < oncoming.mean() < 0.3 + 0.11
    walls = np.array([w.walls for w in driving_worlds])
    assert np.all((walls >= 6) & (walls <= 15))
    assert walls.min() < 7 and walls.max() > 14


def test_driving_cars_ahead_drift_slowly_relative_to_the_ego_car(driving_worlds):
    """A car not oncoming keeps its place relative to the ego car, in the
    camera's heading frame: it starts in a lane (+-0.4 m) and drifts at most
    3 cm a frame sideways and 25 cm a frame along the road (either way), with
    smooth noise of 0.1 m and 0.3 m (bounds at 5 standard deviations); it
    never comes nearer than 4 m."""
    slopes = []
    for w in driving_worlds:
        C, Rc = w.camera_centres, w.camera_rotations
        heading = Rotation.from_euler("Y", _yaw(Rc)[:, None]).as_matrix()
        yaw0 = _yaw(w.object_rotations[:, 0])
        frames = np.arange(C.shape[0])
        for k in np.flatnonzero(np.cos(yaw0) > 0):
            offset = w.object_centres[k] - C
            rel = np.einsum("fji,fj->fi", heading, offset)
            assert np.all(rel[:, 2] >= 4.0 - 1e-9)
            lane = np.array([-3.5, 0.0, 3.5])[
                np.argmin(np.abs(rel[0, 0] - [-3.5, 0, 3.5]))
            ]
            drift = np.abs(rel[:, 0] - lane)
            assert np.all(drift <= 0.4 + 0.03 * frames + 0.5)
            slopes.append(np.polyfit(frames, rel[:, [0, 2]], 1)[0])
    slopes = np.array(slopes)
    # slope of a line fitted through the smooth noise: within ~0.03 m/frame
    assert np.all(np.abs(slopes[:, 0]) < 0.03 + 0.02)
    assert np.all(slopes[:, 1] < 0.25 + 0.08)
    assert np.mean(np.abs(slopes[:, 0]) > 0.015) > 0.2
    assert np.mean(slopes[:, 0] > 0) == pytest.approx(0.5, abs=0.15)
    far = slopes[:, 1] > -0.2  # cars falling behind are stopped at 4 m
    assert np.mean(slopes[far, 1] > 0) == pytest.approx(0.55, abs=0.2)
    assert slopes[:, 1].max() > 0.15


def test_driving_vehicles_stand_on_the_road_in_their_lanes(driving_worlds):
    """Every vehicle's box stands on the road, 1.65 m below the camera (its
    height above the road, Notes), in every frame; it starts within 0.4 m of
    its lane's centre line (uniform), ahead (plus a smooth noise of 0.1 m) or
    oncoming (exactly), so the offsets average 0 with either sign."""
    height = 1.65
    offsets = []
    for w in driving_worlds:
        bottom = w.object_centres[..., 1] + w.object_sizes[:, None, 1] / 2
        np.testing.assert_allclose(bottom, height, atol=1e-12)
        # frame 0: the camera at the origin, heading along z
        x = w.object_centres[:, 0, 0]
        lanes = np.array([-3.5, 0.0, 3.5])
        offsets.append(x - lanes[np.argmin(np.abs(x[:, None] - lanes), axis=1)])
    offsets = np.concatenate(offsets)
    assert np.all(np.abs(offsets) < 0.4 + 5 * 0.1)
    # each side jittered on its own: the boxes' proportions vary
    sizes = np.concatenate([w.object_sizes for w in driving_worlds])
    assert np.log(sizes[:, 0] / sizes[:, 2]).std() > 0.03
    assert abs(offsets.mean()) < 0.1
    assert np.mean(offsets > 0) == pytest.approx(0.5, abs=0.15)


def test_driving_oncoming_traffic_facades_and_following_distance(driving_worlds):
    """Oncoming vehicles drive 0.5-1.2 m a frame (uniform) with a smooth noise
    of 5 %, and start at least 6 m apart; a vehicle ahead turns with the road
    plus a random walk of 2e-3 rad a frame, and one falling behind is held
    4 m ahead of the camera. Each facade stands 6-15 m away (uniform: on 45
    scenes, both ends within a metre)."""
    speeds, noise, gaps, nearest, turns, walls = [], [], [], [], [], []
    for w in driving_worlds:
        yaw0 = _yaw(w.object_rotations[:, 0])
        oncoming = np.cos(yaw0) < 0
        speed = np.linalg.norm(np.diff(w.object_centres, axis=1), axis=-1)
        median = np.median(speed[oncoming], axis=1)
        speeds.append(median)
        noise.append((speed[oncoming] / median[:, None] - 1).ravel())
        start = w.object_centres[oncoming, 0]
        gap = np.linalg.norm(start[:, None] - start[None], axis=-1)
        gaps.append(gap[np.triu_indices(len(start), 1)])
        C, camera_yaw = w.camera_centres, _yaw(w.camera_rotations)
        heading = Rotation.from_euler("Y", camera_yaw[:, None]).as_matrix()
        for k in np.flatnonzero(~oncoming):
            rel = np.einsum("fji,fj->fi", heading, w.object_centres[k] - C)
            nearest.append(rel[:, 2].min())
            turns.append(np.diff(_yaw(w.object_rotations[k]) - camera_yaw))
        walls.append(w.walls)
    speeds = np.concatenate(speeds)
    assert np.all((speeds > 0.5 * 0.85) & (speeds < 1.2 * 1.15))
    assert speeds.min() < 0.6 and speeds.max() > 1.1
    assert 0.025 < np.concatenate(noise).std() < 0.07
    assert np.concatenate(gaps).min() >= 6.0
    assert np.any(np.isclose(nearest, 4.0))
    assert 0.0017 < np.concatenate(turns).std() < 0.0023
    walls = np.array(walls)
    assert np.all((walls >= 6) & (walls <= 15))
    assert np.all(walls.min(axis=0) < 7) and np.all(walls.max(axis=0) > 14)


def test_driving_camera_turns_at_most_0_03_rad_a_frame():
    """The car's yaw rate is a random walk (steps of 5e-4 rad a frame, from an
    initial rate of at most 0.004) clipped to +-0.03 rad a frame: on 3,000
    frames the walk reaches the clip."""
    rates = []
    for seed in range(4):
        world = _draw("driving", 3000, 0, seed)
        rates.append(np.diff(np.unwrap(_yaw(world.camera_rotations))))
    rates = np.concatenate(rates)
    assert np.all(np.abs(rates) <= 0.03 + 1e-9)
    assert np.mean(np.abs(rates) > 0.03 - 1e-9) > 0.01


def test_driving_camera_rides_and_steers_smoothly():
    """The car drives ``forward_speed / 10`` m a frame with a smooth (AR(1))
    relative noise of 5 %; its camera bobs 1 cm, pitches 0.003 rad and rolls
    0.002 rad (smooth noises). Its yaw rate starts uniform within 0.004 rad a
    frame (either sign), then walks by steps of 5e-4 rad (40 scenes of 30
    frames: bounds at 4-5 standard deviations)."""
    forward = SCENES["driving"]["forward_speed"] / SCENES["driving"]["frame_rate"]
    first_rates, rate_steps, speeds, bobs, pitches, rolls = [], [], [], [], [], []
    for seed in range(40):
        world = _draw("driving", 30, 0, seed)
        angles = Rotation.from_matrix(world.camera_rotations).as_euler("YXZ")
        rate = np.diff(angles[:, 0])
        first_rates.append(rate[0])
        rate_steps.append(np.diff(rate))
        C = world.camera_centres
        speeds.append(np.linalg.norm(np.diff(C[:, [0, 2]], axis=0), axis=1))
        bobs.append(C[:, 1])
        pitches.append(angles[:, 1])
        rolls.append(angles[:, 2])
    first_rates = np.array(first_rates)
    assert np.all(np.abs(first_rates) < 0.004 + 5 * 5e-4)
    assert first_rates.max() > 0.002 and first_rates.min() < -0.002
    assert abs(first_rates.mean()) < 0.0013
    assert np.concatenate(rate_steps).std() == pytest.approx(5e-4, rel=0.1)
    relative = np.concatenate(speeds) / forward - 1
    assert abs(relative.mean()) < 0.02
    assert 0.035 < relative.std() < 0.065
    assert 0.0075 < np.concatenate(bobs).std() < 0.0125
    assert 0.0022 < np.concatenate(pitches).std() < 0.0038
    assert 0.0015 < np.concatenate(rolls).std() < 0.0025


@pytest.mark.parametrize("axis", [0, 1])
def test_in_view_at_start_keeps_a_tenth_of_the_image_as_margin(axis):
    """A camera-frame point is in view at the start when it is in front of the
    camera and projects inside the central 90 % of the image in x and y; a
    point on the camera's plane is not, without a division warning."""
    size, f, z = (1000.0, 500.0), 800.0, 10.0
    inside, outside = np.zeros(3), np.zeros(3)
    inside[2] = outside[2] = z
    inside[axis] = 0.89 * size[axis] / 2 * z / f
    outside[axis] = 0.91 * size[axis] / 2 * z / f
    assert _in_view_at_start(inside, f, size)
    assert _in_view_at_start(-inside * [1, 1, -1], f, size)
    assert not _in_view_at_start(outside, f, size)
    assert not _in_view_at_start(-outside * [1, 1, -1], f, size)
    assert not _in_view_at_start(inside * [1, 1, -1], f, size)
    # any depth in front counts, however near
    assert _in_view_at_start(inside * 0.01, f, size)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert not _in_view_at_start(np.zeros(3), f, size)


@pytest.fixture(scope="module")
def handheld_subjects():
    """Subjects of 60 hand-held scenes of 3 objects, 40 frames each."""
    return [_draw("handheld", 40, 3, seed) for seed in range(60)]


def test_handheld_subjects_walk_at_their_kind_s_speed(handheld_subjects):
    """A subject moves at a speed uniform on its kind's range (metres a frame:
    person 0.03-0.06, animal 0.03-0.15, cyclist 0.05-0.15, car 0.05-0.2),
    times a smooth noise of 10 %, in a heading uniform on the circle."""
    ranges = {0.3: (0.03, 0.06), 1.0: (0.03, 0.15), 1.8: (0.05, 0.15), 4.2: (0.05, 0.2)}
    ratios, headings = [], []
    for w in handheld_subjects:
        speed = np.linalg.norm(np.diff(w.object_centres, axis=1), axis=-1)
        for k, length in enumerate(w.object_sizes[:, 2]):
            base = min(ranges, key=lambda b: abs(b - length))
            low, high = ranges[base]
            ratios.append((np.median(speed[k]) - low) / (high - low))
        headings.append(_yaw(w.object_rotations[:, 0]))
    ratios = np.array(ratios)  # where the speed falls in its range
    assert np.all((ratios > -0.5) & (ratios < 1.5))
    assert ratios.min() < 0.1 and ratios.max() > 0.9
    assert np.mean(ratios < 0.5) == pytest.approx(0.5, abs=0.15)
    quarter = np.floor(np.mod(np.concatenate(headings), 2 * np.pi) / (np.pi / 2))
    assert np.all(np.bincount(quarter.astype(int), minlength=4) > 0.15 * len(ratios))
    assert np.mean(quarter < 2) == pytest.approx(0.5, abs=0.1)


def test_handheld_subjects_stand_on_the_ground_ahead_of_the_camera(handheld_subjects):
    """A subject is a person (half of them), an animal (a fifth), a cyclist or
    a car (15 % each), told apart by their length (0.3, 1, 1.8, 4.2 m,
    jittered by 8 %); it stands on the ground, 1.5 m below the camera, in
    every frame; it starts 5-20 m ahead (uniform: both ends within a metre),
    within 0.6 of the half field of view of the centre, on either side."""
    p = SCENES["handheld"]
    half_fov = p["image_size"][0] / 2 / p["focal_length"]
    lengths, depth, across = [], [], []
    for w in handheld_subjects:
        bottom = w.object_centres[..., 1] + w.object_sizes[:, None, 1] / 2
        np.testing.assert_allclose(bottom, 1.5, atol=1e-12)
        lengths.append(w.object_sizes[:, 2])
        # frame 0: the camera at the origin, heading along z
        depth.append(w.object_centres[:, 0, 2])
        across.append(w.object_centres[:, 0, 0] / w.object_centres[:, 0, 2] / half_fov)
    lengths, depth, across = map(np.concatenate, (lengths, depth, across))
    kind = np.argmin(np.abs(lengths[:, None] - [0.3, 1.0, 1.8, 4.2]), axis=1)
    shares = np.bincount(kind, minlength=4) / kind.size
    np.testing.assert_allclose(shares, [0.5, 0.2, 0.15, 0.15], atol=0.1)
    assert np.all((depth >= 5) & (depth <= 20))
    assert depth.min() < 6 and depth.max() > 19
    assert np.all(np.abs(across) <= 0.6)
    assert across.min() < -0.5 and across.max() > 0.5


def test_handheld_camera_pans_to_keep_the_subject_in_the_middle_third(
    handheld_subjects,
):
    """The operator pans by a tenth of the subject's angle beyond the middle
    third of the view (the dead zone, a third of the half field of view),
    plus a shake of 0.002 rad: what the yaw does beyond that is the shake."""
    p = SCENES["handheld"]
    dead_zone = p["image_size"][0] / 2 / p["focal_length"] / 3
    shakes, steering = [], []
    for w in handheld_subjects:
        C, To = w.camera_centres, w.object_centres[0]
        yaw = Rotation.from_matrix(w.camera_rotations).as_euler("YXZ")[:, 0]
        offset = To[:-1] - C[:-1]
        bearing = np.arctan2(offset[:, 0], offset[:, 2])
        off_centre = np.angle(np.exp(1j * (bearing - yaw[:-1])))
        excess = np.sign(off_centre) * np.maximum(np.abs(off_centre) - dead_zone, 0)
        shakes.append(np.diff(yaw) - 0.1 * excess)
        steering.append(excess != 0)
    shakes, steering = np.concatenate(shakes), np.concatenate(steering)
    assert steering.mean() > 0.05  # the controller is exercised
    assert abs(shakes.mean()) < 3e-4
    assert 0.0017 < shakes.std() < 0.0023


def test_switching_outliers_leave_motions_in_their_shares():
    """A drift or jump outlier starts on a motion drawn in proportion to the
    motions' shares of inlier tracks, and switches to another motion, drawn
    in proportion to the shares of the others (module docstring). Complete
    tracks on 10 frames: the switch falls uniformly after frame 1 .. F - 4,
    leaving two frames each side. Binomial bounds at about 5 standard
    deviations."""
    n_frames, sources, switches = 10, [], []
    for seed in range(4):
        _X, y, info = make_tracks(
            scene="lab",
            n_motions=3,
            n_tracks=400,
            n_frames=n_frames,
            background_fraction=0.6,
            outlier_fraction=0.5,
            random_state=seed,
            return_info=True,
        )
        switching = np.isin(info.kind, ["drift", "jump"])
        shares = np.bincount(y[y >= 0], minlength=3) / np.sum(y >= 0)
        first, second = info.source_motions[switching].T
        assert np.all(first != second)
        sources.append((first, second, shares))
        switches.append(info.switch_frame[switching])
    first = np.concatenate([s[0] for s in sources])
    second = np.concatenate([s[1] for s in sources])
    shares = np.mean([s[2] for s in sources], axis=0)
    n = first.size
    for k in range(3):
        assert abs(np.mean(first == k) - shares[k]) < 5 * np.sqrt(0.25 / n)
    # from the background (share 0.6), the two objects equally often
    from_background = second[first == 0]
    expected = shares[1] / (shares[1] + shares[2])
    assert abs(np.mean(from_background == 1) - expected) < 5 * np.sqrt(
        0.25 / from_background.size
    )
    switches = np.concatenate(switches)
    counts = np.bincount(switches, minlength=n_frames)
    assert counts[0] == 0 and np.all(counts[n_frames - 3 :] == 0)
    assert np.all(counts[1 : n_frames - 3] > 0.5 * n / (n_frames - 4))


def test_random_walks_move_at_the_typical_step_in_every_frame():
    """A random walk's velocity is AR(1) (memory 0.8, shocks 0.6 of the step),
    started from its stationary law (standard deviation the step): every
    displacement has the step as standard deviation, and consecutive ones a
    correlation of 0.8. Far from the borders, no reflection."""
    step, n, n_frames = 2.0, 4000, 6
    camera = Bunch(width=1e7, height=1e7)
    births = np.zeros(n, dtype=np.int64)
    pixels, in_view, visible = _random_walks(
        births, step, camera, n_frames, np.random.default_rng(0)
    )
    assert in_view.all() and visible.all()
    moves = np.diff(pixels, axis=1)
    sd = moves.std(axis=(0, 2))
    np.testing.assert_allclose(sd, step, rtol=0.06)
    lag = np.mean(moves[:, 1:] * moves[:, :-1]) / np.mean(moves**2)
    assert lag == pytest.approx(0.8, abs=0.03)


def test_smooth_noise_is_stationary_with_the_given_scale():
    """AR(1) noise with memory ``m`` and shocks of ``scale sqrt(1 - m^2)``,
    started from its stationary law: every frame has standard deviation
    ``scale``, consecutive frames a correlation ``m``."""
    rng = np.random.default_rng(0)
    values = np.array([_smooth_noise(rng, 6, 0.5) for _ in range(4000)])
    np.testing.assert_allclose(values.std(axis=0), 0.5, rtol=0.06)
    lag = np.mean(values[:, 1:] * values[:, :-1]) / np.mean(values**2)
    assert lag == pytest.approx(0.9, abs=0.02)


def test_box_corners_are_the_eight_corners_of_the_centred_box():
    corners = _box_corners((2.0, 4.0, 6.0))
    expected = [[x, y, z] for x in (-1, 1) for y in (-2, 2) for z in (-3, 3)]
    assert sorted(map(tuple, corners)) == sorted(map(tuple, expected))


@pytest.mark.parametrize("scene", ["lab", "handheld"])
def test_object_points_lie_on_their_box_and_observed_points_in_the_image(scene):
    """Object tracks are points of the faces of their box (Notes: "uniformly
    on the visible faces"): inside the box, on a face. Every observed point,
    outliers' too, is inside the image (a track is lost when it leaves it)."""
    X, y, info = make_tracks(
        scene=scene,
        n_tracks=300,
        n_frames=15,
        outlier_fraction=0.2,
        noise=0.0,
        units="pixels",
        random_state=1,
        return_info=True,
    )
    for k, size in enumerate(info.object_sizes, start=1):
        reach = np.abs(info.points[y == k]) / (size / 2)
        assert np.all(reach <= 1 + 1e-9)
        np.testing.assert_allclose(reach.max(axis=1), 1.0, atol=1e-9)
    width, height = info.image_size
    x, v = X[:, 0::2], X[:, 1::2]
    seen = ~np.isnan(x)
    assert np.all((x[seen] >= 0) & (x[seen] <= width))
    assert np.all((v[seen] >= 0) & (v[seen] <= height))


def test_image_size_and_depths_take_any_real_numbers():
    from fractions import Fraction

    X, _y, info = make_tracks(
        scene="lab",
        n_tracks=60,
        n_frames=5,
        image_size=(Fraction(640), Fraction(480)),
        depth_range=(Fraction(2), Fraction(7, 2)),
        random_state=0,
        return_info=True,
    )
    assert info.image_size == (640.0, 480.0)
    assert info.params["depth_range"] == (2.0, 3.5)
    assert np.isfinite(X).all()
