"""Merge/split moves between the motions of a refined segmentation.

Beyond the paper (issue 17). The refinement (smoothed K-subspaces,
:mod:`sklearn_gpca._refine_observed`) only moves tracks one at a time, so it
keeps the two errors a start typically makes on tracker output: a motion cut
in two (both halves span the same subspace) while two other motions share one
label. A *move* fixes both at once: merge two labels ``a`` and ``b`` into
``a``, and give the freed label ``b`` to one half of a cluster ``c`` split in
two (``c = a`` re-partitions the union). Each cluster is split by the
fragments route restricted to its tracks (spectral fragments of the motion
affinity merged into two by subspace linkage,
:mod:`sklearn_gpca._fragments`). Every move is refined and judged by the
selection rule of :func:`sklearn_gpca.segment_motions`; the best move is kept
while the rule prefers it to the current segmentation -- with
``selection="consistency"``, only when it is also significantly better
(:func:`significantly_better`: a move's models can fit the tracks a little
better by chance, and the moves of a round are many).
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
from scipy import stats

from sklearn_gpca._fragments import (
    absorb_small_fragments,
    merge_fragments,
    over_segment,
)

#: One-sided level of :func:`significantly_better`, before the Bonferroni
#: correction over the moves compared in a round (the textbook 5 %; not tuned).
MOVE_LEVEL = 0.05


def significantly_better(current, move, *, misfit_cost, n_compared, level=MOVE_LEVEL):
    """Vuong's test: do the move's models explain the tracks better than chance?

    The two segmentations are non-nested models of the same tracks. Each
    track's cost is its term of the consistency rule (``log(1 + rho /
    noise)`` plus ``misfit_cost`` when another group's model fits it better,
    :func:`sklearn_gpca._model_consistency.model_consistency`); ``d_i`` is
    the move's cost of track ``i`` minus the current one, over the tracks
    tested in both. Vuong's statistic (Econometrica 1989) is ``z = sum d_i /
    (sqrt(n) sd(d))``, standard normal when the two fit equally well; the
    move is significantly better when ``z`` is below the lower
    ``level / n_compared`` quantile (Bonferroni over the moves compared).

    Parameters
    ----------
    current, move : ndarray of shape (n_tracks, 2)
        ``model_consistency(..., per_track=True)``'s per-track terms of the
        current segmentation and of the move (NaN: not tested).
    misfit_cost : float
        Cost of a track nearer another group's model.
    n_compared : int
        Moves compared with the current segmentation.
    level : float, default=MOVE_LEVEL

    Returns
    -------
    better : bool
    """
    both = np.isfinite(current).all(axis=1) & np.isfinite(move).all(axis=1)
    costs = [t[both, 0] + misfit_cost * t[both, 1] for t in (current, move)]
    d = costs[1] - costs[0]
    if d.size < 2:
        return False
    spread = float(np.std(d))
    if spread == 0.0:
        return bool(np.sum(d) < 0)
    z = float(np.sum(d)) / (np.sqrt(d.size) * spread)
    return z < stats.norm.ppf(level / max(n_compared, 1))


def split_in_two(X0, mask, affinity, noise, *, min_size, per_fragment, random_state):
    """Two halves of a group of tracks, from the fragments route.

    Parameters
    ----------
    X0, mask : ndarray of shape (n_members, n_features)
        The group's tracks (zero where missing) and observed entries.
    affinity : sparse matrix of shape (n_members, n_members)
        Motion affinity among the group's tracks.
    noise : float
        Noise variance per coordinate.
    min_size : int
        Fewest tracks per fragment (and per half).
    per_fragment : int
        Tracks per fragment aimed at by the over-segmentation.
    random_state : RandomState instance

    Returns
    -------
    halves : ndarray of shape (n_members,), dtype=intp, or None
        Labels 0 and 1; None when the group is too small to split or its
        fragments all join one.
    """
    n_members = X0.shape[0]
    if n_members < 2 * min_size:
        return None
    n_fragments = min(max(4, n_members // per_fragment), n_members - 1)
    fragments = over_segment(affinity, n_fragments, random_state=random_state)
    fragments = absorb_small_fragments(affinity, fragments, min_size)
    if fragments.max() + 1 < 2:
        return None
    if fragments.max() + 1 > 2:
        fragments = merge_fragments(X0, mask, fragments, 2, noise)
    return fragments


def cached_split(split):
    """``split`` remembered by member set: a cluster left alone by a move is
    split the same way in the next round."""
    cache = {}

    def cached(members):
        key = members.tobytes()
        if key not in cache:
            cache[key] = split(members)
        return cache[key]

    return cached


def merge_split_moves(labels, n_clusters, split):
    """Every merge of two labels combined with a split of one cluster.

    Parameters
    ----------
    labels : ndarray of shape (n_samples,)
        Current labels in ``0 .. n_clusters - 1``.
    n_clusters : int
    split : callable
        ``split(members)`` -> halves (0/1 per member) or None, for an index
        array of tracks (called once per move: cache it, see
        :func:`cached_split`).

    Returns
    -------
    moves : list of ndarray of shape (n_samples,)
        The distinct new labellings (none equal to ``labels``).
    """
    moves = []
    for a in range(n_clusters):
        for b in range(a + 1, n_clusters):
            merged = np.where(labels == b, a, labels)
            for c in range(n_clusters):
                if c == b:
                    continue
                members = np.flatnonzero(merged == c)
                halves = split(members)
                if halves is None:
                    continue
                new = merged.copy()
                new[members[halves == 1]] = b
                if not np.array_equal(new, labels):
                    moves.append(new)
    return moves


def merge_split_search(labels, n_clusters, *, split, refine, choose, max_rounds):
    """Apply the best merge/split move while the selection rule prefers it.

    Parameters
    ----------
    labels : ndarray of shape (n_samples,)
        A refined segmentation in ``0 .. n_clusters - 1``.
    n_clusters : int
    split : callable
        See :func:`merge_split_moves`.
    refine : callable
        ``refine(labels)`` -> list of refined labels (one or more refinements
        of the move).
    choose : callable
        ``choose(segmentations)`` -> index of the one the selection rule
        keeps; ``segmentations[0]`` is the current one (index 0 stops the
        search).
    max_rounds : int
        Most moves kept.

    Returns
    -------
    labels : ndarray of shape (n_samples,), dtype=intp
    n_moves : int
        Moves kept.
    """
    labels = np.asarray(labels, dtype=np.intp)
    split = cached_split(split)
    for n_moves in range(max_rounds):
        refined = [
            segmentation
            for move in merge_split_moves(labels, n_clusters, split)
            for segmentation in refine(move)
        ]
        if not refined:
            return labels, n_moves
        chosen = choose([labels, *refined])
        if chosen == 0:
            return labels, n_moves
        labels = refined[chosen - 1]
    return labels, max_rounds
