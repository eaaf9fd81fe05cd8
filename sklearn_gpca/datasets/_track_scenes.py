"""3-D scenes for :func:`make_tracks`: camera paths, moving objects, presets.

Coordinates follow the computer-vision convention: x right, y down, z along
the optical axis, in metres; the world frame is the camera's at frame 0. A
scene is a camera path (rotation ``Rc[f]``, camera to world, and centre
``C[f]``) and one rigid pose per moving object (``Ro[k, f]``, object to world,
and centre ``To[k, f]``). The static background is the world itself.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
from scipy.spatial.transform import Rotation, Slerp
from sklearn.utils import Bunch

#: Defaults of each scene, beside the real dataset it imitates. Numbers marked
#: "verified" were checked against the source named in the docstring of
#: :func:`make_tracks`; the others are estimates (see its Notes).
SCENES = {
    # KT3DMoSeg (Xu, Cheong & Li, CVPR 2018): KITTI driving clips.
    "driving": {
        "n_motions": 3,
        "n_tracks": 500,
        "n_frames": 20,  # verified: 10-20 frames per clip
        "background_fraction": 0.75,
        "outlier_fraction": 0.05,
        "missing": None,
        "mean_lifetime": 40.0,
        "image_size": (1242, 375),  # verified: KITTI rectified images
        "focal_length": 721.5,  # verified: KITTI P_rect_02
        "depth_range": (8.0, 80.0),
        "forward_speed": 8.0,  # metres per second: 29 km/h
        "frame_rate": 10.0,  # verified: KITTI records at 10 Hz
        "noise": 0.5,
    },
    # FBMS-59 (Ochs, Malik & Brox, PAMI 2014): hand-held and film footage.
    "handheld": {
        "n_motions": 3,
        "n_tracks": 800,
        "n_frames": 100,
        "background_fraction": 0.75,
        "outlier_fraction": 0.03,
        "missing": 0.5,
        "mean_lifetime": None,
        "image_size": (640, 480),
        "focal_length": 600.0,
        "depth_range": (3.0, 40.0),
        "forward_speed": 0.6,
        "frame_rate": 30.0,
        "noise": 0.5,
    },
    # Hopkins155 (Tron & Vidal, CVPR 2007): complete tracks, weak perspective.
    "lab": {
        "n_motions": 2,  # verified: 120 of the 155 sequences
        "n_tracks": 300,  # verified: mean 296 points
        "n_frames": 30,  # verified: mean 29.4 frames
        "background_fraction": 0.65,  # verified: median largest-group share
        "outlier_fraction": 0.0,
        "missing": 0.0,
        "mean_lifetime": None,
        "image_size": (640, 480),  # verified
        "focal_length": 800.0,
        "depth_range": (2.0, 3.5),
        "forward_speed": 0.0,
        "frame_rate": 30.0,
        "noise": 0.25,
    },
}

#: Frame rate (per second) at which each scene's motions are drawn; other
#: frame rates resample the same motions.
NATIVE_RATE = {scene: SCENES[scene]["frame_rate"] for scene in SCENES}

#: Height of the camera above the ground plane (metres): KITTI's camera rig
#: for "driving", eye level for "handheld"; "lab" scenes have no ground.
CAMERA_HEIGHT = {"driving": 1.65, "handheld": 1.5, "lab": None}

# Box sizes (width x, height y, length z) in metres, and speeds in metres per
# frame of the "handheld" scene's subjects (30 frames per second).
_HANDHELD_SUBJECTS = {
    "person": ((0.5, 1.75, 0.3), (0.03, 0.06)),
    "animal": ((0.4, 0.8, 1.0), (0.03, 0.15)),
    "cyclist": ((0.6, 1.7, 1.8), (0.05, 0.15)),
    "car": ((1.8, 1.5, 4.2), (0.05, 0.2)),
}
_CAR = (1.8, 1.5, 4.2)
_CYCLIST = (0.6, 1.7, 1.8)


def _smooth_noise(rng, n_frames, scale, memory=0.9):
    """AR(1) sequence with stationary standard deviation ``scale``."""
    shocks = rng.normal(scale=scale * np.sqrt(1 - memory**2), size=n_frames)
    values = np.empty(n_frames)
    values[0] = rng.normal(scale=scale)
    for f in range(1, n_frames):
        values[f] = memory * values[f - 1] + shocks[f]
    return values


def _yaw_matrices(yaw):
    return Rotation.from_euler("Y", np.reshape(yaw, (-1, 1))).as_matrix()


def _integrate(start, velocities):
    """Positions from a start and per-frame velocities (the last is unused)."""
    steps = np.cumsum(velocities[:-1], axis=0)
    return np.vstack([start, start + steps])


def _jitter(sizes, rng, spread=0.08):
    return np.asarray(sizes) * rng.uniform(1 - spread, 1 + spread, size=3)


def _in_view_at_start(centre, focal_length, image_size, margin=0.9):
    """Whether a camera-frame point at frame 0 projects inside the image."""
    if centre[2] <= 0:
        return False
    half = np.asarray(image_size) / 2
    return bool(np.all(np.abs(focal_length * centre[:2] / centre[2]) < margin * half))


def _separated(centres, new, distance):
    return all(np.linalg.norm(new - c) >= distance for c in centres)


def _driving(n_frames, n_objects, forward_speed, focal_length, image_size, rng):
    """Car-mounted camera driving forward; cars ahead, beside and oncoming."""
    height = CAMERA_HEIGHT["driving"]
    yaw_rate = np.clip(
        rng.uniform(-0.004, 0.004) + np.cumsum(rng.normal(0, 5e-4, n_frames)),
        -0.03,
        0.03,
    )
    yaw = np.concatenate([[0.0], np.cumsum(yaw_rate[:-1])])
    pitch = _smooth_noise(rng, n_frames, 0.003)
    roll = _smooth_noise(rng, n_frames, 0.002)
    Rc = Rotation.from_euler("YXZ", np.column_stack([yaw, pitch, roll])).as_matrix()
    speed = np.maximum(forward_speed * (1 + _smooth_noise(rng, n_frames, 0.05)), 0)
    heading = np.column_stack([np.sin(yaw), np.zeros(n_frames), np.cos(yaw)])
    C = _integrate(np.zeros(3), speed[:, None] * heading)
    C[:, 1] += _smooth_noise(rng, n_frames, 0.01)

    dims, Ro, To, centres = [], [], [], []
    for _ in range(n_objects):
        for _attempt in range(1000):
            size = _jitter(_CYCLIST if rng.uniform() < 0.15 else _CAR, rng)
            oncoming = rng.uniform() < 0.3
            lane = -3.5 if oncoming else rng.choice([-3.5, 0.0, 3.5])
            start = np.array(
                [
                    lane + rng.uniform(-0.4, 0.4),
                    height - size[1] / 2,
                    rng.uniform(15, 45) if oncoming else rng.uniform(8, 30),
                ]
            )
            if _in_view_at_start(start, focal_length, image_size) and _separated(
                centres, start, 6.0
            ):
                break
        centres.append(start)
        dims.append(size)
        if oncoming:
            own_speed = rng.uniform(0.5, 1.2) * (1 + _smooth_noise(rng, n_frames, 0.05))
            obj_yaw = (
                np.pi + rng.normal(0, 0.02) + np.cumsum(rng.normal(0, 2e-3, n_frames))
            )
            direction = np.column_stack(
                [np.sin(obj_yaw), np.zeros(n_frames), np.cos(obj_yaw)]
            )
            centre = _integrate(start, own_speed[:, None] * direction)
        else:
            # Position relative to the ego car, in its heading frame: a slow
            # drift (overtaking, falling behind, changing lane).
            rel_velocity = np.array(
                [rng.uniform(-0.03, 0.03), 0.0, rng.uniform(-0.25, 0.25)]
            )
            rel = start + np.arange(n_frames)[:, None] * rel_velocity
            rel[:, 0] += _smooth_noise(rng, n_frames, 0.1)
            rel[:, 2] += _smooth_noise(rng, n_frames, 0.3)
            rel[:, 2] = np.maximum(rel[:, 2], 4.0)
            centre = np.einsum("fij,fj->fi", _yaw_matrices(yaw), rel)
            centre[:, [0, 2]] += C[:, [0, 2]]
            centre[:, 1] = start[1]
            obj_yaw = yaw + np.cumsum(rng.normal(0, 2e-3, n_frames))
        Ro.append(_yaw_matrices(obj_yaw))
        To.append(centre)
    # Street facades (metres to the left and to the right of the camera).
    walls = (rng.uniform(6, 15), rng.uniform(6, 15))
    return _scene(Rc, C, dims, Ro, To, height, walls)


def _handheld(n_frames, n_objects, forward_speed, focal_length, image_size, rng):
    """Hand-held camera that pans to follow a walking, riding or driving subject."""
    height = CAMERA_HEIGHT["handheld"]
    half_fov = image_size[0] / 2 / focal_length
    dims, Ro, To, centres = [], [], [], []
    kinds = list(_HANDHELD_SUBJECTS)
    for _ in range(n_objects):
        kind = kinds[rng.choice(len(kinds), p=[0.5, 0.2, 0.15, 0.15])]
        base_size, (low, high) = _HANDHELD_SUBJECTS[kind]
        for _attempt in range(1000):
            size = _jitter(base_size, rng)
            depth = rng.uniform(5, 20)
            start = np.array(
                [depth * rng.uniform(-0.6, 0.6) * half_fov, height - size[1] / 2, depth]
            )
            if _separated(centres, start, 1.5 + size[2]):
                break
        centres.append(start)
        dims.append(size)
        speed = rng.uniform(low, high) * (1 + _smooth_noise(rng, n_frames, 0.1))
        obj_yaw = rng.uniform(0, 2 * np.pi) + np.cumsum(
            rng.uniform(-0.01, 0.01) + rng.normal(0, 3e-3, n_frames)
        )
        direction = np.column_stack(
            [np.sin(obj_yaw), np.zeros(n_frames), np.cos(obj_yaw)]
        )
        To.append(_integrate(start, speed[:, None] * direction))
        Ro.append(_yaw_matrices(obj_yaw))

    lateral = rng.uniform(-0.02, 0.02)
    velocity = np.column_stack(
        [
            lateral + _smooth_noise(rng, n_frames, 0.003),
            _smooth_noise(rng, n_frames, 0.002),
            forward_speed * (1 + _smooth_noise(rng, n_frames, 0.2)),
        ]
    )
    yaw = np.empty(n_frames)
    yaw[0] = 0.0
    pan = rng.uniform(-0.005, 0.005)
    dead_zone = half_fov / 3
    C = np.zeros((n_frames, 3))
    for f in range(1, n_frames):
        C[f] = C[f - 1] + _yaw_matrices(yaw[f - 1]) @ velocity[f - 1]
        if n_objects:
            # Keep the first subject in the middle third of the image with a
            # lagging pan, as a camera operator does.
            offset = To[0][f - 1] - C[f - 1]
            bearing = np.arctan2(offset[0], offset[2])
            off_centre = np.angle(np.exp(1j * (bearing - yaw[f - 1])))
            excess = np.sign(off_centre) * max(abs(off_centre) - dead_zone, 0.0)
            step = 0.1 * excess
        else:
            step = pan
        yaw[f] = yaw[f - 1] + step + rng.normal(0, 0.002)
    pitch = _smooth_noise(rng, n_frames, 0.01)
    roll = _smooth_noise(rng, n_frames, 0.01)
    Rc = Rotation.from_euler("YXZ", np.column_stack([yaw, pitch, roll])).as_matrix()
    return _scene(Rc, C, dims, Ro, To, height)


def _lab(n_frames, n_objects, forward_speed, focal_length, image_size, rng, depths):
    """Objects turning and sliding in front of a slowly moving camera."""
    half = np.asarray(image_size) / 2 / focal_length
    dims, Ro, To, centres = [], [], [], []
    for _ in range(n_objects):
        for _attempt in range(1000):
            size = rng.uniform(0.1, 0.3, size=3)
            depth = rng.uniform(*depths)
            start = np.array(
                [
                    depth * rng.uniform(-0.5, 0.5) * half[0],
                    depth * rng.uniform(-0.5, 0.5) * half[1],
                    depth,
                ]
            )
            if _separated(centres, start, 0.4):
                break
        centres.append(start)
        dims.append(size)
        direction = rng.normal(size=3)
        direction[2] *= 0.3
        velocity = rng.uniform(0.003, 0.015) * direction / np.linalg.norm(direction)
        To.append(start + np.arange(n_frames)[:, None] * velocity)
        axis = rng.normal(size=3)
        rate = rng.uniform(0.01, 0.04) * axis / np.linalg.norm(axis)
        spin = Rotation.from_rotvec(np.arange(n_frames)[:, None] * rate)
        Ro.append((spin * Rotation.random(random_state=rng)).as_matrix())

    direction = rng.normal(size=3)
    direction[2] = 0.0
    velocity = rng.uniform(0.002, 0.01) * direction / np.linalg.norm(direction)
    velocity[2] = forward_speed
    C = np.arange(n_frames)[:, None] * velocity
    rates = rng.uniform(-0.003, 0.003, size=2)
    angles = np.column_stack(
        [
            rates[0] * np.arange(n_frames),
            rates[1] * np.arange(n_frames),
            _smooth_noise(rng, n_frames, 0.002),
        ]
    )
    Rc = Rotation.from_euler("YXZ", angles).as_matrix()
    return _scene(Rc, C, dims, Ro, To, None)


def _scene(Rc, C, dims, Ro, To, height, walls=None):
    n_frames = Rc.shape[0]
    return Bunch(
        camera_rotations=Rc,
        camera_centres=C,
        object_sizes=np.array(dims, dtype=float).reshape(-1, 3),
        object_rotations=np.array(Ro, dtype=float).reshape(-1, n_frames, 3, 3),
        object_centres=np.array(To, dtype=float).reshape(-1, n_frames, 3),
        ground_height=height,
        walls=walls,
    )


def _resample(rotations, centres, times):
    """Poses at fractional native frames: Slerp rotations, linear centres."""
    native = np.arange(centres.shape[0])
    rotations = Slerp(native, Rotation.from_matrix(rotations))(times).as_matrix()
    centres = np.column_stack([np.interp(times, native, c) for c in centres.T])
    return rotations, centres


def make_scene(
    scene,
    n_frames,
    n_objects,
    forward_speed,
    focal_length,
    image_size,
    depth_range,
    frame_rate,
    rng,
):
    """Camera path and object poses of one draw of ``scene``, ``n_frames``
    frames at ``frame_rate`` per second (``forward_speed`` in metres per
    second).

    The scene is drawn at its native rate (``NATIVE_RATE``) and its poses are
    resampled at the requested one.
    """
    native_rate = NATIVE_RATE[scene]
    step = native_rate / frame_rate
    n_native = int(np.floor((n_frames - 1) * step)) + 2
    speed = forward_speed / native_rate
    if scene == "driving":
        world = _driving(n_native, n_objects, speed, focal_length, image_size, rng)
    elif scene == "handheld":
        world = _handheld(n_native, n_objects, speed, focal_length, image_size, rng)
    else:
        world = _lab(
            n_native, n_objects, speed, focal_length, image_size, rng, depth_range
        )
    times = np.arange(n_frames) * step
    world.camera_rotations, world.camera_centres = _resample(
        world.camera_rotations, world.camera_centres, times
    )
    rotations, centres = [], []
    for Ro, To in zip(world.object_rotations, world.object_centres, strict=True):
        Ro, To = _resample(Ro, To, times)
        rotations.append(Ro)
        centres.append(To)
    world.object_rotations = np.array(rotations).reshape(-1, n_frames, 3, 3)
    world.object_centres = np.array(centres).reshape(-1, n_frames, 3)
    return world
