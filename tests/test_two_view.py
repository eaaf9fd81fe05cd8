"""Two-view geometry: exact models from synthetic cameras, brute-force residuals."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose

from sklearn_gpca._two_view import (
    fit_fundamental,
    fit_homography,
    normalizing_transforms,
    sampson_fundamental,
    sampson_homography,
)


def _rotation(rng, angle):
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    K = np.array(
        [[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]]
    )
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def _cross(t):
    return np.array([[0, -t[2], t[1]], [t[2], 0, -t[0]], [-t[1], t[0], 0]])


def _camera_pair(seed, n_points=30, planar=False):
    """Points seen by two calibrated pinhole cameras, and the true F and H.

    Camera 1 is ``[I | 0]``, camera 2 ``[R | t]``; ``F = [t]_x R`` (HZ
    result 9.9 with K = I) and, for points on the plane ``n.X = d``,
    ``H = R + t n^T / d`` (HZ result 13.1).
    """
    rng = np.random.RandomState(seed)
    R, t = _rotation(rng, 0.2), rng.normal(scale=0.5, size=3)
    n, d = np.array([0.1, -0.2, 1.0]), 6.0
    if planar:
        xy = rng.uniform(-2, 2, (n_points, 2))
        z = (d - xy @ n[:2]) / n[2]
        P = np.c_[xy, z]
    else:
        P = rng.uniform(-2, 2, (n_points, 3)) + np.array([0.0, 0.0, 6.0])
    Q = P @ R.T + t
    x1, x2 = P[:, :2] / P[:, 2:], Q[:, :2] / Q[:, 2:]
    return x1, x2, _cross(t) @ R, R + np.outer(t, n) / d


def _normalized(M):
    M = M / np.linalg.norm(M)
    return M * np.sign(M.flat[np.argmax(np.abs(M))])


@pytest.mark.parametrize("seed", range(4))
def test_fundamental_from_exact_correspondences_is_the_true_one(seed):
    x1, x2, F_true, _ = _camera_pair(seed)
    F = fit_fundamental(x1[None, :8], x2[None, :8])[0]
    assert_allclose(_normalized(F), _normalized(F_true), atol=1e-8)
    assert np.linalg.matrix_rank(F, tol=1e-10) == 2
    assert sampson_fundamental(F[None], x1, x2).max() < 1e-10


@pytest.mark.parametrize("seed", range(4))
def test_homography_of_a_plane_is_the_true_one(seed):
    x1, x2, _, H_true = _camera_pair(seed, planar=True)
    H = fit_homography(x1[None, :4], x2[None, :4])[0]
    assert_allclose(_normalized(H), _normalized(H_true), atol=1e-8)
    assert sampson_homography(H[None], x1, x2).max() < 1e-10


def test_off_plane_points_do_not_fit_the_homography():
    x1, x2, _, H = _camera_pair(0, planar=False)
    assert np.median(sampson_homography(H[None], x1, x2)) > 1e-3


def test_batches_are_independent():
    """A batch gives, hypothesis by hypothesis, what each sample gives alone."""
    x1, x2, _, _ = _camera_pair(1, n_points=40)
    rng = np.random.RandomState(0)
    samples = np.array([rng.permutation(40)[:8] for _ in range(5)])
    F = fit_fundamental(x1[samples], x2[samples])
    H = fit_homography(x1[samples[:, :4]], x2[samples[:, :4]])
    for k, s in enumerate(samples):
        assert_allclose(
            _normalized(F[k]), _normalized(fit_fundamental(x1[None, s], x2[None, s])[0])
        )
        assert_allclose(
            _normalized(H[k]),
            _normalized(fit_homography(x1[None, s[:4]], x2[None, s[:4]])[0]),
        )


def _sampson_fundamental_loop(F, x1, x2):
    """HZ equation 11.9, one point and one matrix at a time."""
    out = np.empty((x1.shape[0], F.shape[0]))
    for p in range(x1.shape[0]):
        a, b = np.r_[x1[p], 1.0], np.r_[x2[p], 1.0]
        for h in range(F.shape[0]):
            Fa, Ftb = F[h] @ a, F[h].T @ b
            out[p, h] = abs(b @ F[h] @ a) / np.sqrt(
                Fa[0] ** 2 + Fa[1] ** 2 + Ftb[0] ** 2 + Ftb[1] ** 2
            )
    return out


def _sampson_homography_loop(H, x1, x2):
    """HZ section 4.2.6 with a numerical Jacobian, one point at a time."""
    out = np.empty((x1.shape[0], H.shape[0]))

    def errors(v, M):
        w = M[2] @ np.r_[v[:2], 1.0]
        return np.array(
            [
                v[2] * w - M[0] @ np.r_[v[:2], 1.0],
                v[3] * w - M[1] @ np.r_[v[:2], 1.0],
            ]
        )

    for p in range(x1.shape[0]):
        v = np.r_[x1[p], x2[p]]
        for h in range(H.shape[0]):
            J = np.column_stack(
                [
                    (errors(v + 1e-6 * e, H[h]) - errors(v - 1e-6 * e, H[h])) / 2e-6
                    for e in np.eye(4)
                ]
            )
            e = errors(v, H[h])
            out[p, h] = np.sqrt(e @ np.linalg.solve(J @ J.T, e))
    return out


def test_sampson_distances_match_a_point_by_point_computation():
    rng = np.random.RandomState(3)
    x1, x2 = rng.uniform(-1, 1, (12, 2)), rng.uniform(-1, 1, (12, 2))
    M = rng.normal(size=(4, 3, 3))
    assert_allclose(
        sampson_fundamental(M, x1, x2), _sampson_fundamental_loop(M, x1, x2), rtol=1e-10
    )
    assert_allclose(
        sampson_homography(M, x1, x2), _sampson_homography_loop(M, x1, x2), rtol=1e-6
    )


def test_sampson_distance_is_first_order_geometric_distance():
    """Moving x2 by a small distance off its exact position moves it that far."""
    x1, x2, F, H = _camera_pair(2, planar=True)
    rng = np.random.RandomState(0)
    # Displace x2 along the epipolar line's normal by 1e-4: Sampson ~ 1e-4
    # (the first-order distance of (x1, x2) to the variety is at most that).
    line = (F @ np.c_[x1, np.ones(len(x1))].T).T
    normal = line[:, :2] / np.linalg.norm(line[:, :2], axis=1, keepdims=True)
    d = sampson_fundamental(F[None], x1, x2 + 1e-4 * normal)[:, 0]
    assert np.all(d > 0.3e-4) and np.all(d <= 1.0001e-4)
    shift = rng.normal(size=x2.shape)
    shift *= 1e-4 / np.linalg.norm(shift, axis=1, keepdims=True)
    d = sampson_homography(H[None], x1, x2 + shift)[:, 0]
    assert np.all(d > 0.3e-4) and np.all(d <= 1.0001e-4)


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 10_000), planar=st.booleans())
def test_models_do_not_depend_on_the_order_of_the_sample(seed, planar):
    x1, x2, _, _ = _camera_pair(seed % 50, planar=planar)
    noisy = x2 + np.random.RandomState(seed).normal(scale=1e-3, size=x2.shape)
    order = np.random.RandomState(seed + 1).permutation(12)
    for fit in (fit_fundamental, fit_homography):
        a = fit(x1[None, :12], noisy[None, :12])[0]
        b = fit(x1[None, order], noisy[None, order])[0]
        assert_allclose(_normalized(a), _normalized(b), atol=1e-9)


def test_scale_of_the_model_does_not_change_sampson_distances():
    rng = np.random.RandomState(5)
    x1, x2 = rng.uniform(-1, 1, (6, 2)), rng.uniform(-1, 1, (6, 2))
    M = rng.normal(size=(3, 3, 3))
    for sampson in (sampson_fundamental, sampson_homography):
        assert_allclose(sampson(-7.5 * M, x1, x2), sampson(M, x1, x2), rtol=1e-12)


def test_normalizing_transforms_centre_and_scale():
    rng = np.random.RandomState(0)
    points = rng.normal(loc=5, scale=3, size=(4, 10, 2))
    T = normalizing_transforms(points)
    moved = np.einsum(
        "bij,bnj->bni", T, np.concatenate([points, np.ones((4, 10, 1))], axis=-1)
    )[..., :2]
    assert_allclose(moved.mean(axis=1), 0, atol=1e-12)
    assert_allclose(np.linalg.norm(moved, axis=-1).mean(axis=1), np.sqrt(2))
    coincident = normalizing_transforms(np.ones((3, 2)))
    assert_allclose(coincident[:2, :2], np.eye(2))


def test_fundamental_matrices_have_rank_two_on_noisy_samples():
    x1, x2, _, _ = _camera_pair(7, n_points=20)
    noisy = x2 + np.random.RandomState(0).normal(scale=1e-2, size=x2.shape)
    F = fit_fundamental(np.stack([x1[:12], x1[8:]]), np.stack([noisy[:12], noisy[8:]]))
    singular = np.linalg.svd(F, compute_uv=False)
    assert_allclose(singular[:, 2] / singular[:, 0], 0, atol=1e-12)


def test_models_follow_a_change_of_units():
    """Hartley normalisation: scaling the images scales the distances."""
    x1, x2, _, _ = _camera_pair(4, n_points=20)
    noisy = x2 + np.random.RandomState(0).normal(scale=1e-3, size=x2.shape)
    for fit, sampson, n in (
        (fit_fundamental, sampson_fundamental, 10),
        (fit_homography, sampson_homography, 6),
    ):
        M = fit(x1[None, :n], noisy[None, :n])
        M_px = fit(640 * x1[None, :n], 640 * noisy[None, :n])
        assert_allclose(
            sampson(M_px, 640 * x1, 640 * noisy),
            640 * sampson(M, x1, noisy),
            rtol=1e-6,
        )
