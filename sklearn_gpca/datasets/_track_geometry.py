"""Projection, visibility and point sampling for :func:`make_tracks`.

Motion 0 is the static background (its points are in world coordinates);
motion ``k >= 1`` is object ``k - 1`` (its points are in the object's frame,
on the surface of its box).
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
from scipy.spatial import ConvexHull, QhullError
from sklearn.utils import Bunch


class UnseenMotionError(ValueError):
    """A motion of the drawn scene is (almost) never visible."""


# Rounds of rejection sampling before a motion is declared invisible.
_MAX_ROUNDS = 20
# Most candidate points drawn in one round of rejection sampling.
_MAX_CANDIDATES = 200_000
# Density of features on the ground relative to the rest of the background
# (an estimate: asphalt is poorly textured, lane markings and kerbs are not).
_ROAD_TEXTURE = 0.3


def make_camera(kind, focal_length, image_size, depth_range, scene):
    """Camera intrinsics and, for the affine camera, per-motion reference depths.

    The affine camera is weak perspective: motion ``k`` in frame ``f`` is
    projected with the scale ``focal_length / zref[k, f]``, where ``zref`` is
    the depth of the object's centre (objects) or the geometric mean of
    ``depth_range`` (background). Each motion is then exactly affine.
    """
    width, height = (float(s) for s in image_size)
    near = 0.25 * depth_range[0]
    n_frames = scene.camera_rotations.shape[0]
    zref = np.full(
        (1 + scene.object_sizes.shape[0], n_frames), np.sqrt(np.prod(depth_range))
    )
    for j in range(scene.object_sizes.shape[0]):
        centre = _to_camera(np.zeros((1, 3)), scene, j + 1)[0]
        zref[j + 1] = np.maximum(centre[:, 2], near)
    return Bunch(
        kind=kind,
        focal_length=float(focal_length),
        width=width,
        height=height,
        centre=np.array([width / 2, height / 2]),
        near=near,
        zref=zref,
    )


def motion_poses(scene, motion):
    """Rotations (F, 3, 3) and translations (F, 3), motion frame to world."""
    n_frames = scene.camera_rotations.shape[0]
    if motion == 0:
        return np.broadcast_to(np.eye(3), (n_frames, 3, 3)), np.zeros((n_frames, 3))
    return scene.object_rotations[motion - 1], scene.object_centres[motion - 1]


def _to_camera(points, scene, motion):
    """Camera coordinates (n, F, 3) of motion-frame points (n, 3) in every frame."""
    Ro, To = motion_poses(scene, motion)
    world = np.einsum("fij,nj->nfi", Ro, points) + To
    return np.einsum(
        "fji,nfj->nfi", scene.camera_rotations, world - scene.camera_centres
    )


def project(cam_points, camera, motion):
    """Pixels (..., F, 2) of camera coordinates (..., F, 3); NaN behind the camera
    (perspective camera only: the affine camera projects every point)."""
    depth = cam_points[..., 2]
    if camera.kind == "perspective":
        with np.errstate(divide="ignore", invalid="ignore"):
            pixels = camera.focal_length * cam_points[..., :2] / depth[..., None]
        pixels[depth <= camera.near] = np.nan
    else:
        scale = camera.focal_length / camera.zref[motion]
        pixels = cam_points[..., :2] * scale[:, None]
    return pixels + camera.centre


def in_image(pixels, camera):
    with np.errstate(invalid="ignore"):
        return (
            (pixels[..., 0] >= 0)
            & (pixels[..., 0] < camera.width)
            & (pixels[..., 1] >= 0)
            & (pixels[..., 1] < camera.height)
        )


def _box_corners(size):
    signs = np.array(np.meshgrid([-1, 1], [-1, 1], [-1, 1])).reshape(3, -1).T
    return signs * np.asarray(size) / 2


def make_occluders(scene, camera):
    """Image silhouette (convex hull of the box's corners) of every object.

    ``occluders[j][f]`` is ``(equations, depth)`` with the hull's half-planes
    ``a u + b v + c <= 0`` and the depth of the object's centre, or None where a
    corner is behind the camera.
    """
    occluders = []
    for j, size in enumerate(scene.object_sizes):
        corners = _to_camera(_box_corners(size), scene, j + 1)
        pixels = project(corners, camera, j + 1)
        centre_depth = _to_camera(np.zeros((1, 3)), scene, j + 1)[0, :, 2]
        per_frame = []
        for f in range(corners.shape[1]):
            if np.any(corners[:, f, 2] <= camera.near):
                per_frame.append(None)
                continue
            try:
                hull = ConvexHull(pixels[:, f])
            except QhullError:
                per_frame.append(None)
                continue
            per_frame.append((hull.equations, centre_depth[f]))
        occluders.append(per_frame)
    return occluders


def visibility(cam_points, pixels, normals, motion, occluders, camera, scene):
    """``in_view`` (in front, inside the image) and ``visible`` (also facing the
    camera and not hidden by another object), both (n, F)."""
    depth = cam_points[..., 2]
    in_view = (depth > camera.near) & in_image(pixels, camera)
    visible = in_view.copy()
    if normals is not None:
        Ro, _ = motion_poses(scene, motion)
        world_normals = np.einsum("fij,nj->nfi", Ro, normals)
        cam_normals = np.einsum("fji,nfj->nfi", scene.camera_rotations, world_normals)
        visible &= np.einsum("nfi,nfi->nf", cam_normals, cam_points) < 0
    for j, per_frame in enumerate(occluders):
        if j + 1 == motion:
            continue
        for f, occluder in enumerate(per_frame):
            if occluder is None:
                continue
            equations, occluder_depth = occluder
            candidates = np.flatnonzero(visible[:, f] & (depth[:, f] > occluder_depth))
            if candidates.size == 0:
                continue
            sides = pixels[candidates, f] @ equations[:, :2].T + equations[:, 2]
            visible[candidates[np.all(sides <= 0, axis=1)], f] = False
    return in_view, visible


def _background_candidates(births, camera, scene, depth_range, rng):
    """World points seen at a uniform pixel and a log-uniform depth at birth."""
    n = births.size
    pixels = rng.uniform(0, 1, size=(n, 2)) * [camera.width, camera.height]
    depth = np.exp(rng.uniform(*np.log(depth_range), size=n))
    rays = np.column_stack([(pixels - camera.centre) / camera.focal_length, np.ones(n)])
    Rc = scene.camera_rotations[births]
    C = scene.camera_centres[births]
    world_rays = np.einsum("nij,nj->ni", Rc, rays)
    keep = np.ones(n, dtype=bool)
    with np.errstate(divide="ignore", invalid="ignore"):
        if scene.ground_height is not None:
            # Nothing lies below the ground: stop the ray on the road.
            down = world_rays[:, 1]
            ground = (scene.ground_height - C[:, 1]) / down
            on_road = (down > 0) & (ground < depth)
            depth = np.where(on_road, ground, depth)
            # Asphalt has little texture: a tracker finds fewer features there.
            keep &= ~on_road | (rng.uniform(size=n) < _ROAD_TEXTURE)
        if scene.walls is not None:
            # Street facades on either side, parallel to the camera's heading.
            left, right = scene.walls
            side = rays[:, 0]
            wall = np.where(side < 0, -left / side, right / side)
            depth = np.where((side != 0) & (wall < depth), wall, depth)
    if camera.kind == "perspective":
        cam = rays * depth[:, None]
    else:
        lateral = (pixels - camera.centre) * camera.zref[0, births][:, None]
        cam = np.column_stack([lateral / camera.focal_length, depth])
    return np.einsum("nij,nj->ni", Rc, cam) + C, keep


def _object_candidates(size, n, rng):
    """Points uniformly on the surface of a box, with outward normals."""
    size = np.asarray(size, dtype=float)
    areas = np.array([size[1] * size[2], size[0] * size[2], size[0] * size[1]])
    axis = rng.choice(3, size=n, p=areas / areas.sum())
    side = rng.choice([-1.0, 1.0], size=n)
    points = (rng.uniform(-0.5, 0.5, size=(n, 3))) * size
    points[np.arange(n), axis] = side * size[axis] / 2
    normals = np.zeros((n, 3))
    normals[np.arange(n), axis] = side
    return points, normals


def track_geometry(points, normals, motion, occluders, camera, scene):
    """Pixels, depths, ``in_view`` and ``visible`` of motion points in every frame."""
    cam_points = _to_camera(points, scene, motion)
    pixels = project(cam_points, camera, motion)
    in_view, visible = visibility(
        cam_points, pixels, normals, motion, occluders, camera, scene
    )
    return Bunch(
        points=points,
        pixels=pixels,
        depth=cam_points[..., 2],
        in_view=in_view,
        visible=visible,
    )


def visible_share(motion, occluders, camera, scene, rng, n_probes=256):
    """Share of an object's surface visible in each frame (F,), and visible in
    every frame (a float), from probe points.

    A tracker finds features on what it sees: births of an object's tracks
    are drawn in proportion to the first; complete tracks need the second.
    """
    probes, normals = _object_candidates(scene.object_sizes[motion - 1], n_probes, rng)
    geometry = track_geometry(probes, normals, motion, occluders, camera, scene)
    return geometry.visible.mean(axis=0), geometry.visible.all(axis=1).mean()


def sample_points(
    motion, births, complete, occluders, camera, scene, depth_range, rng, strict=True
):
    """Points of ``motion`` visible at their birth frame (every frame if complete).

    Rejection sampling, vectorised over the points still missing. Where no
    visible point is found, raise a ``ValueError`` if ``strict``, else leave
    the point NaN and False in the returned ``found``.
    """
    n = births.size
    points = np.empty((n, 3))
    normals = np.empty((n, 3)) if motion else None
    todo = np.arange(n)
    for attempt in range(_MAX_ROUNDS if strict else _MAX_ROUNDS // 4):
        if todo.size == 0:
            break
        # Several candidates per missing point, more each round, for motions
        # of which little is seen.
        reps = int(min(2**attempt, 64, max(1, _MAX_CANDIDATES // todo.size)))
        slots = np.repeat(todo, reps)
        if motion == 0:
            candidates, keep = _background_candidates(
                births[slots], camera, scene, depth_range, rng
            )
            cand_normals = None
        else:
            candidates, cand_normals = _object_candidates(
                scene.object_sizes[motion - 1], slots.size, rng
            )
            keep = True
        geometry = track_geometry(
            candidates, cand_normals, motion, occluders, camera, scene
        )
        if complete:
            ok = geometry.visible.all(axis=1)
        else:
            ok = geometry.visible[np.arange(slots.size), births[slots]]
        ok = (ok & keep).reshape(todo.size, reps)
        found = ok.any(axis=1)
        chosen = np.arange(todo.size) * reps + ok.argmax(axis=1)
        points[todo[found]] = candidates[chosen[found]]
        if motion:
            normals[todo[found]] = cand_normals[chosen[found]]
        todo = todo[~found]
    if todo.size and not strict:
        points[todo] = 0.0
        if motion:
            normals[todo] = 0.0
    elif todo.size:
        where = "in every frame" if complete else "at the frames it is in view"
        raise UnseenMotionError(
            f"Motion {motion} could not be given {n} visible points {where}: too "
            "little of it is seen. Use fewer frames or another random_state"
            + (" (complete tracks, missing=0, suit scene='lab')." if complete else ".")
        )
    geometry = track_geometry(points, normals, motion, occluders, camera, scene)
    geometry.found = np.ones(n, dtype=bool)
    geometry.found[todo] = False
    return geometry
