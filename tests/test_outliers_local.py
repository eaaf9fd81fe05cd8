"""Tests of the label-free local outlier test and of its place in segment_motions."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
from _outlier_draws import affine_lab_draw
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


def _two_motions(n, n_frames, noise, rng):
    """``n`` tracks of each of two independent affine motions (see _one_motion)."""
    return np.vstack([_one_motion(n, n_frames, noise, rng) for _ in range(2)])


def _plant_drifts(X, rows, sources, rng):
    """Rows slide onto ``sources`` after a frame s in 4 .. 15: drift tracks.

    ``x(t) = x(t)`` for ``t <= s``, ``x(s) + b(t) - b(s)`` after (``b`` the
    source track), as ``make_tracks``' drift outliers.
    """
    tracks = X.reshape(X.shape[0], -1, 2)
    switch = rng.randint(4, 16, size=rows.size)
    for row, b, s in zip(rows, sources, switch, strict=True):
        tracks[row, s + 1 :] = tracks[row, s] + tracks[b, s + 1 :] - tracks[b, s]


def test_planted_drifts_are_flagged():
    # A drift (make_tracks' most common outlier) follows a track a of motion
    # A up to frame s, then slides with a track b of motion B: x(t) = a(t)
    # for t <= s, a(s) + b(t) - b(s) after. Its displacements after s are
    # those of B's tracks, its position A's track's: on the window that
    # straddles s it is in neither motion's 4-D subspace, and B's camera
    # moves ~0.05 per frame, five noise deviations (0.01): all 10 drifts
    # flagged at 1e-3, at most 3 of the 390 inliers (nominal 0.4).
    rng = np.random.RandomState(7)
    X = _two_motions(200, 20, 0.01, rng)
    _plant_drifts(X, np.arange(10), 200 + np.arange(10), rng)
    drift = np.arange(400) < 10
    p = local_outlier_pvalues(*observed_entries(X))
    assert np.all(p[drift] < 1e-3)
    assert np.count_nonzero(p[~drift] < 1e-3) <= 3


def test_a_drift_under_a_translating_camera_is_an_inlier():
    # The limit of any test (benchmarks/results/outliers.md's ceiling): when
    # the second motion's image motion is a translation, x(t) = A P + t_t,
    # a drift a(s) + b(t) - b(s) = A P_a + t_t is exactly the track of a's
    # point: no test may flag it more often than an inlier. (Under a general
    # affine camera the drift is off by A_s (P_a - P_b), not a trajectory of
    # the motion: the drifts that make_tracks' ceiling misses follow motions
    # that nearly translate, or move alike, over their span.)
    rng = np.random.RandomState(8)
    points = rng.uniform(-1, 1, size=(300, 3))
    shifts = np.cumsum(0.05 * rng.normal(size=(20, 2)), axis=0)
    X = (points @ rng.normal(size=(2, 3)).T)[:, None, :] + shifts
    X = X.reshape(300, 40) + 0.01 * rng.normal(size=(300, 40))
    clean = X.copy()
    _plant_drifts(X, np.arange(10), 100 + np.arange(10), rng)
    # the drift is its first track, up to the noise (4 draws of 0.01)
    np.testing.assert_allclose(X[:10], clean[:10], atol=0.1)
    p = local_outlier_pvalues(*observed_entries(X))
    assert np.count_nonzero(p[:10] < 1e-3) <= 1
    assert np.count_nonzero(p < 1e-3) <= 3


def test_bad_inputs_are_refused():
    X0, mask = observed_entries(_one_motion(40, 8, 0.01, np.random.RandomState(5)))
    with pytest.raises(ValueError, match="mask must have the shape of X0"):
        local_outlier_pvalues(X0, mask[:, :-2])
    with pytest.raises(ValueError, match="window must be an integer >= 3"):
        local_outlier_pvalues(X0, mask, window=2)
    with pytest.raises(ValueError, match="window must be an integer >= 3"):
        local_outlier_pvalues(X0, mask, window=4.5)
    with pytest.raises(ValueError, match=r"one bool per track \(40\)"):
        local_outlier_pvalues(X0, mask, exclude=np.zeros(39, dtype=bool))


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
    X, y = affine_lab_draw(0)[:2]
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


@pytest.mark.filterwarnings("error::RuntimeWarning")
@pytest.mark.parametrize("seed", [0, 2, 3])
def test_noise_free_tracks_are_not_outliers_but_a_random_track_is(seed):
    from sklearn_gpca.datasets import make_motions

    X = make_motions(2, n_points=60, n_frames=8, noise=0.0, random_state=seed)[0]
    X0, mask = observed_entries(X)
    # rounding-level residuals over a rounding-level spread: no flag, no overflow
    assert np.all(local_outlier_pvalues(X0, mask) >= 1e-3)
    X[5] = np.random.RandomState(seed).normal(size=X.shape[1]) * X.std() + X.mean()
    X0, mask = observed_entries(X)
    flagged = np.flatnonzero(local_outlier_pvalues(X0, mask) < 1e-3)
    assert flagged.tolist() == [5]


def test_a_lone_coordinate_does_not_make_inliers_outliers():
    # every track misses x (not y) in its first frame, as some trackers
    # report a clipped coordinate; the neighbour distance pairs x and y, and
    # counting the lone y flagged about a third of the inliers (p < 1e-40)
    rng = np.random.RandomState(0)
    X = _one_motion(150, 12, 0.01, rng)
    X[:, 0] = np.nan
    pvalues = local_outlier_pvalues(*observed_entries(X))
    assert pvalues.min() > 1e-3


def test_segment_motions_screening_survives_a_lone_coordinate():
    X, y = make_tracks(scene="lab", n_tracks=120, n_frames=10, random_state=0)
    X, y = X[y >= 0], y[y >= 0]
    X[:, 0] = np.nan
    assert misclassification_rate(y, segment_motions(X, 2, random_state=0)) == 0.0


def test_empirical_null_absorbs_a_noise_level_per_track():
    # Real tracks' noise differs from track to track: here its deviation is
    # log-normal (0.6 in log) about 0.01. Against the F law alone about 18 %
    # of these inliers fall below 1e-3; the empirical null (the window's
    # score width, from its lower half) brings that under 8 %, and a Gaussian
    # cloud of one level is left as conservative as before (tested above).
    rng = np.random.RandomState(0)
    X = _one_motion(400, 24, 0.0, rng, missing=True)
    X += 0.01 * np.exp(rng.normal(scale=0.6, size=(400, 1))) * rng.normal(size=X.shape)
    X0, mask = observed_entries(X)
    widened = np.mean(local_outlier_pvalues(X0, mask) < 1e-3)
    plain = np.mean(local_outlier_pvalues(X0, mask, empirical_null=False) < 1e-3)
    assert plain > 0.12
    assert widened < 0.08


def test_real_hand_cleaned_tracks_are_rarely_flagged(hopkins155_dir):
    # Hopkins155's tracks were cleaned by hand, so every flag is a false
    # alarm. Their noise differs from track to track; the F law alone flags
    # about a fifth of them at 1e-3, the empirical null about one in sixteen
    # (benchmarks/results/false_alarms.md measures all 155 sequences).
    from sklearn_gpca.datasets import load_hopkins155

    flagged = {True: 0, False: 0}
    n_tracks = 0
    for sequence in load_hopkins155(
        hopkins155_dir, sequences=["1R2RC", "cars2B_g12", "kanatani3", "three-cars"]
    ):
        X0, mask = observed_entries(sequence.X)
        n_tracks += len(X0)
        for null in flagged:
            p = local_outlier_pvalues(X0, mask, empirical_null=null)
            flagged[null] += np.count_nonzero(p < 1e-3)
    assert flagged[True] < 0.1 * n_tracks
    assert flagged[True] < 0.5 * flagged[False]
