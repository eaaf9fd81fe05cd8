"""Starts that keep a segmentation's largest motion and segment the rest anew.

Beyond the paper (issue 17). On a tracker's output the background holds
70-80 % of the tracks. The routes of :func:`sklearn_gpca.segment_motions`
build one motion graph over every track, and its spectral fragments are cut
to the background's scale: two small objects that move alike for part of
the sequence fall into fragments shared between them, and the refinement
(which moves tracks one at a time) keeps the mix. Once a candidate has found
the background, the other tracks are a small scene of their own, with
``n_motions - 1`` motions: their own motion graph (neighbours, affinity and
fragments among them alone) separates what the global one blurred. A
*re-segmented* start keeps the candidate's largest motion and labels the rest
by the fragments route (:mod:`sklearn_gpca._fragments`) and by the peeled
starts (:mod:`sklearn_gpca._peel_starts`) on those tracks; the caller refines
every start on all the tracks and judges it beside the others.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._fragments import (
    MIN_FRAGMENT_SIZE,
    merge_fragments,
    track_fragments,
)
from sklearn_gpca._motion_graph import motion_affinity
from sklearn_gpca._peel_starts import peel_candidates
from sklearn_gpca._track_neighbors import track_neighbors


def resegmented_starts(
    X0,
    mask,
    labels,
    n_motions,
    noise,
    *,
    n_neighbors,
    random_state,
):
    """Starts keeping the largest motion of ``labels``, the rest segmented anew.

    Parameters
    ----------
    X0 : ndarray of shape (n_samples, n_features)
        Tracks, zero where missing.
    mask : ndarray of shape (n_samples, n_features), dtype=bool
        Observed entries.
    labels : ndarray of shape (n_samples,)
        A segmentation in ``0 .. n_motions - 1``.
    n_motions : int
        Number of motions, at least 3 (with 2 the rest is one motion).
    noise : float
        Noise variance per coordinate.
    n_neighbors : int
        Neighbours of each track in the rest's motion graph.
    random_state : RandomState instance
        For the spectral over-segmentation.

    Returns
    -------
    starts : list of (str, ndarray of shape (n_samples,))
        Name and labels of each start (the largest motion keeps its label,
        the rest labels ``0 .. n_motions - 1`` but that one); empty when the
        rest has too few tracks to segment.
    """
    labels = np.asarray(labels, dtype=np.intp)
    largest = int(np.argmax(np.bincount(labels, minlength=n_motions)))
    rest = np.flatnonzero(labels != largest)
    n_rest = n_motions - 1
    if n_rest < 2 or rest.size <= max(2 * n_neighbors, n_rest * MIN_FRAGMENT_SIZE):
        return []
    Xr, mr = X0[rest], mask[rest]
    neighbors = track_neighbors(Xr, mr, n_neighbors)
    affinity = motion_affinity(Xr, mr, neighbors)
    # the fragments of the segmentation's own routes, on these tracks alone
    fragments = track_fragments(affinity, n_rest, random_state=random_state)
    found = []
    if fragments.max() + 1 > n_rest:
        found.append(("fragments", merge_fragments(Xr, mr, fragments, n_rest, noise)))
    found.extend(peel_candidates(Xr, mr, fragments, n_rest, noise))
    others = np.delete(np.arange(n_motions), largest)
    starts = []
    for name, sub in found:
        start = labels.copy()
        start[rest] = others[sub]
        starts.append((f"re-segmented {name}", start))
    return starts
