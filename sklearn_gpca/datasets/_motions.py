"""Synthetic multibody motion trajectories seen by an affine camera.

The generators follow the model of Vidal & Hartley (CVPR 2004), section 2:
the image of point ``p`` in frame ``f`` is :math:`x_{fp} = A_f X_p` with an affine
camera matrix ``A_f`` (2 x 4) and homogeneous 3-D point ``X_p``, so the
trajectories of one rigid object span a subspace of dimension 2, 3 or 4 of
:math:`R^{2F}`.
"""

# SPDX-License-Identifier: BSD-3-Clause

from numbers import Integral, Real

import numpy as np
from scipy.spatial.transform import Rotation
from sklearn.utils import check_array, check_random_state, column_or_1d
from sklearn.utils._param_validation import Interval, StrOptions, validate_params
from sklearn.utils.validation import check_consistent_length

from sklearn_gpca.datasets._missing import (
    _apply_missing,
)

_IMAGE_SIZE = (640.0, 480.0)
_MOTION_DIMS = {"full": 4, "planar": 3, "linear": 2}
# Draws of one object's motion before make_motions gives up on min_angle.
_MAX_ATTEMPTS = 1000


def _split_points(n_points, n_motions):
    """Number of points of each motion, as make_blobs splits ``n_samples``."""
    if isinstance(n_points, Integral):
        if n_points < n_motions:
            raise ValueError(
                f"n_points={n_points} is smaller than n_motions={n_motions}; "
                "each motion needs at least one point."
            )
        sizes = np.full(n_motions, n_points // n_motions)
        sizes[: n_points % n_motions] += 1
        return sizes
    sizes = np.asarray(n_points)
    if (
        sizes.ndim != 1
        or sizes.shape[0] != n_motions
        or not np.issubdtype(sizes.dtype, np.integer)
        or np.any(sizes < 1)
    ):
        raise ValueError(
            "n_points must be an int or a sequence of n_motions="
            f"{n_motions} positive ints, got {n_points!r}."
        )
    return sizes.astype(int)


def _motion_types(motion_types, n_motions):
    if motion_types is None:
        return ["full"] * n_motions
    if isinstance(motion_types, str):
        return [motion_types] * n_motions
    types = list(motion_types)
    if len(types) != n_motions or any(t not in _MOTION_DIMS for t in types):
        raise ValueError(
            "motion_types must be None, one of 'full', 'planar', 'linear', or a "
            f"sequence of n_motions={n_motions} of them, got {motion_types!r}."
        )
    return types


def _structure(kind, n_points, rng):
    """3-D points in the object frame and a basis (3, d) of their span.

    ``[X; 1]`` has rank 4, 3 or 2.
    """
    radius = rng.uniform(40.0, 80.0)
    if kind == "full":
        axes = radius * rng.uniform(0.5, 1.0, size=3)
        return rng.uniform(-1.0, 1.0, size=(n_points, 3)) * axes, np.eye(3)
    dim = 2 if kind == "planar" else 1
    basis, _ = np.linalg.qr(rng.normal(size=(3, dim)))
    coefs = rng.uniform(-radius, radius, size=(n_points, dim))
    return coefs @ basis.T, basis


def _rotations(n_frames, rng):
    """Smooth rotation sequence: random start, jittered angular velocity."""
    axis = rng.normal(size=3)
    omega = axis / np.linalg.norm(axis) * rng.uniform(0.03, 0.1)
    steps = omega + rng.normal(scale=0.005, size=(n_frames - 1, 3))
    rotations = [Rotation.random(random_state=rng)]
    for step in steps:
        rotations.append(Rotation.from_rotvec(step) * rotations[-1])
    return np.stack([r.as_matrix() for r in rotations])


def _translations(n_frames, rng):
    """Smooth in-image translation: random start and velocity in pixels."""
    width, height = _IMAGE_SIZE
    start = [rng.uniform(-0.3, 0.3) * width, rng.uniform(-0.3, 0.3) * height, 0.0]
    angle = rng.uniform(0, 2 * np.pi)
    velocity = rng.uniform(1.0, 5.0) * np.array([np.cos(angle), np.sin(angle), 0.0])
    accel = rng.normal(scale=0.3, size=(n_frames - 1, 3))
    accel[:, 2] = 0.0
    velocities = velocity + np.cumsum(accel, axis=0)
    return np.vstack([start, start + np.cumsum(velocities, axis=0)])


def _motion_subspace(rotations, translations, zoom, centre, span):
    """Orthonormal basis of the subspace ``M [X; 1]`` spans in R^{2F}.

    ``span`` (4, d) spans the homogeneous structure ``[X_p; 1]``.
    """
    n_frames = zoom.shape[0]
    motion = np.empty((n_frames, 2, 4))
    motion[:, :, :3] = zoom[:, None, None] * rotations[:, :2, :]
    motion[:, :, 3] = zoom[:, None] * translations[:, :2] + centre
    basis, _ = np.linalg.qr(motion.reshape(2 * n_frames, 4) @ span)
    return basis


def _largest_angle(U, V):
    """Largest principal angle, in degrees, between orthonormal bases U and V."""
    cosines = np.linalg.svd(U.T @ V, compute_uv=False)
    return float(np.degrees(np.arccos(min(cosines.min(), 1.0))))


@validate_params(
    {
        "n_motions": [Interval(Integral, 1, None, closed="left")],
        "n_points": [Interval(Integral, 1, None, closed="left"), "array-like"],
        "n_frames": [Interval(Integral, 3, None, closed="left")],
        "noise": [Interval(Real, 0, None, closed="left")],
        "motion_types": [StrOptions(set(_MOTION_DIMS)), "array-like", None],
        "dependent": [StrOptions({"rotation", "translation"}), None],
        "missing": [Interval(Real, 0, 1, closed="left")],
        "missing_pattern": [StrOptions({"random", "occlusion"})],
        "n_outliers": [Interval(Integral, 0, None, closed="left")],
        "shuffle": ["boolean"],
        "return_complete": ["boolean"],
        "min_angle": [Interval(Real, 0, 90, closed="both")],
        "random_state": ["random_state"],
    },
    prefer_skip_nested_validation=True,
)
def make_motions(
    n_motions=2,
    n_points=100,
    n_frames=10,
    *,
    noise=1.0,
    motion_types=None,
    dependent=None,
    missing=0.0,
    missing_pattern="random",
    n_outliers=0,
    shuffle=True,
    return_complete=False,
    min_angle=10.0,
    random_state=None,
):
    """Generate point trajectories of rigidly moving objects.

    Each motion is a random 3-D object moving rigidly (smooth rotation and
    translation) in front of an affine, weak-perspective camera looking at a
    640 x 480 image. Trajectories are returned in the library's layout: one
    row per point, ``[x_1, y_1, ..., x_F, y_F]`` in pixels, missing entries as
    NaN. Like :func:`sklearn.datasets.make_blobs`, with motions in place of
    blobs.

    Parameters
    ----------
    n_motions : int, default=2
        Number of independently moving objects (groups).

    n_points : int or array-like of int, default=100
        Total number of (inlier) points, split as evenly as possible among
        the motions; or the number of points of each motion.

    n_frames : int, default=10
        Number of frames ``F >= 3`` (three views are the minimum of the
        paper's method). The data has ``2 * n_frames`` features.

    noise : float, default=1.0
        Standard deviation, in pixels, of the Gaussian noise added to every
        image coordinate.

    motion_types : {"full", "planar", "linear"} or list of them, default=None
        Structure of each object, which sets the dimension of its motion
        subspace of :math:`R^{2F}` (for ``F >= 2`` and generic motion):

        - ``"full"``: general 3-D points, ``rank [X_p; 1] = 4``, subspace of
          dimension 4;
        - ``"planar"``: points on a plane, ``rank [X_p; 1] = 3``, dimension 3;
        - ``"linear"``: points on a line, ``rank [X_p; 1] = 2``, dimension 2.

        None means ``"full"`` for every motion; one string applies to all.

    dependent : {"rotation", "translation"}, default=None
        Make the motion subspaces partially dependent (paper, section 2).
        ``"rotation"``: all objects share one rotation sequence (different
        translations), so the union of the subspaces has dimension at most
        ``3 + n_motions``. ``"translation"``: all objects share one
        translation, like parts rotating about a common moving joint, so the
        union has dimension at most ``3 * n_motions + 1``. None: independent
        motions, every object with its own rotation and translation.

    missing : float in [0, 1), default=0.0
        Fraction of point-frame entries that are missing (rounded to a whole
        number of entries). Both coordinates of a point in a frame go missing
        together. Every track keeps at least ``MIN_FRAMES_PER_TRACK = 3``
        observed frames and every frame at least ``MIN_POINTS_PER_FRAME = 5``
        observed points (all points if fewer); a ``ValueError`` says when
        ``missing`` is too large for these guarantees.

    missing_pattern : {"random", "occlusion"}, default="random"
        ``"random"``: missing point-frames drawn uniformly at random beyond
        the guarantees. ``"occlusion"``: each track is visible on one
        contiguous window of frames, as when a tracker picks a point up late
        or loses it.

    n_outliers : int, default=0
        Number of outlying trajectories appended: points drawn uniformly in
        the image independently in every frame, labelled ``-1``.

    shuffle : bool, default=True
        Shuffle the rows. If False, rows are ordered by motion, outliers
        last.

    return_complete : bool, default=False
        If True, also return the data before entries were removed.

    min_angle : float in [0, 90], default=10.0
        Smallest allowed largest principal angle, in degrees, between the
        subspaces of any two motions (see Notes). An object's motion is
        redrawn until it is at least this far from every earlier one; 0
        disables the check, and so does ``dependent="rotation"``.

    random_state : int, RandomState instance or None, default=None
        Seed of all the randomness.

    Returns
    -------
    X : ndarray of shape (n_points + n_outliers, 2 * n_frames)
        Trajectories in pixels, NaN where missing.

    y : ndarray of shape (n_points + n_outliers,)
        Motion label of each row, ``0 .. n_motions - 1``, ``-1`` for
        outliers.

    X_complete : ndarray of shape (n_points + n_outliers, 2 * n_frames)
        The noisy data without missing entries; only if ``return_complete``.

    See Also
    --------
    make_transparent : Add a transparent second motion by swapping x and y.
    sklearn.datasets.make_blobs : The same interface for isotropic blobs.

    Notes
    -----
    Object ``i`` has points ``X_p`` (in pixels, in the object's frame) and in
    frame ``f`` the rotation ``R_if`` and translation ``T_if``; a shared
    weak-perspective scale ``s_f`` (slow zoom, close to 1) and the image
    centre ``c = (320, 240)`` complete the camera:

    .. math:: x_{fp} = s_f \\Pi (R_{if} X_p + T_{if}) + c
              = A_{if} [X_p; 1],

    with :math:`\\Pi` the projection onto the first two coordinates. Stacking
    the frames gives the motion matrix :math:`M_i = [s_f \\Pi R_{if} \\mid
    s_f \\Pi T_{if} + c]_f \\in R^{2F \\times 4}` and the trajectories of
    object ``i`` are the columns of :math:`W_i = M_i [X_p; 1]` (eq. (6) of
    the paper), of rank ``min(4, 2F)``, 3 or 2 for full, planar and linear
    structure. Rotations start at a uniformly random orientation and turn by
    0.03-0.1 rad per frame about a slowly jittering axis; translations move
    1-5 pixels per frame with small random accelerations. Degenerate motions
    of real sequences (e.g. planar motion on a ground plane) reach the same
    subspace dimensions through the motion instead of the structure.

    All motion subspaces nearly contain the trajectories of stationary
    points, so their smallest principal angles are small by nature; two
    motions are told apart by their largest principal angle
    :math:`\\theta_{max}` (:math:`\\sin \\theta_{max} = \\|P_i - P_j\\|_2`
    for subspaces of equal dimension). Every pair of motions has
    :math:`\\theta_{max} \\geq` ``min_angle`` (10 degrees by default): an
    object's rotation and translation (only the rotation under
    ``dependent="translation"``) are redrawn up to 1000 times until its
    subspace is that far from every earlier object's, and a ``ValueError``
    is raised if they never are. Under ``dependent="rotation"`` the subspaces
    share their rotation dimensions and differ, by design, only through the
    translations, by a few degrees (median about 7): no angle is enforced.

    References
    ----------
    .. [1] R. Vidal and R. Hartley, "Motion Segmentation with Missing Data
       using PowerFactorization and GPCA", CVPR 2004.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca.datasets import make_motions
    >>> X, y = make_motions(n_motions=2, n_points=60, n_frames=5,
    ...                     missing=0.2, random_state=0)
    >>> X.shape, np.bincount(y)
    ((60, 10), array([30, 30]))
    >>> round(float(np.isnan(X).mean()), 2)
    0.2
    """
    rng = check_random_state(random_state)
    sizes = _split_points(n_points, n_motions)
    types = _motion_types(motion_types, n_motions)

    zoom = np.exp(np.concatenate([[0.0], np.cumsum(rng.normal(0, 3e-3, n_frames - 1))]))
    centre = np.array(_IMAGE_SIZE) / 2
    shared_rotations = _rotations(n_frames, rng) if dependent == "rotation" else None
    shared_translations = (
        _translations(n_frames, rng) if dependent == "translation" else None
    )

    # A shared rotation leaves only the translations to tell motions apart,
    # a few degrees by design (see Notes): no angle is enforced then.
    required_angle = 0.0 if dependent == "rotation" else min_angle
    blocks, labels, subspaces = [], [], []
    for i, (size, kind) in enumerate(zip(sizes, types, strict=True)):
        points, basis = _structure(kind, size, rng)
        offset = np.zeros(3)
        if dependent == "translation":
            # Offset the object from the shared joint it rotates about.
            direction = rng.normal(size=3)
            offset = 120.0 * direction / np.linalg.norm(direction)
            points = points + offset
        # [X_p; 1] = span @ [coefficients; 1] for every point of the object.
        span = np.zeros((4, basis.shape[1] + 1))
        span[:3, :-1], span[:3, -1], span[3, -1] = basis, offset, 1.0
        for _ in range(_MAX_ATTEMPTS):
            rotations = (
                shared_rotations
                if dependent == "rotation"
                else _rotations(n_frames, rng)
            )
            translations = (
                shared_translations
                if dependent == "translation"
                else _translations(n_frames, rng)
            )
            subspace = _motion_subspace(rotations, translations, zoom, centre, span)
            if all(
                _largest_angle(subspace, other) >= required_angle for other in subspaces
            ):
                break
        else:
            raise ValueError(
                f"Could not draw motion {i} with a largest principal angle of at "
                f"least min_angle={min_angle} degrees to every earlier motion in "
                f"{_MAX_ATTEMPTS} attempts; lower min_angle or use more frames."
            )
        subspaces.append(subspace)
        world = np.einsum("fij,pj->pfi", rotations[:, :2, :], points)
        image = zoom[:, None] * (world + translations[:, :2]) + centre
        blocks.append(image.reshape(size, 2 * n_frames))
        labels.append(np.full(size, i))
    if n_outliers:
        blocks.append(
            rng.uniform(0, 1, size=(n_outliers, n_frames, 2)).reshape(n_outliers, -1)
            * np.tile(_IMAGE_SIZE, n_frames)
        )
        labels.append(np.full(n_outliers, -1))
    X_complete = np.vstack(blocks)
    y = np.concatenate(labels).astype(np.intp)
    X_complete += rng.normal(scale=noise, size=X_complete.shape)

    X = _apply_missing(X_complete, missing, missing_pattern, rng)

    if shuffle:
        order = rng.permutation(X.shape[0])
        X, y, X_complete = X[order], y[order], X_complete[order]
    if return_complete:
        return X, y, X_complete
    return X, y


@validate_params(
    {"X": ["array-like"], "y": ["array-like", None]},
    prefer_skip_nested_validation=True,
)
def make_transparent(X, y=None):
    """Add a transparent motion: a copy of the data with x and y swapped.

    The paper's section 3, item 4: static sequences are made dynamic by
    generating a second set of correspondences with the x and y coordinates
    interchanged, which overlaps the first in the image, so that motion is
    the only cue for clustering.

    Parameters
    ----------
    X : array-like of shape (n_samples, 2 * n_frames)
        Trajectories ``[x_1, y_1, ..., x_F, y_F]``; NaN (missing) allowed.

    y : array-like of shape (n_samples,), default=None
        Integer motion labels (``-1`` for outliers). None means a single
        static scene, all labels 0.

    Returns
    -------
    X2 : ndarray of shape (2 * n_samples, 2 * n_frames)
        ``X`` followed by its swapped copy.

    y2 : ndarray of shape (2 * n_samples,)
        ``y`` followed by the labels of the copy: motion ``k`` becomes
        ``k + max(y) + 1`` (label 1 for a static scene); outliers stay
        ``-1``.

    See Also
    --------
    make_motions : Synthetic multibody trajectories.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca.datasets import make_transparent
    >>> X = np.array([[1.0, 2.0, 3.0, 4.0]])
    >>> make_transparent(X)
    (array([[1., 2., 3., 4.],
           [2., 1., 4., 3.]]), array([0, 1]))
    """
    X = check_array(X, ensure_all_finite="allow-nan", dtype=np.float64)
    if X.shape[1] % 2:
        raise ValueError(
            f"X must have an even number of features [x_1, y_1, ...], got {X.shape[1]}."
        )
    if y is None:
        y = np.zeros(X.shape[0], dtype=np.intp)
    y = column_or_1d(y)
    check_consistent_length(X, y)
    if not np.issubdtype(y.dtype, np.integer):
        raise ValueError(f"y must hold integer labels, got dtype {y.dtype}.")
    swap = np.arange(X.shape[1]).reshape(-1, 2)[:, ::-1].ravel()
    offset = max(int(y.max()), 0) + 1
    y_swapped = np.where(y >= 0, y + offset, y)
    return np.vstack([X, X[:, swap]]), np.concatenate([y, y_swapped])
