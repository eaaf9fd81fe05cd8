"""Tests of the label-free local outlier test and of its place in segment_motions."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from sklearn_gpca import segment_motions
from sklearn_gpca._local_outliers import local_outlier_pvalues
from sklearn_gpca._observed_subspaces import observed_entries
from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.metrics import misclassification_rate


def _one_motion(n, n_frames, noise, rng, missing=False):
    """Tracks of one rigid motion seen by an affine camera, plus Gaussian noise.

    ``x_f = A_f P + t_f`` for 3-D points ``P`` in the unit cube, the camera
    ``A_f, t_f`` drifting smoothly (steps of about 0.05): rows on a 4-D
    subspace of ``R^{2F}``; with ``missing``, each track is seen on one
    window of frames.
    """
    points = rng.uniform(-1, 1, size=(n, 3))
    cameras = rng.normal(size=(2, 3)) + np.cumsum(
        0.05 * rng.normal(size=(n_frames, 2, 3)), axis=0
    )
    shifts = np.cumsum(0.05 * rng.normal(size=(n_frames, 2)), axis=0)
    X = np.einsum("fij,pj->pfi", cameras, points) + shifts
    X = X.reshape(n, 2 * n_frames) + noise * rng.normal(size=(n, 2 * n_frames))
    if missing:
        length = rng.randint(4, n_frames + 1, size=n)
        birth = rng.randint(0, n_frames - length + 1)
        frames = np.arange(n_frames)
        seen = (frames >= birth[:, None]) & (frames < (birth + length)[:, None])
        X[~np.repeat(seen, 2, axis=1)] = np.nan
    return X


@pytest.mark.parametrize("missing", [False, True])
def test_pvalues_of_gaussian_inliers_are_conservative(missing):
    # One affine motion (every neighbourhood pure) with Gaussian noise: the
    # null of the test. P(p < alpha) <= alpha per track (Bonferroni over the
    # windows), up to three binomial standard deviations over 500 tracks.
    rng = np.random.RandomState(0)
    X = _one_motion(500, 24, 0.01, rng, missing=missing)
    p = local_outlier_pvalues(*observed_entries(X))
    for alpha in (0.05, 0.2):
        slack = 3 * np.sqrt(alpha * (1 - alpha) / p.size)
        assert np.mean(p < alpha) <= alpha + slack
    # ... and not degenerate: a good share of the p-values is small
    assert np.mean(p < 0.2) > 0.05


def test_planted_outliers_are_flagged():
    # 300 tracks of one motion; 20 rows replaced: 10 random walks (steps of
    # 0.05 per coordinate, the size of the camera's), 10 jumps to the track
    # farthest away from a frame between 4 and 15 on (a tracker locking onto
    # another feature). Each misfits any 5-D subspace of its co-moving
    # neighbours on the window of its switch by far more than the noise
    # (0.01); some of those neighbours are other outliers (they are the
    # tracks that move least like the inliers), which inflates the local
    # noise: all flagged at 1e-4; no inlier at 1e-6 (280 inliers).
    rng = np.random.RandomState(1)
    X = _one_motion(300, 20, 0.01, rng)
    walks = np.cumsum(rng.normal(scale=0.05, size=(10, 20, 2)), axis=1)
    X[:10] = np.tile(X[:10, :2], 20) + walks.reshape(10, 40)
    switch = 2 * rng.randint(4, 16, size=10)
    for row, s in zip(range(10, 20), switch, strict=True):
        # onto the inlier farthest from it at the switch (a jump of ~1-3)
        far = 20 + np.argmax(np.sum((X[20:, s : s + 2] - X[row, s : s + 2]) ** 2, 1))
        X[row, s:] = X[far, s:]
    p = local_outlier_pvalues(*observed_entries(X))
    assert np.all(p[:20] < 1e-4)
    assert np.all(p[20:] >= 1e-6)


def test_excluded_tracks_are_no_ones_neighbour():
    # 30 complete random walks among inliers each seen on a window of
    # frames: the tracks seen in all of a walk's frames are mostly walks, so
    # a walk's neighbourhood is walks and its local noise theirs (some
    # walks pass). With the walks excluded from every neighbourhood, a walk
    # is compared with the inliers that cover it, and all fail.
    rng = np.random.RandomState(6)
    X = _one_motion(300, 20, 0.01, rng, missing=True)
    walks = np.cumsum(rng.normal(scale=0.05, size=(30, 20, 2)), axis=1)
    X[:30] = walks.reshape(30, 40)
    walk = np.arange(300) < 30
    mixed = local_outlier_pvalues(*observed_entries(X))
    assert np.any(mixed[walk] > 1e-3)
    apart = local_outlier_pvalues(*observed_entries(X), exclude=walk)
    assert np.all(apart[walk] < 1e-12)
    assert np.all(apart[~walk] >= 1e-4)


def test_pvalues_scale_free_and_shape():
    rng = np.random.RandomState(2)
    X = _one_motion(120, 12, 0.01, rng, missing=True)
    p = local_outlier_pvalues(*observed_entries(X))
    assert p.shape == (120,)
    assert np.all((p >= 0) & (p <= 1))
    np.testing.assert_allclose(
        local_outlier_pvalues(*observed_entries(1000.0 * X)), p, rtol=1e-6
    )


@settings(max_examples=10, deadline=None)
@given(order=st.permutations(range(60)))
def test_pvalues_follow_a_permutation_of_the_tracks(order):
    rng = np.random.RandomState(3)
    X = _one_motion(60, 10, 0.01, rng, missing=True)
    X[:3] = rng.normal(size=(3, 20))  # outliers
    p = local_outlier_pvalues(*observed_entries(X))
    order = np.asarray(order)
    np.testing.assert_allclose(
        local_outlier_pvalues(*observed_entries(X[order])), p[order], rtol=1e-9
    )


def test_untestable_tracks_get_pvalue_one():
    rng = np.random.RandomState(4)
    X = _one_motion(80, 10, 0.01, rng)
    X[:5] = np.nan
    X[:5, 6:10] = rng.normal(size=(5, 4))  # seen in 2 frames, anywhere
    assert np.all(local_outlier_pvalues(*observed_entries(X))[:5] == 1.0)
    # too few tracks for any neighbourhood
    assert np.all(local_outlier_pvalues(*observed_entries(X[:6])) == 1.0)


def test_segment_motions_sets_outliers_aside_before_segmenting():
    # The -1 of segment_motions are the local test's flags, and the other
    # tracks are segmented as if the flagged ones were not there.
    X, y = make_tracks(
        scene="lab",
        camera="affine",
        n_tracks=150,
        n_frames=12,
        missing=0,
        outlier_fraction=0.1,
        random_state=0,
    )
    labels, info = segment_motions(
        X, 2, outlier_threshold=1e-3, random_state=0, return_info=True
    )
    flagged = local_outlier_pvalues(*observed_entries(X)) < 1e-3
    np.testing.assert_array_equal(labels == -1, flagged)
    np.testing.assert_array_equal(info.outliers, flagged)
    np.testing.assert_array_equal(info.outlier_pvalues < 1e-3, flagged)
    assert 0 < np.sum(flagged) <= np.sum(y == -1)
    alone = segment_motions(X[~flagged], 2, random_state=0)
    np.testing.assert_array_equal(labels[~flagged], alone)
    assert misclassification_rate(y[y >= 0], labels[y >= 0]) <= 0.02


def test_given_init_of_the_wrong_length_is_refused():
    X = _one_motion(40, 8, 0.01, np.random.RandomState(5))
    with pytest.raises(ValueError, match=r"one label in 0 \.\. 1 per track \(40\)"):
        segment_motions(X, 2, init=np.zeros(39, dtype=int), outlier_threshold=1e-3)
