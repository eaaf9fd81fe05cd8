"""Step 4 of Algorithm 1: affine motion and structure of each segmented group."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
from sklearn.utils import Bunch, check_array, check_consistent_length

from sklearn_gpca._missing import masked_to_nan
from sklearn_gpca._power_factorization import PowerFactorization

_RANK = 4


def estimate_motions(X, labels, *, random_state=None):
    """Affine motion and 3-D structure of every group of trajectories.

    The standard factorisation for affine cameras (Tomasi & Kanade): the
    trajectories of one rigid body satisfy ``W_i = M_i S_i^T`` (equation (6)
    of the paper) with ``M_i`` the ``2F x 4`` stack of affine cameras and
    ``S_i`` the homogeneous 3-D points. Each group is factorised at rank 4
    with :class:`PowerFactorization`, so missing entries are allowed, and the
    factorisation is then fixed, among the ``4 x 4`` ambiguities, so that the
    last structure coordinate is as close to 1 as least squares allows.

    Parameters
    ----------
    X : array-like or masked array of shape (n_samples, 2 * n_frames)
        Trajectories, one per row (``[x_1, y_1, ..., x_F, y_F]``); missing
        entries are NaN (or masked).

    labels : array-like of shape (n_samples,)
        Integer group of each trajectory, e.g. the ``labels_`` of a
        segmentation. Negative labels (outliers, ``-1``) are ignored.

    random_state : int, RandomState instance or None, default=None
        Seed of the factorisations.

    Returns
    -------
    motions : list of Bunch
        One per group, in the order of ``numpy.unique(labels)``, with keys

        - ``label``: the group's label;
        - ``motion``: ndarray of shape (2 * n_frames, 4), the affine camera
          ``A_f`` of frame ``f`` in rows ``2f, 2f + 1`` (equation (4));
        - ``structure``: ndarray of shape (n_points, 4), homogeneous 3-D
          points (last column close to 1), defined up to an affine
          transformation of space;
        - ``points_3d``: ndarray of shape (n_points, 3), the dehomogenised
          structure;
        - ``residual``: root mean square reprojection error over the
          observed entries, in the units of ``X``.

    Raises
    ------
    ValueError
        If ``labels`` are not 1-D integers, a group has fewer than 4
        trajectories, its observed entries are all 0, or its trajectories
        have too few observed entries for a rank-4 factorisation.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca import estimate_motions
    >>> rng = np.random.RandomState(0)
    >>> cameras = rng.standard_normal((10, 4))
    >>> points = np.c_[rng.standard_normal((30, 3)), np.ones(30)]
    >>> X = points @ cameras.T
    >>> [motion] = estimate_motions(X, np.zeros(30, dtype=int), random_state=0)
    >>> motion.motion.shape, motion.points_3d.shape, bool(motion.residual < 1e-8)
    ((10, 4), (30, 3), True)
    """
    X = check_array(masked_to_nan(X), dtype=np.float64, ensure_all_finite="allow-nan")
    labels = _check_labels(labels)
    check_consistent_length(X, labels)
    motions = []
    for label in np.unique(labels[labels >= 0]):
        members = labels == label
        if members.sum() < _RANK:
            raise ValueError(
                f"Group {label} has {members.sum()} trajectories; a rank-4 affine "
                f"factorisation needs at least {_RANK}."
            )
        motions.append(_factorise(X[members], label, random_state))
    return motions


def _check_labels(labels):
    """Integer labels of shape (n_samples,), or a ValueError naming the problem."""
    labels = np.asarray(labels)
    if labels.ndim != 1:
        raise ValueError(
            f"labels must be 1-D (one group per trajectory), got shape {labels.shape}."
        )
    if labels.dtype.kind in "iub":
        return labels.astype(np.intp)
    if labels.dtype.kind == "f":
        fractional = labels[labels != np.round(labels)]
        if fractional.size == 0:
            return labels.astype(np.intp)
        raise ValueError(
            f"labels must be integers, such as the labels_ of a segmentation; "
            f"got {fractional[0]}."
        )
    raise ValueError(
        "labels must be integers, such as the labels_ of a segmentation; got "
        f"dtype {labels.dtype}."
    )


def _factorise(X, label, random_state):
    if not np.any(np.nan_to_num(X)):
        raise ValueError(
            f"Group {label}: every observed entry is 0; there is no motion to estimate."
        )
    pf = PowerFactorization(_RANK, whiten=False, random_state=random_state)
    try:
        coords = pf.fit_transform(X)
    except ValueError as error:
        raise ValueError(f"Group {label}: {error}") from error
    # X ~ coords @ components_: choose T with coords @ T[:, -1] ~ 1, so that
    # structure = coords @ T is homogeneous and motion^T = T^-1 components_.
    h = np.linalg.lstsq(coords, np.ones(len(coords)), rcond=None)[0]
    complement = np.linalg.svd(h[None, :])[2][1:]
    T = np.c_[complement.T, h]
    structure = coords @ T
    motion = np.linalg.solve(T, pf.components_).T
    return Bunch(
        label=label,
        motion=motion,
        structure=structure,
        points_3d=structure[:, :3] / structure[:, 3:],
        residual=pf.reconstruction_err_,
    )
