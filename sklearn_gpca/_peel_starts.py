"""Starts that peel the dominant motion off first (issue 17).

On a tracker's output the background holds 70-80 % of the tracks, and the
other routes of :func:`sklearn_gpca.segment_motions` tend to cut it in two
while two small objects share a label. A *peeled* start finds the background
first, as the largest consensus of fragments (the motion graph's spectral
over-segmentation, :mod:`sklearn_gpca._fragments`) that one ``dim``-D subspace
fits, then segments what is left into ``n_motions - 1`` motions by the
fragments' subspace linkage (:func:`sklearn_gpca._fragments.merge_fragments`):

1. every fragment's subspace is fitted on its tracks' observed entries, and
   ``misfit[g, h]`` is the median over the tracks of fragment ``g`` of their
   residual per degree of freedom to fragment ``h``'s subspace, in units of
   the noise variance;
2. from each of the ``n_seeds`` fragments with the largest consensus (the
   tracks of the fragments it fits below ``threshold``), the consensus is
   grown: one subspace fitted to the union, the fragments it fits below
   ``threshold`` kept, ``n_grow`` times (a RANSAC over fragments, scored by
   the tracks it explains);
3. the largest grown consensus is the background (label 0); the other
   fragments are merged into labels ``1 .. n_motions - 1``.

The threshold trades a background that swallows an object whose motion is
nearly in its subspace (large) against one that leaves its own far tracks
out (small); :func:`peel_candidates` returns one start per threshold and the
caller's refinement and selection choose.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._fragments import (
    _group_medians,
    _residuals_per_dof,
    merge_fragments,
)
from sklearn_gpca._observed_subspaces import fit_observed_subspace

#: Background consensus thresholds, in units of the noise variance per
#: coordinate (2, 4 and 8 times the noise; not tuned: the only values tried).
PEEL_THRESHOLDS = (2.0, 4.0, 8.0)
#: Seed fragments grown per threshold (the largest consensuses).
PEEL_SEEDS = 6
#: Rounds of refit-and-regrow of a consensus.
PEEL_GROW_ROUNDS = 3
#: Tracks with fewer residual degrees of freedom are left out of a misfit.
MIN_DOF = 4


def _check(X0, mask, fragments, n_motions, noise, threshold, dim):
    X0 = np.asarray(X0, dtype=np.float64)
    mask = np.asarray(mask, dtype=bool)
    fragments = np.asarray(fragments)
    if X0.ndim != 2 or mask.shape != X0.shape:
        raise ValueError(
            f"X0 and mask must be 2-D and of one shape, got {X0.shape} and "
            f"{mask.shape}."
        )
    if fragments.shape != (X0.shape[0],) or not np.issubdtype(
        fragments.dtype, np.integer
    ):
        raise ValueError(
            f"fragments must hold one integer label per track ({X0.shape[0]}), "
            f"got shape {fragments.shape} and dtype {fragments.dtype}."
        )
    if fragments.size and fragments.min() < 0:
        raise ValueError("fragments must be non-negative labels.")
    if int(n_motions) < 2:
        raise ValueError(f"n_motions must be at least 2, got {n_motions}.")
    if not (np.isfinite(noise) and noise > 0):
        raise ValueError(f"noise must be a positive variance, got {noise}.")
    if not (np.isfinite(threshold) and threshold > 0):
        raise ValueError(f"threshold must be positive, got {threshold}.")
    if int(dim) < 1:
        raise ValueError(f"dim must be at least 1, got {dim}.")
    _, fragments = np.unique(fragments, return_inverse=True)
    return X0, mask, fragments.astype(np.intp)


def fragment_misfits(X0, mask, fragments, noise, *, dim=4):
    """``misfit[g, h]``: median misfit of fragment ``g``'s tracks to ``h``.

    The residual per degree of freedom of a track to the ``dim``-D subspace
    fitted to fragment ``h`` on observed entries, in units of ``noise``
    (the noise variance per coordinate), median over the tracks of fragment
    ``g`` that have at least ``MIN_DOF`` degrees of freedom (``inf`` when
    none has).

    Parameters
    ----------
    X0, mask : ndarray of shape (n_samples, n_features)
        Tracks (zero where missing) and observed entries.
    fragments : ndarray of shape (n_samples,)
        Fragment labels ``0 .. m - 1``.
    noise : float
    dim : int, default=4

    Returns
    -------
    misfit : ndarray of shape (m, m)
    """
    n_groups = int(fragments.max()) + 1
    misfit = np.empty((n_groups, n_groups))
    for h in range(n_groups):
        members = np.flatnonzero(fragments == h)
        fit = fit_observed_subspace(X0[members], mask[members], dim)
        per_dof = _residuals_per_dof(X0, mask, fit, MIN_DOF)
        misfit[:, h] = _group_medians(per_dof, fragments, n_groups) / noise
    return misfit


def _grow(X0, mask, fragments, inliers, noise, threshold, dim, n_rounds):
    """Refit the consensus on its tracks and keep what it fits, ``n_rounds`` times."""
    n_groups = inliers.size
    for _ in range(n_rounds):
        members = np.flatnonzero(inliers[fragments])
        fit = fit_observed_subspace(X0[members], mask[members], dim)
        per_dof = _residuals_per_dof(X0, mask, fit, MIN_DOF)
        grown = _group_medians(per_dof, fragments, n_groups) / noise < threshold
        if not grown.any() or np.array_equal(grown, inliers):
            break
        inliers = grown
    return inliers


def peel_background(
    X0,
    mask,
    fragments,
    n_motions,
    noise,
    *,
    threshold,
    dim=4,
    n_seeds=PEEL_SEEDS,
    n_grow=PEEL_GROW_ROUNDS,
    misfit=None,
):
    """Labels with the largest fragment consensus as motion 0 (module doc).

    Parameters
    ----------
    X0 : ndarray of shape (n_samples, n_features)
        Tracks, zero where missing.
    mask : ndarray of shape (n_samples, n_features), dtype=bool
        Observed entries.
    fragments : ndarray of shape (n_samples,), dtype=int
        Over-segmentation of the tracks (non-negative labels).
    n_motions : int
        Number of motions, at least 2.
    noise : float
        Noise variance per coordinate, ``> 0``.
    threshold : float
        Largest median misfit of a fragment in the background, in units of
        ``noise``.
    dim : int, default=4
        Dimension of the background's subspace.
    n_seeds : int, default=PEEL_SEEDS
        Seed fragments grown.
    n_grow : int, default=PEEL_GROW_ROUNDS
        Refit-and-regrow rounds per seed.
    misfit : ndarray of shape (m, m), default=None
        :func:`fragment_misfits` of the same fragments, to share between
        thresholds; None computes it.

    Returns
    -------
    labels : ndarray of shape (n_samples,), dtype=intp, or None
        ``0`` the background, ``1 .. n_motions - 1`` the rest; None when
        every consensus leaves fewer than ``n_motions - 1`` fragments.
    """
    X0, mask, fragments = _check(X0, mask, fragments, n_motions, noise, threshold, dim)
    if misfit is None:
        misfit = fragment_misfits(X0, mask, fragments, noise, dim=dim)
    n_groups = misfit.shape[0]
    sizes = np.bincount(fragments, minlength=n_groups)
    fits = misfit < threshold
    consensus = fits.T.astype(np.float64) @ sizes
    best, best_size = None, -1
    for seed in np.argsort(-consensus, kind="stable")[:n_seeds]:
        inliers = fits[:, seed].copy()
        inliers[seed] = True
        inliers = _grow(X0, mask, fragments, inliers, noise, threshold, dim, n_grow)
        size = int(sizes[inliers].sum())
        if size > best_size and np.count_nonzero(~inliers) >= n_motions - 1:
            best, best_size = inliers, size
    if best is None:
        return None
    labels = np.zeros(fragments.size, dtype=np.intp)
    rest = np.flatnonzero(~best[fragments])
    if n_motions == 2:
        labels[rest] = 1
    else:
        labels[rest] = 1 + merge_fragments(
            X0[rest], mask[rest], fragments[rest], n_motions - 1, noise
        )
    return labels


def peel_candidates(X0, mask, fragments, n_motions, noise, *, dim=4):
    """One peeled start per threshold of ``PEEL_THRESHOLDS`` (module doc).

    Returns
    -------
    starts : list of (str, ndarray of shape (n_samples,))
        Name (``"peel <threshold>"``) and labels of every start found,
        duplicates dropped.
    """
    X0, mask, fragments = _check(
        X0, mask, fragments, n_motions, noise, PEEL_THRESHOLDS[0], dim
    )
    misfit = fragment_misfits(X0, mask, fragments, noise, dim=dim)
    starts = []
    for threshold in PEEL_THRESHOLDS:
        labels = peel_background(
            X0,
            mask,
            fragments,
            n_motions,
            noise,
            threshold=threshold,
            dim=dim,
            misfit=misfit,
        )
        if labels is not None and not any(np.array_equal(labels, s) for _, s in starts):
            starts.append((f"peel {threshold:g}", labels))
    return starts
