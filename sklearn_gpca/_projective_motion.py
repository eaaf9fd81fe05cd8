"""A rigid motion seen by a perspective camera, fitted to tracks with missing entries.

Section 2 of the paper models every motion with an affine camera, so that its
complete trajectories span a linear subspace of dimension at most 4 of
``R^{2F}``. A static scene seen by a camera moving through it -- the
background of a tracker's output -- breaks that model when its depths vary:
over a long hand-held sequence its tracks fit no 4-D subspace, and the
segmentation then cuts it in two by depth. The exact model is the perspective
one (projective factorisation, Sturm & Triggs, ECCV 1996)::

    lambda_fp [x_fp, y_fp, 1]^T = P_f X_p

with one ``3 x 4`` camera ``P_f`` per frame and one point ``X_p`` of the
projective space ``P^3`` per track. It is fitted here on the observed points
only, by minimising the reprojection error ``sum ||x_fp - pi(P_f X_p)||^2``
over the seen point-frames with alternating Levenberg-Marquardt steps on the
points (intersection) and on the cameras (resection), the frames added one at a
time (sequential structure from motion), forwards and backwards, the better of
the two fits kept: started on all frames at once, a forward-moving camera often
settles in a reconstruction that leaves a third of the tracks unfitted. Every
step is batched over tracks or frames.

A track seen in ``m`` frames keeps ``2 m - 4`` residual degrees of freedom,
counted as for a 4-D subspace (four parameters per track, where its point has
three), so that the residuals per degree of freedom of the two models compare.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._chunks import row_chunks
from sklearn_gpca._observed_subspaces import fit_observed_subspace
from sklearn_gpca._rows import TINY

#: Fewest tracks seen in a frame to resect its camera (11 parameters).
MIN_CAMERA_POINTS = 6
#: Range of the Levenberg-Marquardt damping of each point's and each camera's
#: step, relative to the mean diagonal of its normal equations (a step is
#: kept only where it lowers that point's or camera's reprojection error).
MIN_DAMPING, MAX_DAMPING = 1e-9, 1e6
#: The damping each run of alternations starts from.
START_DAMPING = 1e-6
#: Most alternations after each frame added, on the frames of the last window.
STEP_ITERATIONS = 4
#: Frames of that window.
STEP_WINDOW = 10
#: Most alternations on all frames at the end of the sequential fit.
FINAL_ITERATIONS = 20
#: Most alternations of a fit started from given cameras.
WARM_ITERATIONS = 10
#: Relative decrease of the reprojection error below which the alternations
#: stop before their number above: less than a tenth of the error's own
#: spread (a chi-square of N terms spreads by sqrt(2 / N) of its value) for
#: fits of up to 2e6 observed coordinates. Set by that reasoning, not swept.
CONVERGED = 1e-4
#: RMS of the coordinates taken as they are; outside, they are rescaled.
ORDER_ONE = (2.0**-4, 2.0**4)
# Tracks per chunk of the batched steps: their (tracks, 2 F, 4) temporaries
# stay small.
_CHUNK = 2**12


def track_frames(X0, mask):
    """Image points and seen frames of each track.

    Parameters
    ----------
    X0 : ndarray of shape (n_tracks, 2 * n_frames)
        Tracks ``[x_1, y_1, ..., x_F, y_F]``, zero where missing.
    mask : ndarray of shape (n_tracks, 2 * n_frames), dtype=bool
        Observed entries.

    Returns
    -------
    points : ndarray of shape (n_tracks, n_frames, 2)
    seen : ndarray of shape (n_tracks, n_frames), dtype=bool
        Both coordinates observed.
    """
    n_tracks, n_features = X0.shape
    points = X0.reshape(n_tracks, n_features // 2, 2)
    seen = mask[:, 0::2] & mask[:, 1::2]
    return points, seen


def _projections(cameras, world):
    """``P_f X_p`` of every track in every frame, shape ``(n, F, 3)``."""
    n_frames = cameras.shape[0]
    return (world @ cameras.reshape(3 * n_frames, 4).T).reshape(-1, n_frames, 3)


def _safe(depth):
    """Depths away from zero (a point on a camera's focal plane)."""
    return np.where(np.abs(depth) > TINY**0.25, depth, TINY**0.25)


def _solve_damped(gram, rhs, damping):
    """Levenberg-damped solves of a batch of normal equations."""
    size = gram.shape[-1]
    ridge = damping * np.trace(gram, axis1=-2, axis2=-1) / size + TINY
    gram = gram + ridge[:, None, None] * np.eye(size)
    return np.linalg.solve(gram, rhs[..., None])[..., 0]


def _accept(old_cost, new_cost, damping):
    """Levenberg-Marquardt bookkeeping: which steps lowered the cost, new damping."""
    better = new_cost < old_cost
    damping = np.where(better, damping / 10, damping * 10)
    return better, np.clip(damping, MIN_DAMPING, MAX_DAMPING)


def _unit(rows):
    return rows / np.maximum(np.linalg.norm(rows, axis=-1, keepdims=True), TINY)


def triangulate(cameras, points, seen):
    """Linear (DLT) triangulation of every track from the given cameras.

    Parameters
    ----------
    cameras : ndarray of shape (n_frames, 3, 4)
    points : ndarray of shape (n_tracks, n_frames, 2)
    seen : ndarray of shape (n_tracks, n_frames), dtype=bool

    Returns
    -------
    world : ndarray of shape (n_tracks, 4)
        Unit homogeneous points; arbitrary for a track seen in fewer than two
        frames.
    """
    from sklearn_gpca import _projective_pairs

    if _projective_pairs.sparse_enough(seen):
        return _projective_pairs.triangulate(cameras, points, seen)
    world = np.empty((points.shape[0], 4))
    for rows in row_chunks(points.shape[0], _CHUNK):
        x, w = points[rows], seen[rows].astype(np.float64)
        # x_f (P_f3 X) - P_f1 X = 0 and y_f (P_f3 X) - P_f2 X = 0
        a = x[..., None] * cameras[None, :, 2:3, :] - cameras[None, :, :2, :]
        a = (a * w[..., None, None]).reshape(x.shape[0], -1, 4)
        world[rows] = np.linalg.eigh(a.transpose(0, 2, 1) @ a)[1][..., 0]
    return world


def resect(world, points):
    """Linear (DLT) camera of one frame from tracks' points and image points.

    Parameters
    ----------
    world : ndarray of shape (n_tracks, 4)
    points : ndarray of shape (n_tracks, 2)

    Returns
    -------
    camera : ndarray of shape (3, 4)
        Unit Frobenius norm.
    """
    zeros = np.zeros_like(world)
    rows = np.concatenate(
        [
            np.hstack([world, zeros, -points[:, :1] * world]),
            np.hstack([zeros, world, -points[:, 1:] * world]),
        ]
    )
    return np.linalg.eigh(rows.T @ rows)[1][:, 0].reshape(3, 4)


def _point_costs(cameras, world, points, seen):
    """Reprojection error of every track and its residual vector."""
    u = _projections(cameras, world)
    depth = _safe(u[..., 2])
    xy = u[..., :2] / depth[..., None]
    error = xy - points
    error *= seen[..., None]
    return np.einsum("pfc,pfc->p", error, error), error, xy, depth


def _state(cameras, world, points, seen):
    """``(error, xy, depth)`` of :func:`_point_costs` for every track, chunked."""
    error = np.empty(points.shape)
    xy = np.empty(points.shape)
    depth = np.empty(points.shape[:2])
    for rows in row_chunks(world.shape[0], _CHUNK):
        _, error[rows], xy[rows], depth[rows] = _point_costs(
            cameras, world[rows], points[rows], seen[rows]
        )
    return error, xy, depth


def frame_blocks(cameras):
    """The four ``4 x 4`` matrices per frame of the points' normal equations.

    Returns shape ``(4, n_frames, 16)``: for a point seen in frame ``f`` at
    projection ``(x, y)`` and depth ``d``, ``J^T J`` adds the blocks ``a``
    weighted by ``1 / d^2`` times ``1, x, y, x^2 + y^2``.
    """
    # The Jacobian rows of a point-frame are (P_1 - x P_3) / d and
    # (P_2 - y P_3) / d.
    p1, p2, p3 = cameras[:, 0], cameras[:, 1], cameras[:, 2]

    def outer(a, b):
        return a[:, :, None] * b[:, None, :]

    return np.stack(
        [
            outer(p1, p1) + outer(p2, p2),
            -(outer(p1, p3) + outer(p3, p1)),
            -(outer(p2, p3) + outer(p3, p2)),
            outer(p3, p3),
        ]
    ).reshape(4, -1, 16)


def camera_gram(blocks):
    """``(F, 12, 12)`` normal matrices of the cameras from the sums ``blocks``.

    ``blocks`` of shape ``(4, F, 4, 4)`` are the sums over a frame's tracks of
    ``X X^T`` weighted by ``1 / d^2`` times ``1, x, y, x^2 + y^2``: the
    Jacobian rows of a point-frame are ``[s, 0, -x s]`` and ``[0, s, -y s]``
    with ``s = X / d``.
    """
    gram = np.zeros((blocks.shape[1], 12, 12))
    gram[:, 0:4, 0:4] = blocks[0]
    gram[:, 4:8, 4:8] = blocks[0]
    gram[:, 0:4, 8:12] = -blocks[1]
    gram[:, 4:8, 8:12] = -blocks[2]
    gram[:, 8:12, 8:12] = blocks[3]
    gram[:, 8:12, 0:4] = -blocks[1]
    gram[:, 8:12, 4:8] = -blocks[2]
    return gram


def _point_normal_equations(cameras, error, xy, depth, seen):
    """Gauss-Newton normal equations of every track's point, cameras fixed.

    ``error``, ``xy`` and ``depth`` are :func:`_point_costs`'s at the current
    points. Returns ``gram`` of shape ``(n, 4, 4)`` and ``rhs`` of shape
    ``(n, 4)``: ``J^T J`` and ``J^T r`` of the residuals ``r = error``.
    """
    # J^T J sums the blocks of frame_blocks over the seen frames (zero
    # weight where unseen), one (n, 4 F) @ (4 F, 16) product; J^T r is one
    # (n, 3 F) @ (3 F, 4) product.
    px, py = xy[..., 0], xy[..., 1]
    h = seen / depth
    g = h / depth
    weights = np.concatenate([g, g * px, g * py, g * (px * px + py * py)], axis=1)
    gram = (weights @ frame_blocks(cameras).reshape(-1, 16)).reshape(-1, 4, 4)
    ex, ey = error[..., 0], error[..., 1]
    coefficients = np.stack([h * ex, h * ey, -h * (px * ex + py * ey)], axis=2)
    rhs = coefficients.reshape(error.shape[0], -1) @ cameras.reshape(-1, 4)
    return gram, rhs


def _camera_normal_equations(world, error, xy, depth, seen):
    """Gauss-Newton normal equations of every frame's camera, points fixed.

    Returns ``gram`` of shape ``(F, 12, 12)`` and ``rhs`` of shape
    ``(F, 12)`` (the camera's rows concatenated), summed over the tracks.
    """
    # camera_gram's sums are one (4 F, n) @ (n, 16) product; J^T r is one
    # (3 F, n) @ (n, 4) product.
    n_tracks, n_frames = error.shape[:2]
    px, py = xy[..., 0], xy[..., 1]
    ex, ey = error[..., 0], error[..., 1]
    h = seen / depth
    g = h / depth
    weights = np.concatenate([g, g * px, g * py, g * (px * px + py * py)], axis=1)
    products = (world[:, :, None] * world[:, None, :]).reshape(n_tracks, 16)
    gram = camera_gram((weights.T @ products).reshape(4, n_frames, 4, 4))
    coefficients = np.concatenate([h * ex, h * ey, -h * (px * ex + py * ey)], axis=1)
    sums = (coefficients.T @ world).reshape(3, n_frames, 4)
    rhs = np.concatenate([sums[0], sums[1], sums[2]], axis=1)
    return gram, rhs


def _intersection_step(cameras, world, points, seen, damping, state=None):
    """One Levenberg-Marquardt step on every track's point, cameras fixed.

    ``state`` is :func:`_state` at ``(cameras, world)`` (None: computed).
    Returns the points, their new damping and the state at the new points
    (each track's from the fit it keeps: no further pass is needed).
    """
    error, xy, depth = _state(cameras, world, points, seen) if state is None else state
    out = world.copy()
    damping = damping.copy()
    new_error, new_xy, new_depth = error.copy(), xy.copy(), depth.copy()
    for rows in row_chunks(world.shape[0], _CHUNK):
        x, w = points[rows], seen[rows]
        gram, rhs = _point_normal_equations(
            cameras, error[rows], xy[rows], depth[rows], w
        )
        trial = _unit(world[rows] - _solve_damped(gram, rhs, damping[rows]))
        trial_cost, trial_error, trial_xy, trial_depth = _point_costs(
            cameras, trial, x, w
        )
        better, damping[rows] = _accept(
            np.sum(error[rows] ** 2, axis=(1, 2)), trial_cost, damping[rows]
        )
        out[rows] = np.where(better[:, None], trial, world[rows])
        keep = np.flatnonzero(better)
        if keep.size:
            chunk = np.arange(world.shape[0])[rows][keep]
            new_error[chunk] = trial_error[keep]
            new_xy[chunk] = trial_xy[keep]
            new_depth[chunk] = trial_depth[keep]
    return out, damping, (new_error, new_xy, new_depth)


def _resection_step(cameras, world, points, seen, damping, fit_rows=None, state=None):
    """One Levenberg-Marquardt step on every frame's camera, points fixed.

    The normal equations and the costs that accept a step are summed over
    ``fit_rows`` (None: every track); frames seen by fewer than
    ``MIN_CAMERA_POINTS`` of them keep their camera. ``state`` is
    :func:`_state` at ``(cameras, world)`` (None: computed). Returns the
    cameras, their new damping and the state at the new cameras (each
    frame's from the camera it keeps).
    """
    n_frames = cameras.shape[0]
    if fit_rows is None:
        fit_rows = np.ones(world.shape[0], dtype=bool)
    error, xy, depth = _state(cameras, world, points, seen) if state is None else state
    fit_index = np.flatnonzero(fit_rows)
    gram = np.zeros((n_frames, 12, 12))
    rhs = np.zeros((n_frames, 12))
    cost = np.zeros(n_frames)
    for chunk in row_chunks(fit_index.size, _CHUNK):
        rows = fit_index[chunk]
        part = error[rows]
        cost += np.einsum("pfc,pfc->f", part, part)
        chunk_gram, chunk_rhs = _camera_normal_equations(
            world[rows], part, xy[rows], depth[rows], seen[rows]
        )
        gram += chunk_gram
        rhs += chunk_rhs
    step = _solve_damped(gram, rhs, damping)
    trial = _unit(cameras.reshape(n_frames, 12) - step).reshape(n_frames, 3, 4)
    trial_error, trial_xy, trial_depth = _state(trial, world, points, seen)
    trial_cost = np.zeros(n_frames)
    for chunk in row_chunks(fit_index.size, _CHUNK):
        part = trial_error[fit_index[chunk]]
        trial_cost += np.einsum("pfc,pfc->f", part, part)
    better, damping = _accept(cost, trial_cost, damping)
    better &= np.count_nonzero(seen[fit_rows], axis=0) >= MIN_CAMERA_POINTS
    state = (
        np.where(better[None, :, None], trial_error, error),
        np.where(better[None, :, None], trial_xy, xy),
        np.where(better[None, :], trial_depth, depth),
    )
    return np.where(better[:, None, None], trial, cameras), damping, state


def _alternate(cameras, world, points, seen, n_iter, fit_rows):
    """At most ``n_iter`` intersection and resection steps (``fit_rows`` resect).

    Stops early once an alternation lowers the reprojection error of the
    ``fit_rows`` tracks by less than ``CONVERGED`` of it, far less than that
    error's own spread under the noise. On mostly unseen point-frames the
    steps run on the seen ones alone (:mod:`sklearn_gpca._projective_pairs`).
    """
    from sklearn_gpca import _projective_pairs

    if _projective_pairs.sparse_enough(seen):
        return _projective_pairs.alternate(
            cameras, world, points, seen, n_iter, fit_rows
        )
    return run_alternations(
        cameras,
        world,
        _state(cameras, world, points, seen),
        n_iter,
        intersect=lambda c, w, damping, state: _intersection_step(
            c, w, points, seen, damping, state
        ),
        resect=lambda c, w, damping, state: _resection_step(
            c, w, points, seen, damping, fit_rows, state
        ),
        fit_cost=lambda state: _fit_cost(state[0], fit_rows),
    )


def run_alternations(cameras, world, state, n_iter, *, intersect, resect, fit_cost):
    """At most ``n_iter`` alternations of ``intersect`` and ``resect`` steps.

    Shared by the dense steps here and those on the seen point-frames
    (:mod:`sklearn_gpca._projective_pairs`): ``intersect(cameras, world,
    damping, state)`` returns ``(world, damping, state)``, ``resect`` the
    same with the cameras, ``fit_cost(state)`` the fit rows' reprojection
    error. Stops once an alternation lowers it by less than ``CONVERGED``.
    """
    point_damping = np.full(world.shape[0], START_DAMPING)
    camera_damping = np.full(cameras.shape[0], START_DAMPING)
    cost = fit_cost(state)
    for _ in range(n_iter):
        world, point_damping, state = intersect(cameras, world, point_damping, state)
        cameras, camera_damping, state = resect(cameras, world, camera_damping, state)
        new_cost = fit_cost(state)
        if cost - new_cost <= CONVERGED * cost:
            break
        cost = new_cost
    return cameras, world


def _fit_cost(error, fit_rows):
    """Reprojection error of the ``fit_rows`` tracks (``error`` of :func:`_state`)."""
    part = error[fit_rows]
    return float(np.einsum("pfc,pfc->", part, part))


def affine_cameras(X0, mask):
    """Cameras of the affine model: ``P_f = [B_f; l^T]``.

    ``B`` is the 4-D subspace of the tracks augmented with a constant
    coordinate (fitted on observed entries), ``l`` the row of that
    coordinate: the affine camera ``x_f = B_f X / (l^T X)`` with ``l^T X``
    constant along every track. Frames outside the subspace's support get
    the camera of the nearest supported frame.
    """
    observed = mask[mask]
    scale = float(np.sqrt(np.mean(X0[mask] ** 2))) if observed.size else 1.0
    scale = scale if scale > 0 else 1.0
    augmented = np.column_stack([X0, np.full(X0.shape[0], scale)])
    augmented_mask = np.column_stack([mask, np.ones(X0.shape[0], dtype=bool)])
    basis, support = fit_observed_subspace(augmented, augmented_mask, 4)
    n_frames = X0.shape[1] // 2
    rows = basis[:-1].reshape(n_frames, 2, 4)
    last = np.broadcast_to(basis[-1] / scale, (n_frames, 1, 4))
    cameras = np.concatenate([rows, last], axis=1)
    supported = np.flatnonzero(support[:-1].reshape(n_frames, 2).all(axis=1))
    if supported.size and supported.size < n_frames:
        nearest = supported[
            np.abs(np.arange(n_frames)[:, None] - supported[None, :]).argmin(axis=1)
        ]
        cameras = cameras[nearest]
    return _unit(cameras.reshape(n_frames, 12)).reshape(n_frames, 3, 4)


def _frame_orders(seen):
    """Orders in which the sequential fit adds the frames, forwards and backwards.

    Each starts with three consecutive frames that at least
    ``2 * MIN_CAMERA_POINTS`` tracks all see (the first such triple,
    respectively the last; the best seen triple when none qualifies), then
    goes on to the end of the sequence and finally back to its other end: a
    motion seen only in the middle of the sequence starts where it is seen.
    """
    n_frames = seen.shape[1]
    if n_frames < 3:
        every = np.arange(n_frames)
        return [every, every[::-1]]
    counts = np.count_nonzero(seen[:, :-2] & seen[:, 1:-1] & seen[:, 2:], axis=0)
    good = np.flatnonzero(counts >= 2 * MIN_CAMERA_POINTS)
    first = int(good[0]) if good.size else int(np.argmax(counts))
    last = int(good[-1]) + 2 if good.size else int(np.argmax(counts)) + 2
    forward = (
        np.r_[first:n_frames, first - 1 : -1 : -1] if first else np.arange(n_frames)
    )
    backward = np.r_[last:-1:-1, last + 1 : n_frames]
    return [forward, backward]


def _sequential_fit(X0, mask, points, seen):
    """Frames added one at a time, each camera resected from the points so far."""
    n_frames = seen.shape[1]
    first = min(3, n_frames)
    cameras = np.empty((n_frames, 3, 4))
    cameras[:first] = affine_cameras(X0[:, : 2 * first], mask[:, : 2 * first])
    fit_rows = np.count_nonzero(seen[:, :first], axis=1) >= 2
    world = triangulate(cameras[:first], points[:, :first], seen[:, :first])
    cameras[:first], world = _alternate(
        cameras[:first],
        world,
        points[:, :first],
        seen[:, :first],
        STEP_ITERATIONS,
        fit_rows,
    )
    for frame in range(first, n_frames):
        known = np.count_nonzero(seen[:, :frame], axis=1) >= 2
        resected = known & seen[:, frame]
        cameras[frame] = cameras[frame - 1]
        if resected.sum() >= MIN_CAMERA_POINTS:
            known_world = world[resected]
            known_points = points[resected, frame : frame + 1]
            known_seen = seen[resected, frame : frame + 1]
            camera = resect(known_world, known_points[:, 0])[None]
            damping = np.full(1, START_DAMPING)
            state = None
            for _ in range(STEP_ITERATIONS):
                camera, damping, state = _resection_step(
                    camera, known_world, known_points, known_seen, damping, state=state
                )
            cameras[frame] = camera[0]
        end = frame + 1
        born = ~known & (np.count_nonzero(seen[:, :end], axis=1) >= 2)
        if born.any():
            world[born] = triangulate(
                cameras[:end], points[born, :end], seen[born, :end]
            )
        start = max(0, end - STEP_WINDOW)
        local = np.count_nonzero(seen[:, start:end], axis=1) > 0
        fit_local = np.count_nonzero(seen[local, :end], axis=1) >= 3
        cameras[start:end], world[local] = _alternate(
            cameras[start:end],
            world[local],
            points[local, start:end],
            seen[local, start:end],
            STEP_ITERATIONS,
            fit_local,
        )
    fit_rows = np.count_nonzero(seen, axis=1) >= 3
    return _alternate(cameras, world, points, seen, FINAL_ITERATIONS, fit_rows)


def supported_frames(mask):
    """Frames seen by ``MIN_CAMERA_POINTS`` tracks seen in two frames or more.

    The frames whose cameras :func:`fit_projective_motion` determines, from
    the observed entries ``mask`` of shape (n_tracks, 2 * n_frames).
    """
    seen = mask[:, 0::2] & mask[:, 1::2]
    informative = np.count_nonzero(seen, axis=1) >= 2
    return np.count_nonzero(seen[informative], axis=0) >= MIN_CAMERA_POINTS


def _fit(X0, mask, cameras):
    """:func:`fit_projective_motion` on coordinates of order 1."""
    points, seen = track_frames(X0, mask)
    supported = supported_frames(mask)
    if cameras is None:
        # frames added forwards and backwards from the first and the last
        # well-seen frames; the fit that leaves the fewer tracks far from it
        # is kept (either order can settle badly)
        fits = []
        for order in _frame_orders(seen):
            columns = np.column_stack([2 * order, 2 * order + 1]).ravel()
            fitted, _ = _sequential_fit(
                X0[:, columns], mask[:, columns], points[:, order], seen[:, order]
            )
            restored = np.empty_like(fitted)
            restored[order] = fitted
            fits.append(restored)
        spreads = [_misfit_quantile(c, X0, mask, supported) for c in fits]
        cameras = fits[int(np.argmin(spreads))]
    else:
        world = triangulate(cameras, points, seen)
        fit_rows = np.count_nonzero(seen, axis=1) >= 3
        cameras, _ = _alternate(cameras, world, points, seen, WARM_ITERATIONS, fit_rows)
    return cameras, supported


def _misfit_quantile(cameras, X0, mask, supported, quantile=0.9):
    """A high quantile of the tracks' reprojection error per degree of freedom."""
    residuals, dofs = _residuals(X0, mask, cameras, supported)
    per_dof = residuals[dofs > 0] / dofs[dofs > 0]
    return float(np.quantile(per_dof, quantile)) if per_dof.size else 0.0


def _residuals(X0, mask, cameras, supported):
    """:func:`projective_residuals` on coordinates of order 1."""
    points, seen = track_frames(X0, mask)
    seen = seen & supported[None, :]
    counts = np.count_nonzero(seen, axis=1)
    dofs = np.maximum(2 * counts - 4, 0).astype(np.intp)
    from sklearn_gpca import _projective_pairs

    if _projective_pairs.sparse_enough(seen):
        return _projective_pairs.residuals(cameras, points, seen), dofs
    world = triangulate(cameras, points, seen)
    damping = np.full(world.shape[0], START_DAMPING)
    state = None
    for _ in range(3):
        world, damping, state = _intersection_step(
            cameras, world, points, seen, damping, state
        )
    residuals = np.empty(points.shape[0])
    for rows in row_chunks(points.shape[0], _CHUNK):
        u = _projections(cameras, world[rows])
        xy = u[..., :2] / _safe(u[..., 2])[..., None]
        squared = np.sum((xy - points[rows]) ** 2, axis=-1)
        residuals[rows] = np.sum(np.where(seen[rows], squared, 0.0), axis=1)
    return residuals, dofs


def _image_scale(X0, mask):
    """1 for coordinates of order 1, else the power of two nearest the RMS of
    the observed coordinates: dividing by it is exact and leaves the linear
    triangulations and resections coordinates of order 1 (pixels, say)."""
    observed = X0[mask]
    rms = float(np.sqrt(np.mean(observed**2))) if observed.size else 0.0
    if not (np.isfinite(rms) and rms > 0) or ORDER_ONE[0] <= rms <= ORDER_ONE[1]:
        return 1.0
    return float(2.0 ** np.round(np.log2(rms)))


def rescaled_cameras(cameras, factor):
    """Cameras for image coordinates multiplied by ``factor``."""
    return cameras * np.array([factor, factor, 1.0])[None, :, None]


def fit_projective_motion(X0, mask, *, cameras=None):
    """Perspective cameras of one rigid motion from its tracks.

    Parameters
    ----------
    X0 : ndarray of shape (n_tracks, 2 * n_frames)
        Tracks of the motion, zero where missing, in any units (they are
        divided by the power of two nearest the RMS of the observed entries
        while fitting).
    mask : ndarray of shape (n_tracks, 2 * n_frames), dtype=bool
        Observed entries.
    cameras : ndarray of shape (n_frames, 3, 4), default=None
        Start (e.g. the previous fit in K-subspaces): up to ``WARM_ITERATIONS``
        alternations on all frames. None fits from scratch, frame by frame.

    Returns
    -------
    cameras : ndarray of shape (n_frames, 3, 4)
        One camera per frame, for the units of ``X0``.
    supported : ndarray of shape (n_frames,), dtype=bool
        Frames seen by at least ``MIN_CAMERA_POINTS`` of the tracks (seen in
        two frames or more); the cameras of the others are not determined.
    """
    scale = _image_scale(X0, mask)
    start = None if cameras is None else rescaled_cameras(cameras, 1 / scale)
    fitted, supported = _fit(X0 / scale, mask, start)
    return rescaled_cameras(fitted, scale), supported


def projective_residuals(X0, mask, cameras, supported):
    """Reprojection residual of every track to a perspective motion.

    Each track's point is triangulated from the cameras of the frames it is
    seen in (linear triangulation, then Levenberg-Marquardt steps on the
    reprojection error); frames outside ``supported`` are ignored.

    Parameters
    ----------
    X0 : ndarray of shape (n_tracks, 2 * n_frames)
        Tracks, zero where missing, in the units of the fit.
    mask : ndarray of shape (n_tracks, 2 * n_frames), dtype=bool
        Observed entries.
    cameras : ndarray of shape (n_frames, 3, 4)
    supported : ndarray of shape (n_frames,), dtype=bool
        From :func:`fit_projective_motion`.

    Returns
    -------
    residuals : ndarray of shape (n_tracks,)
        Squared reprojection errors summed over the frames used.
    dofs : ndarray of shape (n_tracks,), dtype=intp
        ``max(2 m - 4, 0)`` for ``m`` frames used (see the module doc).
    """
    scale = _image_scale(X0, mask)
    residuals, dofs = _residuals(
        X0 / scale, mask, rescaled_cameras(cameras, 1 / scale), supported
    )
    return residuals * scale**2, dofs
