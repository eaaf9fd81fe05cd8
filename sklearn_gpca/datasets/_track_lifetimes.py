"""Births and deaths of tracks, the way a feature tracker makes and loses them.

A tracker detects features in the first frame, then re-detects features
wherever tracks were lost, so that about as many tracks are alive in every
frame: a share of the tracks starts in frame 0 (:func:`first_frame_share`),
the others uniformly in frames 1 .. F-1. A track then lives a geometric
number of frames (mean ``mean_lifetime``), unless it leaves the image, is
occluded or the sequence ends first.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

#: Largest mean lifetime (frames) the calibration of ``missing`` tries; beyond
#: it every track ends by leaving the view or with the sequence.
_MAX_MEAN_LIFETIME = 1e7


def first_frame_share(n_frames, missing=None, mean_lifetime=None):
    """Share of the tracks a stationary tracker starts in frame 0.

    A tracker that keeps ``N`` tracks alive in every frame, replacing each lost
    track by a new one, observes ``N F`` of its ``P F`` entries, so the share
    of its tracks born in frame 0 is ``N / P = 1 - missing``, whatever the
    lifetimes. Without a ``missing`` target, with lifetimes of mean ``m`` and no
    other losses, ``P = N + (F - 1) N / m`` gives ``m / (m + F - 1)``.
    """
    if missing is not None:
        return 1.0 - missing
    if not np.isfinite(mean_lifetime):
        return 1.0
    return mean_lifetime / (mean_lifetime + n_frames - 1)


def birth_probabilities(n_frames, first_share, last=None):
    """Probability of a track to be born in each frame (0 .. ``last``): frame 0
    gets ``first_share``, the later frames the rest in equal parts."""
    probs = np.full(n_frames, (1 - first_share) / max(n_frames - 1, 1))
    probs[0] = first_share if n_frames > 1 else 1.0
    if last is not None:
        probs[last + 1 :] = 0.0
    return probs / probs.sum()


def geometric_lifetimes(uniform, mean_lifetime):
    """Geometric lifetimes on {1, 2, ...} with the given mean, by inversion.

    ``P(L >= k) = (1 - 1/mean)^(k - 1)``; ``uniform`` holds draws in (0, 1].
    """
    if mean_lifetime <= 1:
        return np.ones_like(uniform, dtype=np.int64)
    if not np.isfinite(mean_lifetime):
        return np.full(uniform.shape, np.iinfo(np.int64).max // 4, dtype=np.int64)
    survival = np.log1p(-1.0 / mean_lifetime)
    lifetimes = 1 + np.floor(np.log(uniform) / survival)
    return np.minimum(lifetimes, np.iinfo(np.int64).max // 4).astype(np.int64)


def track_lengths(uniform, mean_lifetime, min_length, max_length):
    """Observed length of every track: its lifetime, clipped to what it can be."""
    lifetimes = geometric_lifetimes(uniform, mean_lifetime)
    return np.minimum(np.maximum(lifetimes, min_length), max_length)


def calibrate_lifetime(uniform, min_length, max_length, n_frames, missing):
    """Mean lifetime at which the tracks miss a fraction ``missing`` of entries.

    Observed lengths grow with the mean lifetime, so bisection on its logarithm
    finds it. Raises ``ValueError`` when the exits from the view alone already
    remove more than ``missing`` (plus half a percent).
    """
    total = uniform.size * n_frames

    def missing_at(mean):
        lengths = track_lengths(uniform, mean, min_length, max_length)
        return 1.0 - lengths.sum() / total

    floor = 1.0 - max_length.sum() / total
    if floor > missing + 0.005:
        raise ValueError(
            f"missing={missing} cannot be reached: tracks leaving the view or "
            f"being occluded already miss {floor:.3f} of the entries with endless "
            "lifetimes. Ask for more missing data, fewer frames, a higher "
            "frame_rate or a slower camera (forward_speed)."
        )
    ceiling = missing_at(1.0)
    if ceiling < missing - 0.005:
        raise ValueError(
            f"missing={missing} cannot be reached: tracks living a single frame "
            f"(their shortest) miss only {ceiling:.3f} of the entries."
        )
    low, high = 0.0, np.log(_MAX_MEAN_LIFETIME)
    for _ in range(60):
        mid = (low + high) / 2
        if missing_at(np.exp(mid)) > missing:
            low = mid
        else:
            high = mid
    # The side of the bisection interval whose missing fraction is closer.
    candidates = (np.exp(low), np.exp(high))
    return float(min(candidates, key=lambda m: abs(missing_at(m) - missing)))


def first_exit(visible, births):
    """First frame at or after each birth where the track is not visible (or F)."""
    n_frames = visible.shape[1]
    after = np.arange(n_frames) >= births[:, None]
    lost = after & ~visible
    return np.where(lost.any(axis=1), lost.argmax(axis=1), n_frames)
