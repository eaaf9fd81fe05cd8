"""Tests for the synthetic generators make_motions and make_transparent."""

# SPDX-License-Identifier: BSD-3-Clause

import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose, assert_array_equal
from scipy.linalg import subspace_angles

from sklearn_gpca.datasets import make_missing, make_motions, make_transparent
from sklearn_gpca.datasets._missing import MIN_FRAMES_PER_TRACK, MIN_POINTS_PER_FRAME
from sklearn_gpca.datasets._motions import _MOTION_DIMS, _structure, _translations


def numerical_rank(A, rtol=1e-9):
    s = np.linalg.svd(A, compute_uv=False)
    return int(np.sum(s > rtol * s[0]))


def observed_frames(X):
    return ~np.isnan(X[:, 0::2])


def largest_angles(X, y, dims):
    """Largest principal angle (degrees) between the row spaces of each pair."""
    bases = [
        np.linalg.svd(X[y == k], full_matrices=False)[2][:dim].T
        for k, dim in enumerate(dims)
    ]
    return {
        (i, j): np.degrees(subspace_angles(bases[i], bases[j]).max())
        for i in range(len(bases))
        for j in range(i)
    }


@pytest.mark.parametrize("n_motions", [1, 2, 3])
@pytest.mark.parametrize("n_frames", [3, 10])
def test_shapes_and_labels(n_motions, n_frames):
    X, y = make_motions(n_motions, 61, n_frames, n_outliers=4, random_state=0)
    assert X.shape == (65, 2 * n_frames)
    assert X.dtype == np.float64
    assert y.shape == (65,)
    assert np.issubdtype(y.dtype, np.integer)
    assert_array_equal(np.unique(y), np.arange(-1, n_motions))
    sizes = np.bincount(y[y >= 0])
    assert sizes.sum() == 61
    assert sizes.max() - sizes.min() <= 1
    assert np.sum(y == -1) == 4
    assert np.all(np.isfinite(X))
    # Pixel-like coordinates in (roughly) a 640 x 480 image.
    assert X[:, 0::2].min() > -100 and X[:, 0::2].max() < 740
    assert X[:, 1::2].min() > -100 and X[:, 1::2].max() < 580


def test_points_per_motion_sequence():
    _, y = make_motions(3, [10, 20, 30], 5, shuffle=False, random_state=0)
    assert_array_equal(y, np.repeat([0, 1, 2], [10, 20, 30]))


@pytest.mark.parametrize(
    ("motion_type", "rank"), [("full", 4), ("planar", 3), ("linear", 2)]
)
@pytest.mark.parametrize("n_frames", [3, 8])
def test_subspace_dimensions(motion_type, rank, n_frames):
    X, y = make_motions(
        3, 90, n_frames, noise=0.0, motion_types=motion_type, random_state=1
    )
    for k in range(3):
        assert numerical_rank(X[y == k]) == rank


def test_mixed_motion_types():
    X, y = make_motions(
        3,
        90,
        10,
        noise=0.0,
        motion_types=["linear", "full", "planar"],
        random_state=2,
    )
    assert [numerical_rank(X[y == k]) for k in range(3)] == [2, 4, 3]
    assert numerical_rank(X) == 9  # independent: 2 + 4 + 3 <= 2F = 20


@pytest.mark.parametrize(
    ("dependent", "union_rank"), [(None, 8), ("rotation", 5), ("translation", 7)]
)
def test_dependent_motions(dependent, union_rank):
    X, y = make_motions(2, 100, 10, noise=0.0, dependent=dependent, random_state=3)
    ranks = [numerical_rank(X[y == k]) for k in range(2)]
    assert ranks == [4, 4]
    assert numerical_rank(X) == union_rank
    # Partially, not fully, dependent (paper eq. (7)).
    assert numerical_rank(X) > max(ranks)


@settings(max_examples=60, deadline=None, derandomize=True)
@given(
    seed=st.integers(min_value=0, max_value=2**32 - 1),
    n_motions=st.integers(min_value=2, max_value=4),
    n_frames=st.integers(min_value=3, max_value=15),
    motion_type=st.sampled_from(["full", "planar", "linear"]),
    dependent=st.sampled_from([None, "translation"]),
)
def test_motions_are_min_angle_apart(seed, n_motions, n_frames, motion_type, dependent):
    # Measured on the noise-free trajectories, not on the generator's model.
    X, y = make_motions(
        n_motions,
        20 * n_motions,
        n_frames,
        noise=0.0,
        motion_types=motion_type,
        dependent=dependent,
        random_state=seed,
    )
    angles = largest_angles(X, y, [_MOTION_DIMS[motion_type]] * n_motions)
    assert min(angles.values()) >= 10.0 - 1e-6


def _scaling_benchmark_draw(**kwargs):
    """The 10,000-point draw of benchmarks/bench_scaling.py, noise free."""
    _, y, X = make_motions(
        3,
        n_points=10000,
        n_frames=10,
        noise=0.0,
        missing=0.1,
        return_complete=True,
        random_state=0,
        **kwargs,
    )
    return X, y


def test_scaling_benchmark_draw_is_separable():
    # The draw of benchmarks/bench_scaling.py once held two motions 7 degrees
    # apart (principal angles 7, 3.2, 0.2, 0.04), which no method separates.
    X, y = _scaling_benchmark_draw()
    angles = largest_angles(X, y, [4, 4, 4])
    assert min(angles.values()) >= 10.0
    # The same motions as with the benchmark's noise: only later draws differ.
    _, y_noisy = make_motions(
        3, n_points=10000, n_frames=10, noise=1.0, missing=0.1, random_state=0
    )
    assert_array_equal(y_noisy, y)


def test_min_angle_zero_keeps_close_motions():
    # Without the check, the benchmark draw keeps its two close motions.
    X, y = _scaling_benchmark_draw(min_angle=0.0)
    assert min(largest_angles(X, y, [4, 4, 4]).values()) < 10.0


def test_min_angle_impossible():
    message = (
        "Could not draw motion 1 with a largest principal angle of at least "
        "min_angle=90.0 degrees to every earlier motion in 1000 attempts; lower "
        "min_angle or use more frames."
    )
    with pytest.raises(ValueError, match=re.escape(message)):
        make_motions(2, 20, 5, min_angle=90.0, random_state=0)


def test_noise_level():
    kwargs = dict(n_motions=2, n_points=200, n_frames=6, random_state=4)
    X0, _ = make_motions(noise=0.0, **kwargs)
    X1, _ = make_motions(noise=2.0, **kwargs)
    assert_allclose(np.std(X1 - X0), 2.0, rtol=0.05)


@pytest.mark.parametrize("pattern", ["random", "occlusion"])
@pytest.mark.parametrize(
    ("n_points", "n_frames", "missing"),
    [(100, 10, 0.3), (60, 3, 0.0), (200, 30, 0.8), (12, 10, 0.5), (50, 4, 0.25)],
)
def test_missing_patterns(pattern, n_points, n_frames, missing):
    X, _, X_complete = make_motions(
        2,
        n_points,
        n_frames,
        missing=missing,
        missing_pattern=pattern,
        n_outliers=3,
        return_complete=True,
        random_state=5,
    )
    n_samples = n_points + 3
    nan = np.isnan(X)
    # x and y of a frame go missing together.
    assert_array_equal(nan[:, 0::2], nan[:, 1::2])
    assert np.all(np.isfinite(X_complete))
    assert_array_equal(X[~nan], X_complete[~nan])
    expected = round(missing * n_samples * n_frames) / (n_samples * n_frames)
    assert nan.mean() == pytest.approx(expected, abs=1e-12)
    observed = observed_frames(X)
    assert observed.sum(axis=1).min() >= MIN_FRAMES_PER_TRACK
    assert observed.sum(axis=0).min() >= min(MIN_POINTS_PER_FRAME, n_samples)
    if pattern == "occlusion":
        # One contiguous visibility window per track.
        starts = np.diff(np.pad(observed.astype(int), ((0, 0), (1, 1))), axis=1) == 1
        assert_array_equal(starts.sum(axis=1), 1)


def test_random_pattern_is_not_banded():
    X, _ = make_motions(2, 300, 20, missing=0.5, random_state=6)
    observed = observed_frames(X)
    starts = np.diff(np.pad(observed.astype(int), ((0, 0), (1, 1))), axis=1) == 1
    assert starts.sum(axis=1).mean() > 2


@pytest.mark.parametrize("pattern", ["random", "occlusion"])
def test_too_much_missing_data(pattern):
    with pytest.raises(ValueError, match="fewer than the 90 needed"):
        make_motions(2, 30, 3, missing=0.1, missing_pattern=pattern)


def test_outliers_are_off_subspace():
    X, y = make_motions(2, 100, 10, noise=0.0, n_outliers=5, random_state=7)
    assert numerical_rank(X[y >= 0]) == 8
    assert numerical_rank(X) == 13


def test_determinism_and_shuffle():
    kwargs = dict(missing=0.2, n_outliers=2)
    X1, y1 = make_motions(random_state=8, **kwargs)
    X2, y2 = make_motions(random_state=np.random.RandomState(8), **kwargs)
    assert_array_equal(X1, X2)
    assert_array_equal(y1, y2)
    X3, _ = make_motions(random_state=9, **kwargs)
    assert not np.array_equal(np.isnan(X1), np.isnan(X3))
    _, y_sorted = make_motions(shuffle=False, random_state=8, **kwargs)
    assert_array_equal(y_sorted, np.sort(y_sorted)[np.r_[2:102, 0:2]])
    assert not np.array_equal(y1, y_sorted)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        (dict(n_motions=0), "n_motions"),
        (dict(n_frames=2), "n_frames"),
        (dict(noise=-1.0), "noise"),
        (dict(missing=1.0), "missing"),
        (dict(missing_pattern="banded"), "missing_pattern"),
        (dict(dependent="scale"), "dependent"),
        (dict(n_outliers=-1), "n_outliers"),
        (dict(motion_types="cubic"), "motion_types"),
        (dict(motion_types=["full"]), "sequence of n_motions=2"),
        (dict(n_points=[10, 0]), "positive ints"),
        (dict(n_points=[10, 10, 10]), "positive ints"),
        (dict(n_motions=3, n_points=2), "smaller than n_motions=3"),
        (dict(random_state="seed"), "random_state"),
        (dict(min_angle=91.0), "min_angle"),
    ],
)
def test_invalid_arguments(kwargs, match):
    with pytest.raises(ValueError, match=match):
        make_motions(**kwargs)


def test_make_transparent():
    X, y = make_motions(2, 40, 5, missing=0.2, random_state=10)
    X2, y2 = make_transparent(X, y)
    assert X2.shape == (80, 10)
    assert_array_equal(X2[:40], X)
    assert_array_equal(X2[40:, 0::2], X[:, 1::2])
    assert_array_equal(X2[40:, 1::2], X[:, 0::2])
    assert_array_equal(y2, np.concatenate([y, y + 2]))


def test_make_transparent_static_scene_and_outliers():
    X, _ = make_motions(1, 30, 4, noise=0.0, random_state=11)
    X2, y2 = make_transparent(X)
    assert_array_equal(y2, np.repeat([0, 1], 30))
    # The swapped copy is a different 4-D subspace: together 8 dimensions.
    assert numerical_rank(X2) == 8
    _, y3 = make_transparent(np.zeros((3, 4)), [0, -1, 1])
    assert_array_equal(y3, [0, -1, 1, 2, -1, 3])


@pytest.mark.parametrize(
    ("X", "y", "match"),
    [
        (np.zeros((3, 5)), None, "even number of features"),
        (np.zeros((3, 4)), [0, 1], "inconsistent numbers of samples"),
        (np.zeros((3, 4)), [0.5, 1, 2], "integer labels"),
    ],
)
def test_make_transparent_errors(X, y, match):
    with pytest.raises(ValueError, match=match):
        make_transparent(X, y)


@pytest.mark.parametrize("pattern", ["random", "occlusion"])
@pytest.mark.parametrize("missing", [0.1, 0.3, 0.5])
def test_make_missing_on_given_trajectories(pattern, missing):
    X = np.arange(200 * 30, dtype=float).reshape(200, 30)
    X_missing = make_missing(X, missing, pattern=pattern, random_state=0)
    observed = ~np.isnan(X_missing[:, ::2])
    assert_array_equal(np.isnan(X_missing[:, ::2]), np.isnan(X_missing[:, 1::2]))
    assert abs(1 - observed.mean() - missing) < 1e-9
    assert observed.sum(axis=1).min() >= MIN_FRAMES_PER_TRACK
    assert observed.sum(axis=0).min() >= MIN_POINTS_PER_FRAME
    assert_array_equal(X_missing[observed.repeat(2, axis=1)], X[observed.repeat(2, 1)])
    if pattern == "occlusion":
        steps = np.diff(observed.astype(int), axis=1)
        assert ((steps == 1).sum(axis=1) <= 1).all()
        assert ((steps == -1).sum(axis=1) <= 1).all()


def test_make_missing_errors():
    with pytest.raises(ValueError, match="X has 5 columns; trajectories need an even"):
        make_missing(np.ones((10, 5)))
    with pytest.raises(ValueError, match=r"missing=0.9 leaves .* fewer than the"):
        make_missing(np.ones((10, 20)), 0.9)


def test_occlusion_windows_that_cannot_exist_are_named():
    """6 tracks on 4 frames with 3 of the 24 point-frames missing passes the
    count check (21 observed >= 5 per frame x 4 frames = 20), but no
    contiguous windows fit: each track keeps >= 3 of its 4 frames, so it
    misses at most one end frame (0 or 3), and each frame may miss at most
    one of its 6 points (5 must stay): 2 missing point-frames at most, not
    3."""
    X = np.arange(6 * 8, dtype=float).reshape(6, 8)
    message = (
        "Could not place occlusion windows with at least 5 points in each of "
        "the 4 frames; lower `missing` or add points."
    )
    with pytest.raises(ValueError, match=f"^{re.escape(message)}$"):
        make_missing(X, 3 / 24, pattern="occlusion", random_state=0)
    # the random pattern needs no windows: 3 missing point-frames fit
    X_missing = make_missing(X, 3 / 24, pattern="random", random_state=0)
    assert np.isnan(X_missing[:, ::2]).sum() == 3


@pytest.mark.parametrize("missing", [0.02, 0.1, 0.25, 0.5, 0.75])
def test_occlusion_window_lengths_spread_about_their_mean(missing):
    """Occlusion: each track is seen on one window of frames, whose length is
    drawn uniformly about the mean ``m = (1 - missing) F`` as widely as the
    guarantees allow, on ``[m - s, m + s]`` with ``s = min(m - 3, F - m)``,
    and rounded (then a few tracks are nudged by one frame to make the total
    exact). The lengths' histogram is compared with that rounded uniform law
    (total variation; ~0.02 from sampling alone with 5000 tracks)."""
    n_tracks, n_frames = 5000, 20
    X = np.zeros((n_tracks, 2 * n_frames))
    observed = ~np.isnan(make_missing(X, missing, random_state=0)[:, ::2])
    lengths = observed.sum(axis=1)
    assert lengths.sum() == round((1 - missing) * n_tracks * n_frames)
    steps = np.diff(observed.astype(int), axis=1)
    assert ((steps == 1).sum(axis=1) <= 1).all()
    assert ((steps == -1).sum(axis=1) <= 1).all()
    mean = (1 - missing) * n_frames
    spread = min(mean - MIN_FRAMES_PER_TRACK, n_frames - mean)
    low, high = mean - spread, mean + spread
    k = np.arange(n_frames + 1)
    law = np.clip(np.minimum(k + 0.5, high) - np.maximum(k - 0.5, low), 0, None)
    law /= law.sum()
    histogram = np.bincount(lengths, minlength=n_frames + 1) / n_tracks
    assert 0.5 * np.abs(histogram - law).sum() < 0.06


@pytest.mark.parametrize("n_tracks", [30, 50])
def test_occlusion_with_little_missing_keeps_its_guarantees(n_tracks):
    """Nearly complete tracks (1 or 2 % missing, so most windows span all 20
    frames): over many draws the missing count is exact, every track keeps
    one window of at least 3 frames and every frame at least 5 points."""
    X = np.zeros((n_tracks, 40))
    for missing in (0.01, 0.02):
        for seed in range(20):
            observed = ~np.isnan(make_missing(X, missing, random_state=seed)[:, ::2])
            assert (~observed).sum() == round(missing * n_tracks * 20)
            assert observed.sum(axis=1).min() >= MIN_FRAMES_PER_TRACK
            assert observed.sum(axis=0).min() >= MIN_POINTS_PER_FRAME
            steps = np.diff(observed.astype(int), axis=1)
            assert ((steps == 1).sum(axis=1) <= 1).all()
            assert ((steps == -1).sum(axis=1) <= 1).all()


@pytest.mark.parametrize(
    ("n_tracks", "n_frames", "n_missing"),
    [
        (6, 10, 1),
        (6, 10, 2),
        (15, 12, 120),
        (15, 20, 190),
        (15, 20, 195),
        (20, 20, 294),
    ],
)
def test_occlusion_windows_are_placed_at_the_edges_of_the_guarantees(
    n_tracks, n_frames, n_missing
):
    """Feasible requests at the edge: 6 tracks with 1 or 2 missing
    point-frames (each frame keeps 5 of its 6 points: the missing ones sit at
    the two ends), 60 point-frames left where 60 are needed (5 per frame on
    12 frames) and 105-110 where 100 are; each draw keeps every guarantee."""
    X = np.zeros((n_tracks, 2 * n_frames))
    for seed in range(3):
        missing = n_missing / (n_tracks * n_frames)
        observed = ~np.isnan(make_missing(X, missing, random_state=seed)[:, ::2])
        assert (~observed).sum() == n_missing
        assert observed.sum(axis=1).min() >= MIN_FRAMES_PER_TRACK
        assert observed.sum(axis=0).min() >= MIN_POINTS_PER_FRAME
        steps = np.diff(observed.astype(int), axis=1)
        assert ((steps == 1).sum(axis=1) <= 1).all()
        assert ((steps == -1).sum(axis=1) <= 1).all()


@pytest.mark.parametrize("missing", [0.35, 0.5])
def test_random_pattern_tops_up_thin_frames(missing):
    """10 tracks on 20 frames: 3 protected frames per track leave frames with
    1.5 points on average, so most frames must be topped up to 5 before the
    rest is drawn; every draw keeps both guarantees (0.5 is the limit: 100
    point-frames, 5 per frame)."""
    X = np.zeros((10, 40))
    for seed in range(5):
        observed = ~np.isnan(
            make_missing(X, missing, pattern="random", random_state=seed)[:, ::2]
        )
        assert (~observed).sum() == round(missing * 200)
        assert observed.sum(axis=0).min() >= MIN_POINTS_PER_FRAME
        assert observed.sum(axis=1).min() >= MIN_FRAMES_PER_TRACK


def test_random_pattern_refusal_names_the_numbers():
    """10 tracks on 6 frames with half missing: 30 observed point-frames, as
    many as 3 per track and 5 per frame need. The random pattern protects 3
    random frames per track, then tops up thin frames, which needs more than
    30 here (a limitation of the greedy draw: an exact arrangement exists);
    it refuses with the numbers."""
    message = (
        r"^Too much missing data: 30 observed point-frames requested but the "
        r"guarantees \(3 frames per track, 5 points per frame\) need (\d+)\.$"
    )
    with pytest.raises(ValueError, match=message) as excinfo:
        make_missing(np.zeros((10, 12)), 0.5, pattern="random", random_state=0)
    assert int(re.match(message, str(excinfo.value)).group(1)) > 30


@pytest.mark.parametrize(
    ("n_tracks", "missing", "n_visible", "n_cells", "required", "per_frame"),
    [(10, 0.9, 10, 100, 50, 5), (4, 0.1, 36, 40, 40, 4), (30, 0.8, 60, 300, 90, 5)],
)
def test_too_much_missing_message_gives_the_counts(
    n_tracks, missing, n_visible, n_cells, required, per_frame
):
    """10 frames: ``n_visible`` of ``n_tracks * 10`` point-frames left, and
    ``max(3 * n_tracks, per_frame * 10)`` needed, ``per_frame`` being 5, or
    every track when there are fewer."""
    message = (
        f"missing={missing} leaves {n_visible} of {n_cells} point-frames observed, "
        f"fewer than the {required} needed to keep 3 frames per track and "
        f"{per_frame} points per frame."
    )
    with pytest.raises(ValueError, match=f"^{re.escape(message)}$"):
        make_missing(np.ones((n_tracks, 20)), missing)


def test_translations_move_one_to_five_pixels_a_frame():
    """Documented: translations move 1-5 pixels per frame (uniform speed, mean
    3) with small random accelerations (0.3 px per frame squared per axis),
    in a uniformly random direction, from a start in the central 60 % of the
    640 x 480 image; depth never moves. 2000 draws; bounds at ~4 standard
    errors."""
    rng = np.random.RandomState(0)
    T = np.array([_translations(6, rng) for _ in range(2000)])
    assert_array_equal(T[:, :, 2], 0.0)
    step = T[:, 1, :2] - T[:, 0, :2]
    assert abs(np.linalg.norm(step, axis=1).mean() - 3.0) < 0.15
    assert abs(np.diff(T[:, :, :2], 2, axis=1).std() - 0.3) < 0.015
    heading = np.arctan2(step[:, 1], step[:, 0]) % (2 * np.pi)
    quadrants = np.histogram(heading, 4, (0, 2 * np.pi))[0]
    assert np.all(np.abs(quadrants - 500) < 80)
    for coordinate, size in ((0, 640.0), (1, 480.0)):
        start = T[:, 0, coordinate]
        assert np.all(np.abs(start) <= 0.3 * size)
        # uniform on [-0.3, 0.3] x size: standard deviation 0.6 size / sqrt(12)
        assert abs(start.std() / (0.6 * size / np.sqrt(12)) - 1) < 0.1


def test_structure_sizes():
    """Objects are 40-80 pixels in radius: a full object's points fill a box
    with half-sides between 0.5 and 1 radius, centred on its origin, of
    unequal sides; planar and linear objects spread +-radius along their
    basis."""
    rng = np.random.RandomState(0)
    extents, ratios = [], []
    for _ in range(200):
        points, basis = _structure("full", 500, rng)
        assert_array_equal(basis, np.eye(3))
        extent = np.abs(points).max(axis=0)
        extents.append(extent)
        ratios.append(extent.min() / extent.max())
        assert np.all(np.abs(points.mean(axis=0)) < 0.15 * extent)
    extents = np.array(extents)
    assert extents.min() > 18 and extents.max() <= 80
    assert min(ratios) < 0.6
    for kind, dim in (("planar", 2), ("linear", 1)):
        for _ in range(50):
            points, basis = _structure(kind, 500, rng)
            assert basis.shape == (3, dim)
            coefs = points @ basis
            assert_allclose(coefs @ basis.T, points, atol=1e-9)
            assert 36 < coefs.max() <= 80 and -80 <= coefs.min() < -36


def test_one_point_per_motion_is_enough():
    """``make_blobs``' rule: each motion needs at least one point, and one is
    enough, whether ``n_points`` is a total or a list of sizes."""
    _X, y = make_motions(2, 2, 5, random_state=0)
    assert_array_equal(np.bincount(y), [1, 1])
    _X, y = make_motions(2, [1, 5], 5, random_state=0)
    assert_array_equal(np.bincount(y), [1, 5])


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (
            dict(n_points=1),
            "n_points=1 is smaller than n_motions=2; each motion needs at least "
            "one point.",
        ),
        (
            dict(n_points=[3, 0]),
            "n_points must be an int or a sequence of n_motions=2 positive ints, "
            "got [3, 0].",
        ),
        (
            dict(motion_types=["full"]),
            "motion_types must be None, one of 'full', 'planar', 'linear', or a "
            "sequence of n_motions=2 of them, got ['full'].",
        ),
    ],
)
def test_make_motions_messages(kwargs, message):
    with pytest.raises(ValueError, match=f"^{re.escape(message)}$"):
        make_motions(2, **kwargs)
