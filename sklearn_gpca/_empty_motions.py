"""The warning for a segmentation with fewer groups than asked for."""

# SPDX-License-Identifier: BSD-3-Clause

import warnings

import numpy as np


def warn_empty_motions(labels, n_motions, X, *, name="n_motions", stacklevel=4):
    """Warn when some of the labels ``0 .. n_motions - 1`` are never used.

    As :class:`~sklearn.cluster.KMeans` does when it finds fewer distinct
    clusters than asked for, the labels are returned as they are and the
    warning says why: too few distinct tracks, or tracks that support fewer
    motions.

    Parameters
    ----------
    labels : ndarray of shape (n_tracks,)
        Motion of each track; ``-1`` (outliers) is ignored.
    n_motions : int
        Number of motions asked for.
    X : ndarray of shape (n_tracks, n_features)
        The tracks, NaN where missing.
    name : str, default="n_motions"
        The caller's name of ``n_motions``, for the message.
    stacklevel : int, default=4
        Passed to :func:`warnings.warn`.
    """
    counts = np.bincount(labels[labels >= 0], minlength=n_motions)
    empty = np.flatnonzero(counts == 0)
    if empty.size == 0:
        return
    kept = labels >= 0
    observed = ~np.isnan(X[kept])
    # a track is its observed values and where they are observed
    distinct = np.unique(np.hstack([np.nan_to_num(X[kept]), observed]), axis=0)
    if distinct.shape[0] < n_motions:
        reason = f"X has only {distinct.shape[0]} distinct tracks"
    else:
        reason = (
            f"the tracks support fewer motions; ask for {name}={n_motions - empty.size}"
        )
    warnings.warn(
        f"{empty.size} of the {name}={n_motions} motions are empty "
        f"(label {', '.join(str(k) for k in empty)}): {reason}.",
        UserWarning,
        stacklevel=stacklevel,
    )
