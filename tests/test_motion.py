import numpy as np
import pytest
from numpy.testing import assert_allclose

from sklearn_gpca import estimate_motions


def two_bodies(n_frames=8, seed=0):
    rng = np.random.RandomState(seed)
    X, y, truth = [], [], []
    for label, n_points in enumerate([25, 35]):
        cameras = rng.standard_normal((2 * n_frames, 4))
        points = np.c_[rng.standard_normal((n_points, 3)), np.ones(n_points)]
        X.append(points @ cameras.T)
        y.append(np.full(n_points, label))
        truth.append((cameras, points))
    return np.vstack(X), np.concatenate(y), truth


def test_recovers_motion_and_structure_up_to_an_affinity():
    X, y, truth = two_bodies()
    X[np.random.RandomState(1).rand(*X.shape) < 0.2] = np.nan
    motions = estimate_motions(X, y, random_state=0)
    assert [m.label for m in motions] == [0, 1]
    for motion, (cameras, points) in zip(motions, truth, strict=True):
        assert motion.residual < 1e-6
        assert_allclose(motion.structure[:, 3], 1.0, atol=1e-6)
        # the recovered points are an affine image of the true ones
        affine = np.linalg.lstsq(points, motion.structure, rcond=None)[0]
        assert_allclose(points @ affine, motion.structure, atol=1e-6)
        # and the cameras reproduce every entry, observed or not
        complete = points @ cameras.T
        assert_allclose(motion.structure @ motion.motion.T, complete, atol=1e-6)


def test_outliers_are_ignored():
    X, y, _ = two_bodies()
    y[:3] = -1
    assert len(estimate_motions(X, y, random_state=0)) == 2


def test_small_group_is_named():
    X, y, _ = two_bodies()
    y[:3] = 7
    with pytest.raises(ValueError, match="Group 7 has 3 trajectories"):
        estimate_motions(X, y)


def test_length_mismatch():
    X, y, _ = two_bodies()
    with pytest.raises(ValueError, match="inconsistent numbers of samples"):
        estimate_motions(X, y[:-1])


# --- against a least-squares reference on noisy data ----------------------


def rank4_reference(W, mask=None, n_iter=5000):
    """Best rank-4 fit of ``W`` on its observed entries, ``(fit, rms)``.

    Complete data: the truncated SVD (Eckart-Young). Missing data: plain
    alternating least squares on the observed entries from the SVD of the
    zero-filled matrix, run to convergence (an independent solver).
    """
    if mask is None:
        U, s, Vt = np.linalg.svd(W, full_matrices=False)
        fit = (U[:, :4] * s[:4]) @ Vt[:4]
        return fit, np.sqrt(np.mean((W - fit) ** 2))
    filled = np.where(mask, W, 0.0)
    U, s, Vt = np.linalg.svd(filled, full_matrices=False)
    B = U[:, :4] * s[:4]
    previous = np.inf
    for _ in range(n_iter):
        A = np.array(
            [
                np.linalg.lstsq(B[m], w[m], rcond=None)[0]
                for w, m in zip(filled.T, mask.T, strict=True)
            ]
        )
        B = np.array(
            [
                np.linalg.lstsq(A[m], w[m], rcond=None)[0]
                for w, m in zip(filled, mask, strict=True)
            ]
        )
        cost = np.sum((W - B @ A.T)[mask] ** 2)
        if previous - cost <= 1e-13 * cost:
            break
        previous = cost
    fit = B @ A.T
    return fit, np.sqrt(np.mean((W - fit)[mask] ** 2))


def noisy_bodies(noise, seed=0):
    X, y, _ = two_bodies(seed=seed)
    X = X + noise * np.random.RandomState(seed + 10).standard_normal(X.shape)
    return X, y


def affine_residual(points, reference):
    """Largest misfit of ``points`` by an affine image of ``reference``."""
    design = np.c_[reference, np.ones(len(reference))]
    affine = np.linalg.lstsq(design, points, rcond=None)[0]
    return np.abs(design @ affine - points).max()


def test_residual_and_points_match_least_squares_on_noisy_complete_data():
    X, y = noisy_bodies(noise=0.05)
    motions = estimate_motions(X, y, random_state=0)
    for motion in motions:
        W = X[y == motion.label]
        fit, rms = rank4_reference(W)
        assert rms > 0.01  # the noise is visible in the residual
        assert_allclose(motion.residual, rms, rtol=1e-6)
        assert_allclose(motion.structure @ motion.motion.T, fit, atol=1e-6)
        # The homogeneous coordinate is the projection of the ones vector on
        # the column space of the fit (least squares), not exactly 1.
        U = np.linalg.svd(W, full_matrices=False)[0][:, :4]
        w = U @ (U.T @ np.ones(len(W)))
        assert_allclose(motion.structure[:, 3], w, atol=1e-6)
        assert np.ptp(w) > 1e-4
        # points_3d = structure[:, :3] / w is an affine image of any other
        # basis of the same space divided by w.
        basis = np.linalg.svd((U.T @ np.ones(len(W)))[None, :])[2][1:]
        reference = (U @ basis.T) / w[:, None]
        assert motion.points_3d.shape == (len(W), 3)
        assert affine_residual(motion.points_3d, reference) < 1e-6
        assert affine_residual(motion.structure[:, :3], reference) > 1e-3


def test_residual_matches_least_squares_on_noisy_incomplete_data():
    X, y = noisy_bodies(noise=0.05, seed=1)
    mask = np.random.RandomState(2).rand(*X.shape) > 0.2
    mask[:, 0::2] = mask[:, 1::2]
    motions = estimate_motions(np.where(mask, X, np.nan), y, random_state=0)
    for motion in motions:
        rows = y == motion.label
        fit, rms = rank4_reference(X[rows], mask[rows])
        assert rms > 0.01
        assert_allclose(motion.residual, rms, rtol=1e-4)
        fitted = motion.structure @ motion.motion.T
        assert_allclose(fitted[mask[rows]], fit[mask[rows]], atol=1e-4)


# --- bad labels: clear errors ----------------------------------------------


@pytest.mark.parametrize(
    ("make_labels", "match"),
    [
        (lambda y: np.array(["a", "b"])[y], r"^labels must be integers.*<U1\.$"),
        (lambda y: np.r_[y[:-1], 2.5], r"^labels must be integers.*got 2.5\.$"),
        (lambda y: y[:, None], r"labels must be 1-D.*\(60, 1\)"),
        (lambda y: np.c_[y, y], r"labels must be 1-D.*\(60, 2\)"),
    ],
    ids=["strings", "fractions", "column", "2-D"],
)
def test_bad_labels_are_named(make_labels, match):
    X, y, _ = two_bodies()
    with pytest.raises(ValueError, match=match):
        estimate_motions(X, make_labels(y))


def test_integral_float_labels_are_accepted():
    X, y, _ = two_bodies()
    motions = estimate_motions(X, y.astype(float), random_state=0)
    assert [m.label for m in motions] == [0, 1]
    assert all(isinstance(m.label, np.integer) for m in motions)


def test_group_of_exactly_four_trajectories_is_factorised():
    X, y, _ = two_bodies()
    y[4:25] = -1  # group 0 keeps trajectories 0-3
    motions = estimate_motions(X, y, random_state=0)
    assert motions[0].structure.shape == (4, 4)
    assert motions[0].points_3d.shape == (4, 3)


def test_same_random_state_same_result():
    X, y = noisy_bodies(noise=0.05)
    X[np.random.RandomState(3).rand(*X.shape) < 0.2] = np.nan
    first = estimate_motions(X, y, random_state=0)
    second = estimate_motions(X, y, random_state=0)
    for a, b in zip(first, second, strict=True):
        np.testing.assert_array_equal(a.motion, b.motion)
        np.testing.assert_array_equal(a.points_3d, b.points_3d)


def test_group_without_enough_observed_entries_is_named():
    X, y, _ = two_bodies()
    X[y == 1, 2:] = np.nan  # group 1 seen in one frame: no rank-4 fit is determined
    with pytest.raises(ValueError, match=r"^Group 1: .*observed entries"):
        estimate_motions(X, y, random_state=0)


def test_all_zero_group_is_named():
    X, y, _ = two_bodies()
    X[y == 1] = 0.0
    with pytest.raises(ValueError, match=r"Group 1: every observed entry is 0"):
        estimate_motions(X, y, random_state=0)
