"""Missing entries the way feature trackers lose them."""

# SPDX-License-Identifier: BSD-3-Clause

from numbers import Real

import numpy as np
from sklearn.utils import check_array, check_random_state
from sklearn.utils._param_validation import Interval, StrOptions, validate_params

#: Every track of :func:`make_missing` keeps at least this many observed
#: frames, i.e. 6 observed entries, enough to determine its coordinates in a
#: rank-5 factorisation (PowerFactorization needs 5 observed entries per row).
MIN_FRAMES_PER_TRACK = 3

#: Every frame of :func:`make_missing` keeps at least this many observed
#: points (or all of them when there are fewer), so that each of its two rows
#: of the measurement matrix can be solved for in a rank-5 factorisation.
MIN_POINTS_PER_FRAME = 5


def _random_observed(n_samples, n_frames, n_visible, min_points, rng):
    """Observed (point, frame) cells: uniformly random beyond the guarantees."""
    # MIN_FRAMES_PER_TRACK protected frames per track, drawn at random.
    order = np.argsort(rng.random_sample((n_samples, n_frames)), axis=1)
    protected = np.zeros((n_samples, n_frames), dtype=bool)
    np.put_along_axis(protected, order[:, :MIN_FRAMES_PER_TRACK], True, axis=1)
    for f in np.flatnonzero(protected.sum(axis=0) < min_points):
        need = min_points - protected[:, f].sum()
        free = np.flatnonzero(~protected[:, f])
        protected[rng.choice(free, size=need, replace=False), f] = True
    n_extra = n_visible - protected.sum()
    if n_extra < 0:
        raise ValueError(
            f"Too much missing data: {n_visible} observed point-frames requested "
            f"but the guarantees ({MIN_FRAMES_PER_TRACK} frames per track, "
            f"{min_points} points per frame) need {protected.sum()}."
        )
    free = np.flatnonzero(~protected.ravel())
    observed = protected.ravel().copy()
    observed[rng.choice(free, size=n_extra, replace=False)] = True
    return observed.reshape(n_samples, n_frames)


def _occlusion_observed(n_samples, n_frames, n_visible, min_points, rng):
    """Each track visible on one contiguous window of frames."""
    mean = n_visible / n_samples
    spread = min(mean - MIN_FRAMES_PER_TRACK, n_frames - mean)
    lengths = np.rint(rng.uniform(mean - spread, mean + spread, size=n_samples))
    lengths = np.clip(lengths, MIN_FRAMES_PER_TRACK, n_frames).astype(int)
    diff = n_visible - lengths.sum()
    while diff != 0:
        room = lengths < n_frames if diff > 0 else lengths > MIN_FRAMES_PER_TRACK
        candidates = np.flatnonzero(room)
        n_change = min(abs(diff), candidates.size)
        chosen = rng.choice(candidates, size=n_change, replace=False)
        lengths[chosen] += np.sign(diff)
        diff = n_visible - lengths.sum()
    starts = rng.randint(0, n_frames - lengths + 1)
    frames = np.arange(n_frames)

    def windows():
        return (frames >= starts[:, None]) & (frames < (starts + lengths)[:, None])

    observed = windows()
    for _ in range(50 * n_frames):
        counts = observed.sum(axis=0)
        deficient = np.flatnonzero(counts < min_points)
        if deficient.size == 0:
            return observed
        f = rng.choice(deficient)
        # Prefer moving a track whose window only covers well-covered frames.
        safe = np.all(np.where(observed, counts > min_points, True), axis=1)
        candidates = np.flatnonzero(~observed[:, f] & safe)
        if candidates.size == 0:
            candidates = np.flatnonzero(~observed[:, f])
        p = rng.choice(candidates)
        low = max(0, f - lengths[p] + 1)
        high = min(f, n_frames - lengths[p])
        starts[p] = rng.randint(low, high + 1)
        observed = windows()
    raise ValueError(
        "Could not place occlusion windows with at least "
        f"{min_points} points in each of the {n_frames} frames; lower "
        "`missing` or add points."
    )


def _apply_missing(X, missing, pattern, rng):
    """Copy of the complete ``X`` with a fraction ``missing`` of point-frames NaN."""
    X = X.copy()
    n_samples, n_frames = X.shape[0], X.shape[1] // 2
    n_missing = round(missing * n_samples * n_frames)
    if not n_missing:
        return X
    n_visible = n_samples * n_frames - n_missing
    min_points = min(MIN_POINTS_PER_FRAME, n_samples)
    required = max(MIN_FRAMES_PER_TRACK * n_samples, min_points * n_frames)
    if n_visible < required:
        raise ValueError(
            f"missing={missing} leaves {n_visible} of {n_samples * n_frames} "
            f"point-frames observed, fewer than the {required} needed to keep "
            f"{MIN_FRAMES_PER_TRACK} frames per track and {min_points} points "
            "per frame."
        )
    make_observed = _random_observed if pattern == "random" else _occlusion_observed
    observed = make_observed(n_samples, n_frames, n_visible, min_points, rng)
    X[~np.repeat(observed, 2, axis=1)] = np.nan
    return X


@validate_params(
    {
        "X": ["array-like"],
        "missing": [Interval(Real, 0, 1, closed="left")],
        "pattern": [StrOptions({"random", "occlusion"})],
        "random_state": ["random_state"],
    },
    prefer_skip_nested_validation=True,
)
def make_missing(X, missing=0.3, *, pattern="occlusion", random_state=None):
    """Remove a fraction of the point-frames of complete trajectories.

    Parameters
    ----------
    X : array-like of shape (n_samples, 2 * n_frames)
        Complete trajectories, one per row, ``[x_1, y_1, ..., x_F, y_F]``.

    missing : float in [0, 1), default=0.3
        Fraction of point-frames removed (rounded to a whole number). Both
        coordinates of a point in a frame go missing together. Every track
        keeps at least ``MIN_FRAMES_PER_TRACK = 3`` observed frames and every
        frame at least ``MIN_POINTS_PER_FRAME = 5`` observed points (all of
        them if there are fewer); a ``ValueError`` says so when ``missing`` is
        too large for these guarantees.

    pattern : {"occlusion", "random"}, default="occlusion"
        ``"occlusion"``: each track is visible on one contiguous window of
        frames, the way feature trackers lose and pick up points.
        ``"random"``: missing point-frames drawn uniformly at random beyond
        the guarantees.

    random_state : int, RandomState instance or None, default=None
        Seed of the pattern.

    Returns
    -------
    X_missing : ndarray of shape (n_samples, 2 * n_frames)
        A copy of ``X`` with NaN at the removed entries.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca.datasets import make_missing
    >>> X = np.ones((50, 20))
    >>> X_missing = make_missing(X, 0.3, random_state=0)
    >>> float(np.isnan(X_missing).mean())
    0.3
    """
    X = check_array(X, dtype=np.float64)
    if X.shape[1] % 2:
        raise ValueError(
            f"X has {X.shape[1]} columns; trajectories need an even number "
            "(x and y per frame)."
        )
    return _apply_missing(X, missing, pattern, check_random_state(random_state))
