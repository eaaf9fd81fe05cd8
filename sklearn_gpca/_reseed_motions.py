"""New tracks for the motions a refinement emptied.

Beyond the paper. Smoothed K-subspaces (:mod:`sklearn_gpca._refine_observed`)
can lose a motion: a small object whose subspace the background's nearly
contains is absorbed by it, and its label is left with no track (or too few to
span a subspace). Asked for ``n`` motions, the segmentation then holds fewer,
and an object is mislabelled whole. As :class:`~sklearn.cluster.KMeans`
relocates an empty cluster, each emptied motion gets the smaller half of the
largest motion, split in two by the fragments route on its own tracks
(:func:`sklearn_gpca._merge_split.split_in_two`); the caller refines the
result again.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._merge_split import split_in_two


def reseed_empty_motions(
    X0,
    mask,
    labels,
    n_motions,
    affinity,
    noise,
    *,
    min_tracks,
    min_size,
    per_fragment,
    random_state,
):
    """Labels with every motion of fewer than ``min_tracks`` tracks re-seeded.

    Parameters
    ----------
    X0, mask : ndarray of shape (n_tracks, n_features)
        Tracks (zero where missing) and observed entries.
    labels : ndarray of shape (n_tracks,)
        Motion of each track in ``0 .. n_motions - 1``; ``-1`` (outliers) is
        left alone.
    n_motions : int
    affinity : sparse matrix of shape (n_tracks, n_tracks)
        Motion affinity of the tracks
        (:func:`sklearn_gpca._motion_graph.motion_affinity`).
    noise : float
        Noise variance per coordinate.
    min_tracks : int
        A motion with fewer tracks counts as emptied (``subspace_dim + 1``:
        too few to span its subspace).
    min_size, per_fragment : int
        Of the split (see :func:`sklearn_gpca._merge_split.split_in_two`).
    random_state : RandomState instance

    Returns
    -------
    labels : ndarray of shape (n_tracks,) or None
        The re-seeded labels, None when no motion was emptied or the largest
        motion could not be split.
    """
    labels = np.asarray(labels, dtype=np.intp).copy()
    changed = False
    for _ in range(n_motions):
        sizes = np.bincount(labels[labels >= 0], minlength=n_motions)
        emptied = np.flatnonzero(sizes < min_tracks)
        if not emptied.size:
            break
        members = np.flatnonzero(labels == np.argmax(sizes))
        halves = split_in_two(
            X0[members],
            mask[members],
            affinity[members][:, members],
            noise,
            min_size=min_size,
            per_fragment=per_fragment,
            random_state=random_state,
        )
        if halves is None:
            break
        smaller = int(np.sum(halves == 1) < np.sum(halves == 0))
        labels[members[halves == smaller]] = emptied[0]
        changed = True
    return labels if changed else None
