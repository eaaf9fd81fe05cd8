"""Tests of the two-view check of the outlier test under strong perspective."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest

from sklearn_gpca import segment_motions
from sklearn_gpca._epipolar_outliers import (
    PERSPECTIVE_DEVIATION,
    epipolar_outlier_pvalues,
    perspective_checked_pvalues,
)
from sklearn_gpca._local_outliers import local_outlier_pvalues
from sklearn_gpca._observed_subspaces import observed_entries
from sklearn_gpca.datasets import make_tracks


def _forward_scene(n, n_frames, noise, rng, near=4.0, far=40.0, travel=3.0):
    """A static scene seen by a pinhole camera driving forward (focal length 1).

    Points at depths log-uniform in ``[near, far]``, seen at image positions
    uniform in ``[-0.8, 0.8]^2`` in the first frame; the camera travels
    ``travel`` along its axis, drifts sideways and turns slowly (yaw 0.05).
    Every track is complete; Gaussian noise of deviation ``noise`` on every
    coordinate. A near point's trajectory ``(X - C_t) / (Z - c_t)`` bends far
    from the 4-D subspace of an affine camera.
    """
    depth = np.exp(rng.uniform(np.log(near), np.log(far), n))
    image = rng.uniform(-0.8, 0.8, (n, 2))
    points = np.column_stack([image * depth[:, None], depth])
    t = np.linspace(0.0, 1.0, n_frames)
    centres = np.column_stack([0.3 * t**2, 0.05 * np.sin(3 * t), travel * t])
    c, s = np.cos(0.05 * t), np.sin(0.05 * t)
    zero, one = np.zeros_like(t), np.ones_like(t)
    rotations = np.stack(
        [
            np.stack([c, zero, s], axis=1),
            np.stack([zero, one, zero], axis=1),
            np.stack([-s, zero, c], axis=1),
        ],
        axis=1,
    )
    # camera coordinates R_t^T (P - C_t)
    local = np.einsum("fji,pfj->pfi", rotations, points[:, None] - centres[None])
    x = local[..., :2] / local[..., 2:]
    return x.reshape(n, 2 * n_frames) + noise * rng.normal(size=(n, 2 * n_frames))


@pytest.mark.parametrize("seed", [0, 1])
def test_epipolar_pvalues_of_a_perspective_scene_are_conservative(seed):
    # One rigid motion, any depth: the epipolar constraint holds exactly, so
    # P(p < alpha) <= alpha per track (Bonferroni over the frame pairs), up
    # to three binomial standard deviations over 400 tracks.
    X = _forward_scene(400, 12, 0.002, np.random.RandomState(seed))
    p, deviation = epipolar_outlier_pvalues(*observed_entries(X), 1, random_state=seed)
    for alpha in (0.05, 0.2):
        slack = 3 * np.sqrt(alpha * (1 - alpha) / p.size)
        assert np.mean(p < alpha) <= alpha + slack
    assert np.mean(p < 0.2) > 0.02  # not degenerate
    # strongly perspective: an affine camera misfits by many noise deviations
    assert deviation > 2 * PERSPECTIVE_DEVIATION


def test_checked_test_keeps_the_near_tracks_the_local_test_flags():
    # The local test's linear model misfits the nearest points of a forward
    # motion (many times the nominal rate flagged at 1e-3); flagged only
    # when the two-view test also rejects them, inliers are flagged at most
    # at the nominal rate (3 binomial deviations over 400 tracks: < 4 tracks).
    X = _forward_scene(400, 12, 0.002, np.random.RandomState(1))
    X0, mask = observed_entries(X)
    local = local_outlier_pvalues(X0, mask)
    assert np.mean(local < 1e-3) > 0.01
    checked = perspective_checked_pvalues(X0, mask, local, 1, random_state=0)
    assert np.all(checked >= local)
    assert np.count_nonzero(checked < 1e-3) <= 0.001 * 400 + 3 * np.sqrt(0.4)


def test_planted_outliers_on_a_perspective_scene_are_flagged():
    # 20 of 400 rows replaced: 10 random walks (steps of 0.02 per
    # coordinate, the size of the near points' motion per frame) and 10
    # jumps, from a frame between 3 and 8 on, to the track farthest away
    # (a tracker locking onto another feature). Neither is the image of a
    # rigid point, and both tests reject all of them by far.
    rng = np.random.RandomState(2)
    X = _forward_scene(400, 12, 0.002, rng)
    walks = np.cumsum(rng.normal(scale=0.02, size=(10, 12, 2)), axis=1)
    X[:10] = np.tile(X[:10, :2], 12) + walks.reshape(10, 24)
    for row, s in zip(range(10, 20), 2 * rng.randint(3, 9, size=10), strict=True):
        far = 20 + np.argmax(np.sum((X[20:, s : s + 2] - X[row, s : s + 2]) ** 2, 1))
        X[row, s:] = X[far, s:]
    X0, mask = observed_entries(X)
    local = local_outlier_pvalues(X0, mask)
    checked = perspective_checked_pvalues(X0, mask, local, 1, random_state=0)
    assert np.all(checked[:20] < 1e-6)
    assert np.count_nonzero(checked[20:] < 1e-3) <= 3


def test_affine_scene_keeps_the_local_pvalues():
    # Far points (depths 400-440) and a short travel: an affine camera
    # explains the motion, the affine deviation is about 1 noise deviation,
    # and the local test's p-values are returned unchanged.
    X = _forward_scene(150, 10, 0.002, np.random.RandomState(3), 400.0, 440.0, 3.0)
    X0, mask = observed_entries(X)
    _, deviation = epipolar_outlier_pvalues(X0, mask, 1, random_state=0)
    assert deviation < 2.0
    local = local_outlier_pvalues(X0, mask)
    checked = perspective_checked_pvalues(X0, mask, local, 1, random_state=0)
    np.testing.assert_array_equal(checked, local)


def test_tracks_in_no_tested_pair_get_pvalue_zero():
    # A p-value of 0 means no evidence of fitting: such a track's flag is
    # the local test's alone. Tracks seen in one frame are in no pair;
    # with fewer than MIN_SUPPORT tracks no pair is tested at all.
    rng = np.random.RandomState(4)
    X = _forward_scene(200, 8, 0.002, rng)
    X[:5, 2:] = np.nan
    p, _ = epipolar_outlier_pvalues(*observed_entries(X), 1, random_state=0)
    assert np.all(p[:5] == 0.0)
    assert np.all(p[5:] > 0.0)
    p, deviation = epipolar_outlier_pvalues(*observed_entries(X[5:15]), 1)
    assert np.all(p == 0.0) and deviation == 0.0


def test_segment_motions_flags_with_the_checked_test_on_a_driving_draw():
    # On a driving draw (strong perspective) the tracks set aside are those
    # both tests reject: fewer than the local test's flags, with a larger
    # share of true outliers; the -1 of segment_motions are those of them
    # that no segmented motion's model explains either
    # (sklearn_gpca._explained_outliers), at least as pure.
    X, y = make_tracks(
        scene="driving", n_tracks=150, n_frames=12, outlier_fraction=0.1, random_state=0
    )
    labels, info = segment_motions(
        X, 3, outlier_threshold=1e-3, random_state=0, return_info=True
    )
    X0, mask = observed_entries(X)
    local = local_outlier_pvalues(X0, mask)
    checked = perspective_checked_pvalues(X0, mask, local, 3, random_state=0)
    flagged, set_aside, local_flagged = labels == -1, checked < 1e-3, local < 1e-3
    assert not np.any(flagged & ~set_aside)
    np.testing.assert_array_equal(info.outlier_pvalues[~set_aside], checked[~set_aside])
    assert np.all(info.outlier_pvalues >= checked)
    np.testing.assert_array_equal(flagged, info.outlier_pvalues < 1e-3)
    assert np.sum(set_aside) < np.sum(local_flagged)
    assert np.mean(y[set_aside] == -1) > np.mean(y[local_flagged] == -1)
    assert np.mean(y[flagged] == -1) >= np.mean(y[set_aside] == -1)


@pytest.mark.parametrize("noise", [0.0, 0.002])
def test_degenerate_points_give_no_model_not_a_crash(noise):
    # Every track at the same x (a tracker stuck on a vertical edge, or a
    # column of constants): the first model explains the pairs exactly, its
    # scale is TINY, and its refit keeps none of them: the pair has no model.
    X = _forward_scene(120, 6, noise, np.random.RandomState(5))
    X[:, ::2] = 3.0
    p, deviation = epipolar_outlier_pvalues(*observed_entries(X), 2, random_state=0)
    assert p.shape == (120,) and np.all((p >= 0) & (p <= 1))
    assert np.isfinite(deviation)
