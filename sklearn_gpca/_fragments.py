"""Over-segment tracks into pure fragments, then merge fragments into motions.

Beyond the paper. Spectral clustering of the motion affinity
(:func:`sklearn_gpca._motion_graph.motion_affinity`) into many more clusters
than motions gives *fragments*: spatially coherent groups of tracks that move
alike, nearly always of one motion (on Hopkins155, the fragments' majority
labels misassign 0.8 % of the tracks). Fragments too small to fix a subspace
join the fragment they are most connected to. The rest are merged greedily:
each fragment gets the subspace of smallest dimension that fits its tracks
to the noise level (:func:`fit_adaptive_subspace`), the linkage of two
fragments is the smaller of the two median residuals per degree of freedom
of one fragment's tracks to the other's subspace (in units of the noise), and
the pair with the smallest linkage merges until ``n_clusters`` are left. The
smaller of the two directions is used because a small fragment's subspace
is poorly conditioned away from its own tracks, while the larger fragment's
subspace judges the smaller one fairly.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._affinity import _between_cluster_weights
from sklearn_gpca._observed_subspaces import (
    fit_adaptive_subspace,
    subspace_residuals,
)
from sklearn_gpca._spectral import embedding_kmeans, leading_eigenvectors

#: Most tracks of a group used to fit its subspace and to take the medians of
#: its linkage: evenly spread over its members (its fragments in proportion).
#: Beyond a few hundred tracks a subspace of dimension <= 8 and a median are
#: set; without the cap each merge refits the whole grown group and the
#: merging costs grow as the square of the number of tracks (6,400 tracks:
#: 62 s of segment_motions' 97 s).
MAX_GROUP_TRACKS = 1000
#: Fragments smaller than this join a neighbouring fragment before merging.
MIN_FRAGMENT_SIZE = 12
#: Tracks per fragment aimed at by the over-segmentation (at least 4 per motion).
TRACKS_PER_FRAGMENT = 40


def over_segment(affinity, n_fragments, *, random_state):
    """Spectral clustering of ``affinity`` into ``n_fragments`` clusters.

    Returns labels in ``0 .. n_fragments - 1`` (dtype intp).
    """
    n_samples = affinity.shape[0]
    n_fragments = min(n_fragments, n_samples - 1)
    vectors = leading_eigenvectors(affinity, n_fragments, random_state)
    return embedding_kmeans(vectors, n_fragments, n_init=3, random_state=random_state)


def track_fragments(affinity, n_motions, *, random_state):
    """Spectral over-segmentation of the motion graph, small fragments absorbed."""
    n_samples = affinity.shape[0]
    n_fragments = max(4 * n_motions, n_samples // TRACKS_PER_FRAGMENT)
    n_fragments = min(n_fragments, n_samples - 1)
    fragments = over_segment(affinity, n_fragments, random_state=random_state)
    return absorb_small_fragments(affinity, fragments, MIN_FRAGMENT_SIZE)


def absorb_small_fragments(affinity, fragments, min_size):
    """Join every fragment of fewer than ``min_size`` tracks to its best neighbour.

    The smallest fragment goes first, to the fragment it shares the most
    affinity with (the largest one when it has no edge out). Returns labels
    renumbered ``0 .. m - 1``.
    """
    _, fragments = np.unique(fragments, return_inverse=True)
    fragments = fragments.astype(np.intp)
    while True:
        sizes = np.bincount(fragments)
        small = np.flatnonzero(sizes < min_size)
        if small.size == 0 or sizes.size <= 1:
            return fragments
        weights = _between_cluster_weights(affinity, fragments, sizes.size)
        np.fill_diagonal(weights, 0.0)
        g = small[np.argmin(sizes[small])]
        if weights[g].sum() > 0:
            target = int(np.argmax(weights[g]))
        else:
            target = int(np.argmax(np.where(np.arange(sizes.size) == g, -1, sizes)))
        fragments[fragments == g] = target
        _, fragments = np.unique(fragments, return_inverse=True)
        fragments = fragments.astype(np.intp)


def _group_medians(values, groups, n_groups):
    """Median of the finite ``values`` of each group; inf for a group with none.

    The same numbers as ``np.median`` of each group's finite values (the
    mean of the two middle ones for an even count), from one sort.
    """
    finite = np.isfinite(values)
    values, groups = values[finite], groups[finite]
    values = values[np.lexsort((values, groups))]
    counts = np.bincount(groups, minlength=n_groups)
    found = counts > 0
    starts = (np.cumsum(counts) - counts)[found]
    low = values[starts + (counts[found] - 1) // 2]
    high = values[starts + counts[found] // 2]
    medians = np.full(n_groups, np.inf)
    medians[found] = np.where(counts[found] % 2, low, (low + high) / 2)
    return medians


def _residuals_per_dof(X0, mask, fit, min_dof):
    """Residual per degree of freedom of every track to one subspace.

    NaN for a track with fewer than ``min_dof`` residual degrees of freedom.
    """
    residuals, dofs = subspace_residuals(X0, mask, [fit[0]], [fit[1]])
    usable = dofs[:, 0] >= min_dof
    per_dof = np.full(X0.shape[0], np.nan)
    per_dof[usable] = residuals[usable, 0] / dofs[usable, 0]
    return per_dof


def merge_fragments(X0, mask, fragments, n_clusters, noise, *, max_dim=8, min_dof=4):
    """Greedy merge of fragments into ``n_clusters`` motions (see module doc).

    Parameters
    ----------
    X0, mask : ndarray of shape (n_samples, n_features)
        Tracks (zero where missing) and observed entries.
    fragments : ndarray of shape (n_samples,)
        Fragment labels, ``m`` distinct values.
    n_clusters : int
        Number of motions to keep (``<= m``).
    noise : float
        Noise variance per coordinate.
    max_dim : int, default=8
        Largest subspace dimension of a fragment.
    min_dof : int, default=4
        Tracks with fewer residual degrees of freedom are left out of a
        linkage.

    Returns
    -------
    labels : ndarray of shape (n_samples,), dtype=intp
        In ``0 .. n_clusters - 1``.

    Notes
    -----
    The residual per degree of freedom of every track to every fragment's
    subspace is kept (``n_samples x m`` floats), so that a merge refits one
    subspace and scores the tracks against it once: ``m`` fits and
    ``O(m n_samples)`` residuals in all; a group of more than
    ``MAX_GROUP_TRACKS`` tracks is fitted on, and links to the others by, that
    many of them, evenly spread. Of two equal linkages the pair
    ``(a, b)``, ``a < b``, that comes first in row-major order merges, into
    ``a``.
    """
    _, group_of = np.unique(fragments, return_inverse=True)
    group_of = group_of.astype(np.intp)
    n_groups = int(group_of.max()) + 1
    members = [np.flatnonzero(group_of == g) for g in range(n_groups)]

    def spread(index):
        if index.size <= MAX_GROUP_TRACKS:
            return index
        return index[np.linspace(0, index.size - 1, MAX_GROUP_TRACKS).astype(np.intp)]

    def fit(index):
        index = spread(index)
        return fit_adaptive_subspace(X0[index], mask[index], noise, max_dim=max_dim)

    # per_dof[p, a]: residual per dof of track p to fragment a's subspace;
    # misfit[a, b]: median of per_dof[b's tracks, a], in units of the noise
    per_dof = np.empty((X0.shape[0], n_groups))
    misfit = np.empty((n_groups, n_groups))
    for a in range(n_groups):
        per_dof[:, a] = _residuals_per_dof(X0, mask, fit(members[a]), min_dof)
        misfit[a] = _group_medians(per_dof[:, a], group_of, n_groups) / noise
    alive = np.ones(n_groups, dtype=bool)
    # each unordered pair once, in row-major order
    first, second = np.triu_indices(n_groups, k=1)
    for _ in range(n_groups - n_clusters):
        pairs = np.flatnonzero(alive[first] & alive[second])
        # the smaller of the two directions
        linkage = np.minimum(
            misfit[first[pairs], second[pairs]], misfit[second[pairs], first[pairs]]
        )
        best = pairs[np.argmin(linkage)]
        a, b = first[best], second[best]
        members[a] = np.concatenate([members[a], members[b]])
        group_of[members[b]] = a
        alive[b] = False
        per_dof[:, a] = _residuals_per_dof(X0, mask, fit(members[a]), min_dof)
        misfit[a] = _group_medians(per_dof[:, a], group_of, n_groups) / noise
        mine = per_dof[spread(members[a])]
        misfit[:, a] = (
            _group_medians(
                mine.T.ravel(),
                np.repeat(np.arange(n_groups), mine.shape[0]),
                n_groups,
            )
            / noise
        )
    _, labels = np.unique(group_of, return_inverse=True)
    return labels.astype(np.intp)
