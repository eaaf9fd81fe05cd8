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
