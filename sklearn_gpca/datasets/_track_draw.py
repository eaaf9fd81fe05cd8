"""One draw of :func:`make_tracks`: a scene and its tracks in every frame.

The scene (camera path and moving objects), the inlier tracks of every motion
(born visible, sampled by rejection) and the outliers, with the first frame
each track is lost; lifetimes come after, in :func:`make_tracks`.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
from sklearn.utils import Bunch

from sklearn_gpca.datasets._track_geometry import (
    UnseenMotionError,
    make_camera,
    make_occluders,
    sample_points,
    visible_share,
)
from sklearn_gpca.datasets._track_lifetimes import (
    birth_probabilities,
    first_exit,
    first_frame_share,
)
from sklearn_gpca.datasets._track_outliers import make_outliers
from sklearn_gpca.datasets._track_scenes import make_scene

# Scenes drawn before a missing target is declared out of reach.
_TARGET_SCENES = 5
# Scenes drawn before giving up on one where every motion is seen, and the
# least share of an object's surface that must be visible in some frame.
_SCENE_ATTEMPTS = 20
_MIN_VISIBLE_SHARE = 0.02


def _typical_step(pixels, visible):
    """Median image displacement per frame (pixels) of visible inlier tracks."""
    both = visible[:, 1:] & visible[:, :-1]
    steps = np.linalg.norm(np.diff(pixels, axis=1), axis=2)[both]
    return max(float(np.median(steps)), 0.5) if steps.size else 1.0


def _draw(scene, camera, p, counts, n_outliers, first_share, complete, rng):
    """Scene, inlier and outlier tracks, every frame, before lifetimes.

    A scene in which some motion is almost never seen (an object hidden behind
    another, or turned away) is drawn again.
    """
    for _ in range(_SCENE_ATTEMPTS):
        try:
            return _draw_once(
                scene, camera, p, counts, n_outliers, first_share, complete, rng
            )
        except UnseenMotionError as error:
            last_error = error
    raise ValueError(
        f"No draw of the {scene!r} scene in {_SCENE_ATTEMPTS} attempts showed every "
        f"motion enough: {last_error}"
    )


def _draw_once(scene, camera, p, counts, n_outliers, first_share, complete, rng):
    F = p["n_frames"]

    world = make_scene(
        scene,
        F,
        p["n_motions"] - 1,
        p["forward_speed"],
        p["focal_length"],
        p["image_size"],
        p["depth_range"],
        p["frame_rate"],
        rng,
    )
    cam = make_camera(
        camera, p["focal_length"], p["image_size"], p["depth_range"], world
    )
    occluders = make_occluders(world, cam)
    context = (occluders, cam, world, p["depth_range"])

    # Inliers, motion by motion: birth frames, then points visible at birth.
    births_probs = birth_probabilities(F, first_share)
    geometries, births = [], []
    for k, count in enumerate(counts):
        probs = births_probs
        if k:
            per_frame, throughout = visible_share(k, occluders, cam, world, rng)
            if complete and throughout < _MIN_VISIBLE_SHARE:
                raise UnseenMotionError(f"object {k} is almost never seen throughout.")
            if not complete:
                probs = births_probs * per_frame
                if probs.max() < _MIN_VISIBLE_SHARE * births_probs.max():
                    raise UnseenMotionError(f"object {k} is almost never in view.")
                probs = probs / probs.sum()
        born = (
            np.zeros(count, dtype=np.int64)
            if complete
            else rng.choice(F, size=count, p=probs)
        )
        geometries.append(
            sample_points(
                k, born, complete, occluders, cam, world, p["depth_range"], rng
            )
        )
        births.append(born)
    pixels = np.concatenate([g.pixels for g in geometries])
    in_view = np.concatenate([g.in_view for g in geometries])
    visible = np.concatenate([g.visible for g in geometries])
    births = np.concatenate(births)
    points = np.concatenate([g.points for g in geometries])
    labels = np.repeat(np.arange(p["n_motions"]), counts)
    min_lengths = np.ones(births.size, dtype=np.int64)
    kinds = np.full(births.size, "inlier", dtype=object)
    switch = np.full(births.size, -1, dtype=np.int64)
    sources = np.full((births.size, 2), -1, dtype=np.int64)

    if n_outliers:
        step = _typical_step(pixels, visible)
        out = make_outliers(
            n_outliers, counts / counts.sum(), step, complete, first_share, context, rng
        )
        pixels = np.concatenate([pixels, out.pixels])
        in_view = np.concatenate([in_view, out.in_view])
        visible = np.concatenate([visible, out.visible])
        births = np.concatenate([births, out.births])
        points = np.concatenate([points, np.full((n_outliers, 3), np.nan)])
        labels = np.concatenate([labels, np.full(n_outliers, -1)])
        min_lengths = np.concatenate([min_lengths, out.min_lengths])
        kinds = np.concatenate([kinds, out.kinds.astype(object)])
        switch = np.concatenate([switch, out.switch])
        sources = np.concatenate([sources, out.sources])

    return Bunch(
        world=world,
        camera=cam,
        pixels=pixels,
        in_view=in_view,
        births=births,
        exits=first_exit(visible, births),
        points=points,
        labels=labels,
        kinds=kinds,
        switch=switch,
        sources=sources,
        min_lengths=min_lengths,
    )


def _missing_floor(d, n_frames):
    """Missing fraction of the drawn tracks with endless lifetimes."""
    return 1 - (d.exits - d.births).sum() / (d.births.size * n_frames)


def draw_for_target(scene, camera, p, counts, n_outliers, complete, rng):
    """A draw whose exits from the view leave the missing target reachable.

    A tracker replaces its lost tracks: a share ``1 - missing`` of them start
    in frame 0 (:func:`first_frame_share`). Where tracks leave the view so
    fast that no lifetime reaches the target, it replaces fewer: the share
    moves halfway to 1, then to 1, in the same scene. A scene where even that
    fails (every track born in frame 0 and never dying still misses more) is
    drawn again, up to ``_TARGET_SCENES`` times; the calibration then says
    how far off the last one is.
    """
    F = p["n_frames"]
    share = first_frame_share(F, p["missing"], p["mean_lifetime"])
    if p["missing"] is None or complete:
        d = _draw(scene, camera, p, counts, n_outliers, share, complete, rng)
        d.first_share = share
        return d
    target = p["missing"]
    for _ in range(_TARGET_SCENES):
        state = rng.get_state()
        # Every track born in frame 0 first: the least the scene can miss.
        d = _draw(scene, camera, p, counts, n_outliers, 1.0, complete, rng)
        d.first_share = 1.0
        if _missing_floor(d, F) > target:
            continue
        after = rng.get_state()
        for q in (share, (1 + share) / 2):
            rng.set_state(state)
            candidate = _draw(scene, camera, p, counts, n_outliers, q, complete, rng)
            if _missing_floor(candidate, F) <= target:
                candidate.first_share = q
                return candidate
        rng.set_state(after)
        return d
    return d
