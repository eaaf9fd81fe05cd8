"""Synthetic tracker output: long sequences of tracks born and lost in a 3-D scene."""

# SPDX-License-Identifier: BSD-3-Clause

from numbers import Integral, Real

import numpy as np
from sklearn.utils import Bunch, check_random_state
from sklearn.utils._param_validation import Interval, StrOptions, validate_params

from sklearn_gpca.datasets._track_draw import draw_for_target
from sklearn_gpca.datasets._track_geometry import motion_poses
from sklearn_gpca.datasets._track_lifetimes import (
    calibrate_lifetime,
    geometric_lifetimes,
    track_lengths,
)
from sklearn_gpca.datasets._track_scenes import SCENES

#: Most motions (background included) :func:`make_tracks` draws.
MAX_MOTIONS = 10


def _resolve(scene, **given):
    """Scene defaults for the parameters left to None, checked where needed."""
    if given["missing"] is not None and given["mean_lifetime"] is not None:
        raise ValueError(
            f"Give missing={given['missing']} or mean_lifetime="
            f"{given['mean_lifetime']}, not both: the mean lifetime is calibrated "
            "to reach the missing fraction."
        )
    params = {
        name: SCENES[scene][name] if value is None else value
        for name, value in given.items()
    }
    if given["missing"] is not None:
        params["mean_lifetime"] = None
    elif given["mean_lifetime"] is not None:
        params["missing"] = None
    for name in ("image_size", "depth_range"):
        values = (
            np.asarray(params[name], dtype=float) if _numeric(params[name]) else None
        )
        if (
            values is None
            or values.shape != (2,)
            or not np.all(np.isfinite(values))
            or np.any(values <= 0)
        ):
            raise ValueError(
                f"{name} must be two positive numbers, got {params[name]!r}."
            )
        params[name] = tuple(float(v) for v in values)
    if params["depth_range"][0] > params["depth_range"][1]:
        raise ValueError(
            f"depth_range must be (nearest, farthest) with nearest <= farthest, "
            f"got {params['depth_range']!r}."
        )
    return params


def _numeric(value):
    try:
        np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        return False
    return True


def _track_counts(n_tracks, n_motions, background_fraction, outlier_fraction, rng):
    """Tracks of each motion (background first) and number of outliers."""
    n_outliers = round(outlier_fraction * n_tracks)
    n_inliers = n_tracks - n_outliers
    n_objects = n_motions - 1
    n_background = (
        n_inliers if n_objects == 0 else round(background_fraction * n_inliers)
    )
    n_moving = n_inliers - n_background
    if n_background < 1 or n_moving < n_objects:
        raise ValueError(
            f"n_tracks={n_tracks} with outlier_fraction={outlier_fraction} and "
            f"background_fraction={background_fraction} gives {n_background} "
            f"background tracks and {n_moving} tracks for the {n_objects} moving "
            "objects; every motion needs at least one track."
        )
    counts = np.zeros(n_motions, dtype=np.int64)
    counts[0] = n_background
    if n_objects:
        # Objects near and far, large and small: unequal shares, at least one each.
        shares = rng.dirichlet(np.full(n_objects, 4.0))
        extra = n_moving - n_objects
        floors = np.floor(shares * extra).astype(np.int64)
        remainder = extra - floors.sum()
        floors[np.argsort(floors - shares * extra)[:remainder]] += 1
        counts[1:] = 1 + floors
    return counts, n_outliers


def _end_reasons(births, ends, exits, in_view, n_frames):
    reasons = np.full(births.size, "lifetime", dtype=object)
    lost = ends == exits
    reasons[lost & (exits == n_frames)] = "sequence_end"
    rows = np.flatnonzero(lost & (exits < n_frames))
    seen = in_view[rows, exits[rows]]
    reasons[rows[~seen]] = "left_view"
    reasons[rows[seen]] = "occluded"
    return reasons.astype(str)


def _motion_matrices(scene, camera):
    """Exact affine camera of each motion, :math:`x_{fp} = M_{k,f} [X_p; 1]`."""
    n_frames = scene.camera_rotations.shape[0]
    n_motions = camera.zref.shape[0]
    matrices = np.empty((n_motions, n_frames, 2, 4))
    Rc, C = scene.camera_rotations, scene.camera_centres
    for k in range(n_motions):
        Ro, To = motion_poses(scene, k)
        scale = (camera.focal_length / camera.zref[k])[:, None, None]
        rotation = np.einsum("fji,fjk->fik", Rc, Ro)[:, :2]
        translation = np.einsum("fji,fj->fi", Rc, To - C)[:, :2]
        matrices[k, :, :, :3] = scale * rotation
        matrices[k, :, :, 3] = scale[:, :, 0] * translation + camera.centre
    return matrices.reshape(n_motions, 2 * n_frames, 4)


@validate_params(
    {
        "n_motions": [Interval(Integral, 1, MAX_MOTIONS, closed="both"), None],
        "scene": [StrOptions(set(SCENES))],
        "n_tracks": [Interval(Integral, 1, None, closed="left"), None],
        "n_frames": [Interval(Integral, 3, None, closed="left"), None],
        "background_fraction": [Interval(Real, 0, 1, closed="both"), None],
        "outlier_fraction": [Interval(Real, 0, 1, closed="left"), None],
        "missing": [Interval(Real, 0, 1, closed="left"), None],
        "mean_lifetime": [Interval(Real, 1, None, closed="left"), None],
        "camera": [StrOptions({"perspective", "affine"})],
        "focal_length": [Interval(Real, 0, None, closed="neither"), None],
        "image_size": ["array-like", None],
        "depth_range": ["array-like", None],
        "forward_speed": [Interval(Real, 0, None, closed="left"), None],
        "frame_rate": [Interval(Real, 0, None, closed="neither"), None],
        "noise": [Interval(Real, 0, None, closed="left"), None],
        "units": [StrOptions({"normalized", "pixels"})],
        "shuffle": ["boolean"],
        "random_state": ["random_state"],
        "return_info": ["boolean"],
    },
    prefer_skip_nested_validation=True,
)
def make_tracks(
    n_motions=None,
    *,
    scene="driving",
    n_tracks=None,
    n_frames=None,
    background_fraction=None,
    outlier_fraction=None,
    missing=None,
    mean_lifetime=None,
    camera="perspective",
    focal_length=None,
    image_size=None,
    depth_range=None,
    forward_speed=None,
    frame_rate=None,
    noise=None,
    units="normalized",
    shuffle=True,
    random_state=None,
    return_info=False,
):
    """Generate a feature tracker's output on a 3-D scene with moving objects.

    A camera moves through a static world (the background) in which 0-9 rigid
    objects move on their own; a tracker follows points of all of them. Tracks
    are born all along the sequence (in the first frame and wherever the
    tracker re-detects features) and lost after a geometric lifetime, or when
    they leave the image, go behind the camera, turn away or are hidden by an
    object. A few tracks are outliers that follow no single rigid motion. Rows
    are trajectories ``[x_1, y_1, ..., x_F, y_F]`` with NaN where a track is
    not observed, as :func:`make_motions` returns them, but shaped like real
    tracker output rather than Hopkins155.

    Parameters left to None take the ``scene``'s default (see Notes).

    Parameters
    ----------
    n_motions : int in [1, 10], default=None
        Number of motions, the background included: label 0 is the background
        (the static world seen by the moving camera), labels 1 ..
        ``n_motions - 1`` are independently moving objects.

    scene : {"driving", "handheld", "lab"}, default="driving"
        The kind of footage, which sets the camera path, the objects and the
        defaults of every parameter left to None:

        - ``"driving"`` imitates KT3DMoSeg (KITTI): a car-mounted camera
          driving forward, cars and cyclists ahead, beside and oncoming,
          strong perspective;
        - ``"handheld"`` imitates FBMS-59: a hand-held camera panning to
          follow walking, riding or driving subjects, long sequences;
        - ``"lab"`` imitates Hopkins155: boxes sliding and turning in front of
          a slowly moving camera, complete tracks, weak perspective.

    n_tracks : int, default=None
        Number of tracks (rows), outliers included.

    n_frames : int >= 3, default=None
        Number of frames ``F``; the data has ``2 F`` features.

    background_fraction : float in [0, 1], default=None
        Share of the inlier tracks on the background. The moving objects share
        the rest unequally (Dirichlet proportions), at least one track each.

    outlier_fraction : float in [0, 1), default=None
        Share of the tracks that are outliers, labelled ``-1`` (the noise
        label of DBSCAN and HDBSCAN); ``round(outlier_fraction * n_tracks)``
        of them. The mix of outlier kinds is documented in Notes.

    missing : float in [0, 1), default=None
        Target fraction of missing entries. The mean lifetime of the tracks is
        calibrated so that the drawn tracks miss this fraction of the
        ``n_tracks x n_frames`` point-frames (within 0.005, usually a few
        entries). 0 gives complete tracks, every one seen in every frame.
        Tracks leaving the view set a floor that grows with the sequence's
        duration: a ``ValueError`` says when even endless lifetimes miss more
        (then shorten the sequence, raise ``frame_rate`` or slow the camera;
        ``benchmarks/results/tracks.md`` shows the floors). Exclusive with
        ``mean_lifetime``.

    mean_lifetime : float >= 1, default=None
        Mean of the geometric lifetime of the tracks, in frames, instead of a
        ``missing`` target: then the missing fraction is whatever the births,
        lifetimes and exits from the view give.

    camera : {"perspective", "affine"}, default="perspective"
        ``"perspective"``: a pinhole camera. ``"affine"``: a weak-perspective
        camera, each motion projected with the scale ``focal_length / Z``, the
        depth ``Z`` of the object's centre in that frame (the geometric mean
        of ``depth_range`` for the background); every motion's complete tracks
        then span a subspace of dimension at most 4 (the exact model of the
        paper, returned in ``info.motion_matrices``). The visibility of the
        points (depth, image, occlusions) is the same in both.

    focal_length : float > 0, default=None
        Focal length in pixels.

    image_size : (width, height), default=None
        Image size in pixels; the principal point is its centre.

    depth_range : (nearest, farthest), default=None
        Depths (metres) of the background points where the tracker first sees
        them, drawn log-uniformly (and never below the ground plane). Points
        nearer than ``nearest / 4`` are lost. In the "lab" scene the objects
        stand in this range too.

    forward_speed : float >= 0, default=None
        Mean camera speed along its heading, in metres per second.

    frame_rate : float > 0, default=None
        Frames per second. The scene's motions are drawn at its native rate
        (the default) and resampled, so a higher rate gives the same motion
        in more, closer frames.

    noise : float >= 0, default=None
        Standard deviation (pixels) of the Gaussian noise on every observed
        coordinate; in normalised units it is divided by ``width / 2`` (x) and
        ``height / 2`` (y).

    units : {"normalized", "pixels"}, default="normalized"
        ``"normalized"``: Hopkins155's ``x``, the image mapped onto
        ``[-1, 1] x [-1, 1]`` by ``x = K^{-1} u`` with ``K = [[w/2, 0, w/2],
        [0, h/2, h/2], [0, 0, 1]]`` (the matrix in every Hopkins155 file);
        values of order 1, the scale the library's defaults are set for.
        ``"pixels"``: image coordinates. The two differ by one affine map per
        frame, so subspace dimensions are the same.

    shuffle : bool, default=True
        Shuffle the rows. If False, rows are ordered by label, outliers last.

    random_state : int, RandomState instance or None, default=None
        Seed of all the randomness.

    return_info : bool, default=False
        Also return a :class:`~sklearn.utils.Bunch` describing the draw.

    Returns
    -------
    X : ndarray of shape (n_tracks, 2 * n_frames)
        Tracks, NaN where not observed. Each track is observed on one window
        of consecutive frames, at least one frame long.

    y : ndarray of shape (n_tracks,)
        Label of each track: 0 the background, 1 .. ``n_motions - 1`` the
        objects, -1 the outliers.

    info : Bunch
        Only if ``return_info``:

        - ``birth``, ``end`` (n_tracks,): the track is observed in frames
          ``birth <= f < end``;
        - ``end_reason`` (n_tracks,): ``"lifetime"``, ``"left_view"`` (left
          the image or went behind the camera), ``"occluded"`` (hidden by an
          object or turned away) or ``"sequence_end"``;
        - ``lifetime`` (n_tracks,): the drawn geometric lifetime, before the
          view and the sequence cut it (-1 for complete tracks);
          ``mean_lifetime``: its mean (the calibrated value when ``missing``
          is the target; inf for complete tracks); ``first_frame_share``: the
          share ``q`` of births in frame 0 (see Notes);
        - ``kind`` (n_tracks,): ``"inlier"``, ``"drift"``, ``"jump"`` or
          ``"random_walk"``; ``switch_frame`` (the last frame before an
          outlier's switch, -1 otherwise) and ``source_motions`` (n_tracks, 2)
          (the motions a drift or jump outlier follows, -1 otherwise);
        - ``X_clean``: ``X`` without noise; ``X_complete``: the noise-free
          projection in every frame, seen or not (NaN behind a perspective
          camera); for an outlier, its path in every frame;
        - ``points`` (n_tracks, 3): each inlier's 3-D point in its motion's
          frame (world for the background, the object's box frame otherwise;
          NaN for outliers);
        - ``camera_rotations`` (F, 3, 3), ``camera_centres`` (F, 3): camera to
          world; ``object_rotations`` (n_motions - 1, F, 3, 3),
          ``object_centres`` (n_motions - 1, F, 3), ``object_sizes``
          (n_motions - 1, 3): box to world, in metres;
        - ``K``: the normalisation matrix (identity for ``units="pixels"``);
          ``focal_length``, ``image_size``, ``noise`` (in output units,
          (x, y));
        - ``motion_matrices`` (n_motions, 2F, 4): for the affine camera, the
          exact motion of each motion, ``X_complete[p] = M[y_p] @ [X_p; 1]``
          in output units; None for the perspective camera;
        - ``params``: every parameter of the draw, defaults resolved.

    See Also
    --------
    make_motions : Complete or randomly masked tracks under an affine camera.
    make_missing : Remove entries from complete tracks.

    Notes
    -----
    **Scenes and the datasets they imitate.** Defaults:

    ========================  ========  ========  ========
    parameter                 driving   handheld  lab
    ========================  ========  ========  ========
    n_motions                 3         3         2
    n_tracks                  500       800       300
    n_frames                  20        100       30
    frame_rate (per second)   10        30        30
    background_fraction       0.75      0.75      0.65
    outlier_fraction          0.05      0.03      0
    missing                   --        0.5       0
    mean_lifetime (frames)    40        --        --
    image_size                1242x375  640x480   640x480
    focal_length (pixels)     721.5     600       800
    depth_range (metres)      8-80      3-40      2-3.5
    forward_speed (m/s)       8         0.6       0
    noise (pixels)            0.5       0.5       0.25
    ========================  ========  ========  ========

    - ``"driving"``, KT3DMoSeg (Xu, Cheong & Li, CVPR 2018): 22 KITTI clips
      of 10-20 frames with 2-5 motions, chosen for strong camera translation
      (the dataset's README); KITTI's rectified images are 1242 x 375 pixels
      with a focal length of 721.5 pixels (``P_rect_02`` of the calibration
      files) and it records at 10 Hz (Geiger et al., IJRR 2013); its camera
      stands about 1.65 m above the road. The street has facades 6-15 m to
      either side, a road with few features (asphalt) and clutter at 8-80 m;
      cars and cyclists drive ahead, beside or towards the camera. In
      forward motion tracks leave the view fast, so the missing fraction
      follows from the motion (a lifetime, not a target, is the default).
      Estimates: the speed (8 m/s, urban), the number of tracks, the
      background share, the lifetime and the outlier rate. KT3DMoSeg keeps
      tracks of 5 frames or more from a dense tracker; here the short ones
      stay, as in raw tracker output.
    - ``"handheld"``, FBMS-59 (Ochs, Malik & Brox, PAMI 2014): 59 sequences of
      hand-held and film footage, 19 to 800 frames, of people, animals and
      cars, with tracks born and lost all along (from the paper, not
      rechecked here). The camera walks slowly and pans to keep one subject
      in the middle third of the image. Estimates: 100 frames, 30 frames per
      second, subjects walking at 1-2 m/s, a 56-degree field of view.
    - ``"lab"``, Hopkins155 (Tron & Vidal, CVPR 2007): 640 x 480 images; 120
      of the 155 sequences have 2 motions, 29.4 frames and 296 tracks on
      average, the largest group holds a median 65% of the tracks, and every
      track is complete (all measured on the dataset's files). Boxes of
      10-30 cm slide and turn in front of a slowly moving camera. Estimates:
      the focal length and depths (weak perspective); the noise is set so
      that a rank-4 fit of each motion leaves about the RMS residual measured
      on Hopkins155 (0.26 pixels, see ``benchmarks/results/tracks.md``).

    The outlier rates are estimates: the Hopkins155 sequences released with
    outliers have 13.9% outlier tracks and 29.5% missing entries on average
    (4 sequences, 54 frames, from their README); tracker output that has not
    been hand-cleaned has a few percent.

    **Births and lifetimes.** A tracker that keeps as many tracks alive in
    every frame, replacing each lost track by a new one, starts a share ``q``
    of its tracks in frame 0 and the rest in equal numbers in frames 1 ..
    F-1; it observes ``N F`` of its ``P F`` entries with ``N = q P`` alive
    per frame, so ``q = 1 - missing``. With a ``mean_lifetime`` ``m`` instead,
    ``q = m / (m + F - 1)`` (no other losses). Where tracks leave the view so
    fast that no lifetime reaches ``missing``, the tracker replaces fewer of
    them: ``q`` moves halfway to 1, then to 1 (``info.first_frame_share``);
    a scene in which even that misses more than ``missing`` is drawn again,
    up to 5 times, so that targets near the floor favour calmer scenes. A track is born
    at a point of its motion visible in that frame (background points at a
    uniform pixel and a log-uniform depth, stopped by the ground and the
    facades; object points uniformly on the visible faces of its box, in the
    frames in proportion to how much of the box is visible) and lives ``L``
    frames, ``P(L >= k) = (1 - 1/m)^(k-1)`` (geometric, mean ``m``, so
    ``P(L <= 2) ~ 2/m``), unless it leaves the image, goes behind the camera,
    turns away, is hidden by an object or the sequence ends first. With a
    ``missing`` target, ``m`` is calibrated to it by bisection;
    with ``missing=0`` every track is born in frame 0 and stays visible to
    the end.

    **Outliers.** Half are *drift* tracks (the tracker slides from a point of
    one motion to another at frame ``s``: continuous position, switched
    motion), a quarter *jump* tracks (the tracker locks onto a feature of
    another motion: the position jumps), a quarter *random walks* (a point on
    no rigid body, moving at the scene's typical image speed). Drift and jump
    tracks are seen at least two frames each side of the switch, random walks
    at least three frames. This mix is an estimate.

    References
    ----------
    .. [1] X. Xu, L.-F. Cheong and Z. Li, "Motion Segmentation by Exploiting
       Complementary Geometric Models", CVPR 2018 (KT3DMoSeg).
    .. [2] P. Ochs, J. Malik and T. Brox, "Segmentation of Moving Objects by
       Long Term Video Analysis", IEEE TPAMI 36(6), 2014 (FBMS-59).
    .. [3] R. Tron and R. Vidal, "A Benchmark for the Comparison of 3-D Motion
       Segmentation Algorithms", CVPR 2007 (Hopkins155).
    .. [4] A. Geiger, P. Lenz, C. Stiller and R. Urtasun, "Vision meets
       Robotics: The KITTI Dataset", IJRR 32(11), 2013.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca.datasets import make_tracks
    >>> X, y = make_tracks(
    ...     scene="handheld", n_tracks=200, n_frames=50, missing=0.5, random_state=0
    ... )
    >>> X.shape
    (200, 100)
    >>> round(float(np.isnan(X).mean()), 2)
    0.5
    >>> sorted(set(y.tolist()))
    [-1, 0, 1, 2]
    """
    rng = check_random_state(random_state)
    p = _resolve(
        scene,
        n_motions=n_motions,
        n_tracks=n_tracks,
        n_frames=n_frames,
        background_fraction=background_fraction,
        outlier_fraction=outlier_fraction,
        missing=missing,
        mean_lifetime=mean_lifetime,
        focal_length=focal_length,
        image_size=image_size,
        depth_range=depth_range,
        forward_speed=forward_speed,
        frame_rate=frame_rate,
        noise=noise,
    )
    F = p["n_frames"]
    counts, n_outliers = _track_counts(
        p["n_tracks"],
        p["n_motions"],
        p["background_fraction"],
        p["outlier_fraction"],
        rng,
    )
    complete = p["missing"] == 0
    d = draw_for_target(scene, camera, p, counts, n_outliers, complete, rng)
    pixels, in_view, births, exits = d.pixels, d.in_view, d.births, d.exits
    points, labels, kinds = d.points, d.labels, d.kinds
    switch, sources, min_lengths, world = d.switch, d.sources, d.min_lengths, d.world
    cam = d.camera

    # Lifetimes: geometric, cut by the view and the end of the sequence.
    max_lengths = exits - births
    uniform = 1.0 - rng.random_sample(births.size)
    if complete:
        mean = np.inf
    elif p["missing"] is not None:
        mean = calibrate_lifetime(uniform, min_lengths, max_lengths, F, p["missing"])
    else:
        mean = float(p["mean_lifetime"])
    lengths = track_lengths(uniform, mean, min_lengths, max_lengths)
    ends = births + lengths
    frames = np.arange(F)
    observed = (frames >= births[:, None]) & (frames < ends[:, None])

    # Noise in pixels, then the output units.
    width, height = p["image_size"]
    K = np.eye(3)
    if units == "normalized":
        K = np.array(
            [[width / 2, 0, width / 2], [0, height / 2, height / 2], [0, 0, 1]]
        )
    scale = np.array([K[0, 0], K[1, 1]])
    offset = K[:2, 2]
    X_complete = ((pixels - offset) / scale).reshape(births.size, 2 * F)
    X_clean = np.where(np.repeat(observed, 2, axis=1), X_complete, np.nan)
    noise_px = rng.normal(scale=p["noise"], size=X_clean.shape)
    X = X_clean + (noise_px.reshape(-1, F, 2) / scale).reshape(X_clean.shape)
    y = labels.astype(np.intp)

    order = rng.permutation(y.size) if shuffle else np.arange(y.size)
    X, y = X[order], y[order]
    if not return_info:
        return X, y

    motion_matrices = None
    if camera == "affine":
        to_units = np.tile(np.array([1 / scale[0], 1 / scale[1]]), F)[:, None]
        motion_matrices = _motion_matrices(world, cam) * to_units
        motion_matrices[:, :, 3] -= np.tile(offset / scale, F)
    if np.isfinite(mean):
        lifetimes = geometric_lifetimes(uniform, mean)
    else:
        lifetimes = np.full(births.size, -1, dtype=np.int64)
    info = Bunch(
        birth=births[order],
        end=ends[order],
        end_reason=_end_reasons(births, ends, exits, in_view, F)[order],
        lifetime=lifetimes[order],
        mean_lifetime=mean,
        first_frame_share=d.first_share,
        kind=kinds.astype(str)[order],
        switch_frame=switch[order],
        source_motions=sources[order],
        X_clean=X_clean[order],
        X_complete=X_complete[order],
        points=points[order],
        camera_rotations=world.camera_rotations,
        camera_centres=world.camera_centres,
        object_rotations=world.object_rotations,
        object_centres=world.object_centres,
        object_sizes=world.object_sizes,
        K=K,
        focal_length=p["focal_length"],
        image_size=p["image_size"],
        noise=(p["noise"] / scale[0], p["noise"] / scale[1]),
        motion_matrices=motion_matrices,
        params=dict(p, scene=scene, camera=camera, units=units),
    )
    return X, y, info
