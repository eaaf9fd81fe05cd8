"""The perspective fit's steps on the seen point-frames only.

:mod:`sklearn_gpca._projective_motion` batches its steps over arrays of shape
``(n_tracks, n_frames, ...)`` with the unseen point-frames weighted 0: BLAS
products, fast while most point-frames are seen. A tracker's output over a
long sequence sees each track in a short window (the giraffe of the low-rank
benchmarks: 7 % of the point-frames), and there these arrays are mostly
zeros. The same steps here run on the seen point-frames as flat arrays, their
sums over a track's frames or a frame's tracks as sparse products: the same
equations, in time linear in the seen point-frames.
"""

# SPDX-License-Identifier: BSD-3-Clause

import functools

import numpy as np
from scipy import sparse

from sklearn_gpca._projective_motion import (
    MIN_CAMERA_POINTS,
    START_DAMPING,
    _accept,
    _safe,
    _solve_damped,
    _unit,
    camera_gram,
    frame_blocks,
    run_alternations,
)

#: Fraction of seen point-frames below which the perspective fit runs on
#: them alone (:class:`PointFrames`). A speed setting: the warm fit is 1.6 to
#: 4.6 times faster there, 1.2 times at 0.29 and 0.8 at 0.47 (hand-held and
#: giraffe tracks, ``benchmarks/results/projective_pairs.md``); a round value
#: below the break-even.
MAX_DENSITY = 0.25


def sparse_enough(seen):
    """Whether the steps are faster on the seen point-frames alone."""
    return seen.size > 0 and np.count_nonzero(seen) < MAX_DENSITY * seen.size


class PointFrames:
    """The seen point-frames of tracks: track, frame and image point of each.

    Parameters
    ----------
    points : ndarray of shape (n_tracks, n_frames, 2)
    seen : ndarray of shape (n_tracks, n_frames), dtype=bool
    """

    def __init__(self, points, seen):
        self.n_tracks, self.n_frames = seen.shape
        self.track, self.frame = np.nonzero(seen)  # sorted by track
        self.points = points[self.track, self.frame]
        self.indptr = np.zeros(self.n_tracks + 1, dtype=np.intp)
        np.cumsum(np.count_nonzero(seen, axis=1), out=self.indptr[1:])
        size = self.track.size
        self._to_tracks = sparse.csr_matrix(
            (np.ones(size), np.arange(size), self.indptr), shape=(self.n_tracks, size)
        )

    def by_track(self, values):
        """``(n_tracks, n_frames)`` sparse matrix of one value per point-frame."""
        return sparse.csr_matrix(
            (values, self.frame, self.indptr), shape=(self.n_tracks, self.n_frames)
        )

    def track_sums(self, values):
        """Sums over each track's point-frames of ``values`` (leading axis)."""
        if values.ndim == 1:
            return np.bincount(self.track, weights=values, minlength=self.n_tracks)
        return self._to_tracks @ values

    def frame_sums(self, values):
        """Sums over each frame's point-frames of ``values`` of shape (n_seen,)."""
        return np.bincount(self.frame, weights=values, minlength=self.n_frames)

    def state(self, cameras, world):
        """``(error, xy, depth)`` of every point-frame: reprojection error,
        projection and depth, as :func:`_projective_motion._point_costs`."""
        u = np.matmul(cameras[self.frame], world[self.track][:, :, None])[..., 0]
        depth = _safe(u[:, 2])
        xy = u[:, :2] / depth[:, None]
        return xy - self.points, xy, depth


def _squared(error):
    return np.einsum("kc,kc->k", error, error)


def _weights(error, xy, depth):
    """Per point-frame: the normal equations' weights ``g (1, x, y, x^2 + y^2)``
    and the right-hand side's coefficients ``h (e_x, e_y, -(x e_x + y e_y))``,
    with ``h = 1 / d`` and ``g = h / d``."""
    px, py = xy[:, 0], xy[:, 1]
    ex, ey = error[:, 0], error[:, 1]
    h = 1.0 / depth
    g = h / depth
    weights = (g, g * px, g * py, g * (px * px + py * py))
    coefficients = (h * ex, h * ey, -h * (px * ex + py * ey))
    return weights, coefficients


def _point_normal_equations(pairs, cameras, state):
    weights, coefficients = _weights(*state)
    blocks = frame_blocks(cameras)
    gram = sum(
        pairs.by_track(w) @ block for w, block in zip(weights, blocks, strict=True)
    )
    rhs = sum(pairs.by_track(c) @ cameras[:, i] for i, c in enumerate(coefficients))
    return gram.reshape(-1, 4, 4), rhs


def _camera_normal_equations(pairs, world, state, fit):
    weights, coefficients = _weights(*state)
    products = (world[:, :, None] * world[:, None, :]).reshape(-1, 16)
    blocks = np.stack([pairs.by_track(w * fit).T @ products for w in weights])
    sums = [pairs.by_track(c * fit).T @ world for c in coefficients]
    return camera_gram(blocks.reshape(4, -1, 4, 4)), np.concatenate(sums, axis=1)


def _kept(better, state, trial_state):
    return tuple(
        np.where(better.reshape(-1, *([1] * (old.ndim - 1))), new, old)
        for old, new in zip(state, trial_state, strict=True)
    )


def intersection_step(pairs, cameras, world, damping, state):
    """:func:`_projective_motion._intersection_step` on the seen point-frames."""
    gram, rhs = _point_normal_equations(pairs, cameras, state)
    trial = _unit(world - _solve_damped(gram, rhs, damping))
    trial_state = pairs.state(cameras, trial)
    better, damping = _accept(
        pairs.track_sums(_squared(state[0])),
        pairs.track_sums(_squared(trial_state[0])),
        damping,
    )
    world = np.where(better[:, None], trial, world)
    return world, damping, _kept(better[pairs.track], state, trial_state)


def resection_step(pairs, cameras, world, damping, fit, state):
    """:func:`_projective_motion._resection_step` on the seen point-frames.

    ``fit`` weighs each point-frame 1 if its track is one of the fit rows, else 0.
    """
    n_frames = cameras.shape[0]
    cost = pairs.frame_sums(_squared(state[0]) * fit)
    gram, rhs = _camera_normal_equations(pairs, world, state, fit)
    step = _solve_damped(gram, rhs, damping)
    trial = _unit(cameras.reshape(n_frames, 12) - step).reshape(n_frames, 3, 4)
    trial_state = pairs.state(trial, world)
    better, damping = _accept(
        cost, pairs.frame_sums(_squared(trial_state[0]) * fit), damping
    )
    better &= pairs.frame_sums(fit) >= MIN_CAMERA_POINTS
    cameras = np.where(better[:, None, None], trial, cameras)
    return cameras, damping, _kept(better[pairs.frame], state, trial_state)


def alternate(cameras, world, points, seen, n_iter, fit_rows):
    """:func:`_projective_motion._alternate` on the seen point-frames."""
    pairs = PointFrames(points, seen)
    fit = fit_rows[pairs.track].astype(np.float64)
    return run_alternations(
        cameras,
        world,
        pairs.state(cameras, world),
        n_iter,
        intersect=functools.partial(intersection_step, pairs),
        resect=lambda c, w, damping, state: resection_step(
            pairs, c, w, damping, fit, state
        ),
        fit_cost=lambda state: float(np.dot(_squared(state[0]), fit)),
    )


def triangulate(cameras, points, seen):
    """:func:`_projective_motion.triangulate` on the seen point-frames."""
    pairs = PointFrames(points, seen)
    return _triangulate(pairs, cameras)


def _triangulate(pairs, cameras):
    # x_f (P_f3 X) - P_f1 X = 0 and y_f (P_f3 X) - P_f2 X = 0
    P = cameras[pairs.frame]
    x, y = pairs.points[:, :1], pairs.points[:, 1:]
    rows = (x * P[:, 2] - P[:, 0], y * P[:, 2] - P[:, 1])
    outer = sum(r[:, :, None] * r[:, None, :] for r in rows).reshape(-1, 16)
    normal = pairs.track_sums(outer).reshape(-1, 4, 4)
    return np.linalg.eigh(normal)[1][..., 0]


def residuals(cameras, points, seen):
    """Each track's squared reprojection error after its point's
    re-triangulation and three intersection steps, as
    :func:`_projective_motion._residuals`."""
    pairs = PointFrames(points, seen)
    world = _triangulate(pairs, cameras)
    damping = np.full(world.shape[0], START_DAMPING)
    state = pairs.state(cameras, world)
    for _ in range(3):
        world, damping, state = intersection_step(pairs, cameras, world, damping, state)
    return pairs.track_sums(_squared(pairs.state(cameras, world)[0]))
