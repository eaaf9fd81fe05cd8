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
import scipy.sparse as sp
from sklearn.cluster import KMeans

from sklearn_gpca._observed_subspaces import (
    fit_adaptive_subspace,
    subspace_residuals,
)
from sklearn_gpca._spectral import leading_eigenvectors

_TINY = np.finfo(np.float64).tiny


# Up to this many tracks the spectral embedding uses a dense eigensolver
# (faster than Lanczos for the many eigenvectors of an over-segmentation).
_DENSE_EIGEN = 3000


def _leading_eigenvectors(affinity, n_components, random_state):
    """Leading eigenvectors of ``D^{-1/2} A D^{-1/2}``, dense when small."""
    n_samples = affinity.shape[0]
    if n_samples > _DENSE_EIGEN:
        return leading_eigenvectors(affinity, n_components, random_state)
    degrees = np.asarray(affinity.sum(axis=1)).ravel()
    inv_sqrt = 1.0 / np.sqrt(np.maximum(degrees, _TINY))
    normalized = (
        affinity.multiply(inv_sqrt[:, None]).multiply(inv_sqrt[None, :])
    ).toarray()
    _, vectors = np.linalg.eigh(normalized)
    vectors = vectors[:, ::-1][:, :n_components]
    vectors[degrees <= 0] = 0.0
    return vectors


def over_segment(affinity, n_fragments, *, random_state):
    """Spectral clustering of ``affinity`` into ``n_fragments`` clusters.

    Returns labels in ``0 .. n_fragments - 1`` (dtype intp).
    """
    n_samples = affinity.shape[0]
    n_fragments = min(n_fragments, n_samples - 1)
    vectors = _leading_eigenvectors(affinity, n_fragments, random_state)
    norms = np.linalg.norm(vectors, axis=1, keepdims=True)
    embedding = vectors / np.maximum(norms, _TINY)
    kmeans = KMeans(n_fragments, n_init=3, random_state=random_state)
    return kmeans.fit_predict(embedding).astype(np.intp)


def _between(affinity, labels, n_labels):
    n_samples = labels.shape[0]
    indicator = sp.csr_matrix(
        (np.ones(n_samples), (np.arange(n_samples), labels)),
        shape=(n_samples, n_labels),
    )
    return (indicator.T @ affinity @ indicator).toarray()


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
        weights = _between(affinity, fragments, sizes.size)
        np.fill_diagonal(weights, 0.0)
        g = small[np.argmin(sizes[small])]
        if weights[g].sum() > 0:
            target = int(np.argmax(weights[g]))
        else:
            target = int(np.argmax(np.where(np.arange(sizes.size) == g, -1, sizes)))
        fragments[fragments == g] = target
        _, fragments = np.unique(fragments, return_inverse=True)
        fragments = fragments.astype(np.intp)


def merge_fragments(X0, mask, fragments, n_clusters, noise, *, max_dim=8, min_dof=4):
    """Greedy merge of fragments into ``n_clusters`` motions (see module doc).

    Parameters
    ----------
    X0, mask : ndarray of shape (n_samples, n_features)
        Tracks (zero where missing) and observed entries.
    fragments : ndarray of shape (n_samples,)
        Fragment labels ``0 .. m - 1``.
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
    """
    groups = {g: np.flatnonzero(fragments == g) for g in np.unique(fragments)}

    def fit(index):
        return fit_adaptive_subspace(X0[index], mask[index], noise, max_dim=max_dim)

    fits = {g: fit(index) for g, index in groups.items()}

    def misfit(a, b):
        """Median residual per dof of b's tracks to a's subspace (noise units)."""
        index = groups[b]
        residuals, dofs = subspace_residuals(
            X0[index], mask[index], [fits[a][0]], [fits[a][1]]
        )
        usable = dofs[:, 0] >= min_dof
        if not usable.any():
            return np.inf
        return float(np.median(residuals[usable, 0] / dofs[usable, 0]) / noise)

    def linkage(a, b):
        return min(misfit(a, b), misfit(b, a))

    keys = sorted(groups)
    links = {(a, b): linkage(a, b) for i, a in enumerate(keys) for b in keys[i + 1 :]}
    while len(groups) > n_clusters:
        a, b = min(links, key=links.get)
        groups[a] = np.concatenate([groups[a], groups.pop(b)])
        fits.pop(b)
        fits[a] = fit(groups[a])
        links = {
            pair: v for pair, v in links.items() if a not in pair and b not in pair
        }
        for g in groups:
            if g != a:
                links[(min(a, g), max(a, g))] = linkage(a, g)
    labels = np.empty(fragments.shape[0], dtype=np.intp)
    for new, index in enumerate(groups.values()):
        labels[index] = new
    return labels
