"""Outlier tracks for :func:`make_tracks`: tracks that follow no single motion.

Three kinds, in a fixed mix (an estimate: no dataset reports one):

- ``"drift"`` (1/2): the tracker slides off a feature at an occlusion boundary
  and follows another motion from frame ``s`` on. The position is continuous,
  ``x(t) = a(t)`` for ``t <= s`` and ``a(s) + b(t) - b(s)`` after, with ``a``
  and ``b`` points of two different motions.
- ``"jump"`` (1/4): the tracker locks onto another feature, ``x(t) = b(t)``
  after ``s``, a discontinuous switch.
- ``"random_walk"`` (1/4): a point on no rigid body (a reflection, a
  specularity, a T-junction), whose velocity wanders at the scene's typical
  image speed; it stays in the image (reflected at the borders).

A switch is only an outlier if it is seen: drift and jump tracks are observed
in at least two frames on each side of ``s``; a random walk in at least three
frames. With fewer than 5 frames every outlier is a random walk.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
from sklearn.utils import Bunch

from sklearn_gpca.datasets._track_geometry import in_image, sample_points
from sklearn_gpca.datasets._track_lifetimes import birth_probabilities, first_exit

OUTLIER_KINDS = {"drift": 0.5, "jump": 0.25, "random_walk": 0.25}
_MAX_ROUNDS = 100
# Frames a drift or jump outlier is seen on each side of its switch.
_SIDE = 2
_MIN_RANDOM_WALK = 3


def _random_walks(births, step, camera, n_frames, rng):
    n = births.size
    velocity = np.empty((n, n_frames, 2))
    velocity[:, 0] = rng.normal(scale=step, size=(n, 2))
    shocks = rng.normal(scale=0.6 * step, size=(n, n_frames, 2))
    for f in range(1, n_frames):
        velocity[:, f] = 0.8 * velocity[:, f - 1] + shocks[:, f]
    start = rng.uniform(0, 1, size=(n, 1, 2)) * [camera.width, camera.height]
    offsets = np.cumsum(velocity, axis=1) - velocity[:, :1]
    # Positions before the birth are never observed; start the walk there.
    offsets -= np.take_along_axis(offsets, births[:, None, None], axis=1)
    size = np.array([camera.width, camera.height])
    folded = np.mod(start + offsets, 2 * size)
    pixels = np.where(folded >= size, 2 * size - folded, folded)
    pixels = np.minimum(pixels, np.nextafter(size, 0))
    visible = np.ones((n, n_frames), dtype=bool)
    return pixels, visible, visible.copy()


def _switching(jump, shares, complete, first_share, context, rng):
    """Drift (``jump`` False) and jump outliers, redrawn until the switch is seen."""
    occluders, camera, scene, depth_range = context
    n_frames = scene.camera_rotations.shape[0]
    n_motions = shares.size
    n = jump.size
    frames = np.arange(n_frames)
    out = Bunch(
        pixels=np.empty((n, n_frames, 2)),
        in_view=np.empty((n, n_frames), dtype=bool),
        visible=np.empty((n, n_frames), dtype=bool),
        births=np.zeros(n, dtype=np.int64),
        switch=np.zeros(n, dtype=np.int64),
        sources=np.zeros((n, 2), dtype=np.int64),
    )
    todo = np.arange(n)
    if n == 0:
        out.failed = todo
        return out
    probs = birth_probabilities(n_frames, first_share, last=n_frames - 2 * _SIDE - 1)
    for _ in range(_MAX_ROUNDS):
        if todo.size == 0:
            break
        m = todo.size
        if complete:
            births = np.zeros(m, dtype=np.int64)
        else:
            births = rng.choice(n_frames, size=m, p=probs)
        # The switch falls 1 .. span frames after the second observed frame.
        span = np.maximum(n_frames - 2 * _SIDE - births, 1)
        switch = (
            births + _SIDE - 1 + np.floor(rng.uniform(size=m) * span).astype(np.int64)
        )
        first = rng.choice(n_motions, size=m, p=shares)
        second = first.copy()
        if n_motions > 1:
            # Another motion, in proportion to the motions' shares of tracks.
            weights = np.tile(shares, (m, 1))
            weights[np.arange(m), first] = 0.0
            cumulative = np.cumsum(weights / weights.sum(axis=1, keepdims=True), axis=1)
            second = np.minimum(
                (rng.uniform(size=(m, 1)) > cumulative).sum(axis=1), n_motions - 1
            )
        a = [
            np.empty((m, n_frames, 2)),
            np.empty((m, n_frames), bool),
            np.empty((m, n_frames), bool),
        ]
        b = [
            np.empty((m, n_frames, 2)),
            np.empty((m, n_frames), bool),
            np.empty((m, n_frames), bool),
        ]
        b_depth = np.empty((m, n_frames))
        found = np.ones(m, dtype=bool)
        for k in range(n_motions):
            for target, motions, at in ((a, first, births), (b, second, switch)):
                rows = np.flatnonzero(motions == k)
                if rows.size == 0:
                    continue
                geometry = sample_points(
                    k,
                    at[rows],
                    False,
                    occluders,
                    camera,
                    scene,
                    depth_range,
                    rng,
                    strict=False,
                )
                found[rows] &= geometry.found
                target[0][rows] = geometry.pixels
                target[1][rows] = geometry.in_view
                target[2][rows] = geometry.visible
                if target is b:
                    b_depth[rows] = geometry.depth
        rows = np.arange(m)
        drift = ~jump[todo]
        shift = np.where(drift[:, None], a[0][rows, switch] - b[0][rows, switch], 0.0)
        after = frames > switch[:, None]
        pixels = np.where(after[..., None], b[0] + shift[:, None, :], a[0])
        # After the switch: in front (b's depth), inside the image, and not
        # hidden where b itself would be hidden.
        after_in_view = (b_depth > camera.near) & in_image(pixels, camera)
        after_visible = after_in_view & ~(b[1] & ~b[2])
        in_view = np.where(after, after_in_view, a[1])
        visible = np.where(after, after_visible, a[2])
        exits = first_exit(visible, births)
        ok = exits == n_frames if complete else exits >= switch + _SIDE + 1
        ok &= found
        done = todo[ok]
        out.pixels[done] = pixels[ok]
        out.in_view[done] = in_view[ok]
        out.visible[done] = visible[ok]
        out.births[done] = births[ok]
        out.switch[done] = switch[ok]
        out.sources[done] = np.column_stack([first, second])[ok]
        todo = todo[~ok]
    out.failed = todo
    return out


def make_outliers(n_outliers, shares, step, complete, first_share, context, rng):
    """Outlier tracks: pixels (n, F, 2), visibility, births and minimum lengths.

    ``shares`` are the motions' shares of inlier tracks (drift and jump
    outliers leave motions in these proportions); ``step`` is the typical
    per-frame image displacement (pixels) for the random walks.
    """
    camera, scene = context[1], context[2]
    n_frames = scene.camera_rotations.shape[0]
    names = np.array(list(OUTLIER_KINDS))
    counts = rng.multinomial(n_outliers, list(OUTLIER_KINDS.values()))
    kinds = rng.permutation(np.repeat(names, counts))
    if n_frames < 2 * _SIDE + 1:
        kinds[:] = "random_walk"
    switching = np.flatnonzero(kinds != "random_walk")
    result = _switching(
        kinds[switching] == "jump", shares, complete, first_share, context, rng
    )
    # A switch that could not be placed (every track leaves the view within a
    # few frames) becomes a random walk.
    kinds[switching[result.failed]] = "random_walk"
    kept = np.setdiff1d(np.arange(switching.size), result.failed)
    walks = np.flatnonzero(kinds == "random_walk")

    out = Bunch(
        kinds=kinds,
        pixels=np.empty((n_outliers, n_frames, 2)),
        in_view=np.empty((n_outliers, n_frames), dtype=bool),
        visible=np.empty((n_outliers, n_frames), dtype=bool),
        births=np.zeros(n_outliers, dtype=np.int64),
        min_lengths=np.zeros(n_outliers, dtype=np.int64),
        switch=np.full(n_outliers, -1, dtype=np.int64),
        sources=np.full((n_outliers, 2), -1, dtype=np.int64),
    )
    rows = switching[kept]
    for name in ("pixels", "in_view", "visible", "births", "switch", "sources"):
        getattr(out, name)[rows] = getattr(result, name)[kept]
    out.min_lengths[rows] = result.switch[kept] + _SIDE + 1 - result.births[kept]

    if complete:
        births = np.zeros(walks.size, dtype=np.int64)
    else:
        last = n_frames - _MIN_RANDOM_WALK
        births = rng.choice(
            n_frames,
            size=walks.size,
            p=birth_probabilities(n_frames, first_share, last),
        )
    pixels, in_view, visible = _random_walks(births, step, camera, n_frames, rng)
    out.pixels[walks], out.in_view[walks], out.visible[walks] = pixels, in_view, visible
    out.births[walks] = births
    out.min_lengths[walks] = _MIN_RANDOM_WALK
    if complete:
        out.min_lengths[:] = n_frames
    return out
