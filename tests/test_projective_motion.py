"""Tests for the perspective motion model (sklearn_gpca._projective_motion)."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest

from sklearn_gpca._observed_subspaces import (
    fit_observed_subspace,
    observed_entries,
    subspace_residuals,
)
from sklearn_gpca._projective_motion import (
    MIN_CAMERA_POINTS,
    _camera_normal_equations,
    _point_costs,
    _point_normal_equations,
    affine_cameras,
    fit_projective_motion,
    projective_residuals,
    resect,
    track_frames,
    triangulate,
)
from sklearn_gpca._refine_observed import refine_observed
from sklearn_gpca._segment import segment_motions, track_graph
from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.metrics import misclassification_rate


def _rotation(angles):
    a, b, c = angles
    rx = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    ry = np.array([[np.cos(b), 0, np.sin(b)], [0, 1, 0], [-np.sin(b), 0, np.cos(b)]])
    rz = np.array([[np.cos(c), -np.sin(c), 0], [np.sin(c), np.cos(c), 0], [0, 0, 1]])
    return rx @ ry @ rz


def _scene(n_tracks=200, n_frames=15, noise=0.0, forward=False, seed=0, speed=1.0):
    """A static scene (depths 8-40) seen by a moving pinhole camera.

    Each track is seen on one window of at least 3 frames. Returns the tracks
    (NaN where unseen), their windows and the true cameras.
    """
    rng = np.random.default_rng(seed)
    depth = np.exp(rng.uniform(np.log(8.0), np.log(40.0), n_tracks))
    world = np.column_stack(
        [rng.uniform(-0.6, 0.6, (n_tracks, 2)) * depth[:, None], depth]
    )
    step = np.array([0.0, 0.0, 0.3]) if forward else np.array([0.08, 0.02, 0.03])
    step = speed * step
    X = np.full((n_tracks, 2 * n_frames), np.nan)
    cameras = []
    for f in range(n_frames):
        rotation = _rotation(0.01 * f * np.array([1.0, 2.0, 0.5]))
        centre = f * step
        camera = np.hstack([rotation, -rotation @ centre[:, None]])
        cameras.append(camera)
        h = np.hstack([world, np.ones((n_tracks, 1))]) @ camera.T
        X[:, 2 * f : 2 * f + 2] = h[:, :2] / h[:, 2:]
    X = X + noise * rng.standard_normal(X.shape)
    start = rng.integers(0, n_frames - 3, n_tracks)
    length = rng.integers(3, n_frames + 1, n_tracks)
    end = np.minimum(start + length, n_frames)
    frames = np.arange(n_frames)
    hidden = (frames[None, :] < start[:, None]) | (frames[None, :] >= end[:, None])
    X[np.repeat(hidden, 2, axis=1)] = np.nan
    return X, np.array(cameras)


def _per_dof(X, cameras=None):
    X0, mask = observed_entries(X)
    if cameras is None:
        cameras, supported = fit_projective_motion(X0, mask)
    else:
        supported = np.ones(cameras.shape[0], dtype=bool)
    residuals, dofs = projective_residuals(X0, mask, cameras, supported)
    return residuals[dofs > 0] / dofs[dofs > 0]


@pytest.mark.parametrize("forward", [False, True])
def test_noise_free_scene_is_fitted_exactly(forward):
    X, _ = _scene(forward=forward)
    # coordinates of order 1: far below any pixel noise (1e-3 here)
    assert np.max(_per_dof(X)) < 1e-7


@pytest.mark.parametrize("seed", [1, 2])
def test_noisy_scene_is_fitted_to_the_noise(seed):
    noise = 1e-3
    X, cameras = _scene(noise=noise, speed=4.0, seed=seed)
    per_dof = _per_dof(X) / noise**2
    # about the noise (2 m - 4 degrees of freedom counted where the point
    # leaves 2 m - 3), and no worse than the true cameras
    assert np.median(per_dof) < 2.0
    assert np.quantile(per_dof, 0.99) < 8.0
    assert np.median(per_dof) <= 1.05 * np.median(_per_dof(X, cameras) / noise**2)


def test_subspace_does_not_fit_the_perspective_scene():
    """The reason for the model: a deep scene spans no 4-D subspace."""
    noise = 1e-3
    X, _ = _scene(noise=noise, speed=8.0, seed=1)
    X0, mask = observed_entries(X)
    basis, support = fit_observed_subspace(X0, mask, 4)
    residuals, dofs = subspace_residuals(X0, mask, [basis], [support])
    affine = np.median(residuals[dofs[:, 0] > 0, 0] / dofs[dofs[:, 0] > 0, 0])
    assert affine > 10 * noise**2
    assert np.median(_per_dof(X)) < 2.0 * noise**2


def test_another_motion_misfits():
    X, _ = _scene(seed=3)
    other, _ = _scene(seed=4)
    # the same scene seen by a camera moving otherwise
    other = other[:, ::-1].copy()
    X0, mask = observed_entries(X)
    cameras, supported = fit_projective_motion(X0, mask)
    O0, omask = observed_entries(other)
    residuals, dofs = projective_residuals(O0, omask, cameras, supported)
    long = dofs >= 6
    # noise-free: its own motion leaves below 1e-7 per degree of freedom
    assert np.median(residuals[long] / dofs[long]) > 1e-6


def test_invariant_to_an_affine_map_of_the_image():
    """Projective cameras absorb any affine change of image coordinates."""
    X, _ = _scene(noise=1e-3, seed=5)
    A = np.array([[300.0, 20.0], [0.0, 280.0]])
    t = np.array([320.0, 240.0])
    points = X.reshape(X.shape[0], -1, 2) @ A.T + t
    mapped = points.reshape(X.shape)
    base = np.median(_per_dof(X))
    scaled = np.median(_per_dof(mapped)) / np.linalg.det(A)
    assert scaled == pytest.approx(base, rel=0.05)


def test_linear_steps_recover_the_truth():
    X, cameras = _scene(seed=6)
    X0, mask = observed_entries(X)
    points, seen = track_frames(X0, mask)
    world = triangulate(cameras, points, seen)
    h = np.einsum("fij,nj->nfi", cameras, world)
    assert np.allclose(
        np.where(seen[..., None], h[..., :2] / h[..., 2:], points), points
    )
    camera = resect(world[seen[:, 4]], points[seen[:, 4], 4])
    camera *= np.sign(camera[2, 3] * cameras[4][2, 3])
    expected = cameras[4] / np.linalg.norm(cameras[4])
    assert np.allclose(camera, expected, atol=1e-8)


def test_affine_cameras_fit_an_affine_scene():
    rng = np.random.default_rng(7)
    motion = rng.standard_normal((20, 4))
    world = np.column_stack([rng.standard_normal((60, 3)), np.ones(60)])
    X = world @ motion.T
    X0, mask = observed_entries(X)
    cameras = affine_cameras(X0, mask)
    residuals, _ = projective_residuals(X0, mask, cameras, np.ones(10, dtype=bool))
    assert np.max(residuals) < 1e-18 * np.sum(X**2)


def test_frames_seen_by_few_tracks_are_unsupported():
    X, _ = _scene(seed=8)
    X[:, 10:12] = np.nan
    X[: MIN_CAMERA_POINTS - 1, 10:12] = 1.0
    X0, mask = observed_entries(X)
    _, supported = fit_projective_motion(X0, mask)
    assert not supported[5]
    assert supported[[4, 6]].all()


def test_warm_start_keeps_a_good_fit():
    noise = 1e-3
    X, _ = _scene(noise=noise, seed=9)
    X0, mask = observed_entries(X)
    cameras, supported = fit_projective_motion(X0, mask)
    warm, _ = fit_projective_motion(X0, mask, cameras=cameras)
    before, _ = projective_residuals(X0, mask, cameras, supported)
    after, _ = projective_residuals(X0, mask, warm, supported)
    assert np.sum(after) <= 1.001 * np.sum(before)


def test_refinement_with_a_perspective_background_keeps_the_truth():
    """From the true groups of a long hand-held draw, the affine refinement
    moves background tracks to the objects; the perspective background keeps
    them (6.4 % against 1.3 % on this draw)."""
    X, y = make_tracks(scene="handheld", n_tracks=400, random_state=3)
    inliers = y >= 0
    X, y = X[inliers], y[inliers]
    X0, mask = observed_entries(X)
    X0 = X0 / np.sqrt(np.mean(X0[mask] ** 2))
    random_state = np.random.RandomState(0)
    neighbors, _, _, weights = track_graph(X0, mask, 10, random_state=random_state)
    kwargs = dict(neighbors=neighbors[:, :10], neighbor_weights=weights)
    affine = refine_observed(X0, mask, y, 3, random_state=random_state, **kwargs)[0]
    perspective = refine_observed(
        X0, mask, y, 3, perspective_cluster=0, random_state=random_state, **kwargs
    )[0]
    assert misclassification_rate(y, perspective) < 0.02
    assert misclassification_rate(y, affine) > 0.05


def test_segment_motions_reports_the_perspective_candidates():
    X, y = make_tracks(scene="handheld", n_tracks=300, n_frames=60, random_state=3)
    inliers = y >= 0
    X, y = X[inliers], y[inliers]
    _, info = segment_motions(
        X, 3, screen_outliers=False, init="gpca", random_state=0, return_info=True
    )
    assert info.candidates == [
        "gpca",
        "gpca + perspective background",
        "gpca + perspective background, from its start",
    ]
    _, plain = segment_motions(
        X,
        3,
        screen_outliers=False,
        init="gpca",
        perspective_background=False,
        random_state=0,
        return_info=True,
    )
    assert plain.candidates == ["gpca"]
    np.testing.assert_array_equal(plain.refined[0], info.refined[0])


def test_a_motion_seen_only_mid_sequence_is_fitted():
    """The sequential fit starts where the motion is seen (an object that
    enters and leaves the view), not at the first frame."""
    noise = 1e-3
    X, _ = _scene(noise=noise, speed=4.0, seed=1, n_frames=20)
    X[:, :10] = np.nan
    X[:, 30:] = np.nan
    X = X[~np.isnan(X).all(axis=1)]
    X0, mask = observed_entries(X)
    cameras, supported = fit_projective_motion(X0, mask)
    np.testing.assert_array_equal(
        supported, (np.arange(20) >= 5) & (np.arange(20) < 15)
    )
    residuals, dofs = projective_residuals(X0, mask, cameras, supported)
    assert np.median(residuals[dofs > 0] / dofs[dofs > 0]) < 2.0 * noise**2


@pytest.mark.parametrize("scale", [2.0**-20, 1.0, 640.0, 2.0**30])
def test_units_do_not_matter(scale):
    """Pixels or normalised units: the same fit, residuals in the data's units."""
    noise = 1e-3
    X, _ = _scene(noise=noise, speed=4.0, seed=1)
    base = np.median(_per_dof(X))
    assert np.median(_per_dof(scale * X)) / scale**2 == pytest.approx(base, rel=1e-6)


def _numeric_jacobian(residual, x, step=1e-6):
    base = residual(x)
    columns = []
    for j in range(x.size):
        moved = x.copy()
        moved.flat[j] += step
        columns.append((residual(moved) - base) / step)
    return np.column_stack(columns)


def test_normal_equations_are_those_of_the_reprojection_error():
    """J^T J and J^T r of the batched steps, against finite differences of
    the reprojection residuals of one track (points) and one frame (camera)."""
    rng = np.random.default_rng(0)
    n_tracks, n_frames = 7, 5
    cameras = rng.standard_normal((n_frames, 3, 4))
    cameras[:, 2, 3] += 10.0  # every point well in front of every camera
    world = np.column_stack([rng.standard_normal((n_tracks, 3)), np.ones(n_tracks)])
    points = rng.standard_normal((n_tracks, n_frames, 2))
    seen = rng.random((n_tracks, n_frames)) < 0.7
    _, error, xy, depth = _point_costs(cameras, world, points, seen)

    gram, rhs = _point_normal_equations(cameras, error, xy, depth, seen)
    for p in range(n_tracks):

        def residual(point, p=p):
            return _point_costs(
                cameras, point[None], points[p : p + 1], seen[p : p + 1]
            )[1].ravel()

        jac = _numeric_jacobian(residual, world[p])
        np.testing.assert_allclose(gram[p], jac.T @ jac, rtol=1e-4, atol=1e-6)
        np.testing.assert_allclose(
            rhs[p], jac.T @ error[p].ravel(), rtol=1e-4, atol=1e-6
        )

    gram, rhs = _camera_normal_equations(world, error, xy, depth, seen)
    for f in range(n_frames):

        def residual(camera, f=f):
            moved = cameras.copy()
            moved[f] = camera.reshape(3, 4)
            return _point_costs(moved, world, points, seen)[1][:, f].ravel()

        jac = _numeric_jacobian(residual, cameras[f].ravel())
        np.testing.assert_allclose(gram[f], jac.T @ jac, rtol=1e-4, atol=1e-6)
        np.testing.assert_allclose(
            rhs[f], jac.T @ error[:, f].ravel(), rtol=1e-4, atol=1e-6
        )


def test_alternations_stop_once_converged(monkeypatch):
    import sklearn_gpca._projective_motion as module

    X, _ = _scene(noise=1e-3, seed=3)
    X0, mask = observed_entries(X)
    cameras, supported = fit_projective_motion(X0, mask)
    steps = []
    original = module._intersection_step

    def counted(*args, **kwargs):
        steps.append(1)
        return original(*args, **kwargs)

    monkeypatch.setattr(module, "_intersection_step", counted)
    early, _ = fit_projective_motion(X0, mask, cameras=cameras)
    # a converged start stops after few of its alternations
    assert len(steps) < module.WARM_ITERATIONS
    monkeypatch.setattr(module, "CONVERGED", 0.0)
    monkeypatch.setattr(module, "WARM_ITERATIONS", 50)
    full, _ = fit_projective_motion(X0, mask, cameras=cameras)
    # and the alternations it skipped would not have fitted the tracks better
    # by more than a thousandth
    stopped = np.sum(projective_residuals(X0, mask, early, supported)[0])
    longer = np.sum(projective_residuals(X0, mask, full, supported)[0])
    assert stopped <= 1.001 * longer
