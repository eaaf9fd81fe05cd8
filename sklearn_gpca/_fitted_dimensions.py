"""The dimension each group of a segmentation needs, from its tracks' fit.

A rigid motion seen by an affine camera spans at most 4 dimensions of
``R^{2F}`` (Vidal & Hartley, CVPR 2004, section 2). A perspective camera
bends the trajectories of a scene with depth out of that subspace: over 100
frames a hand-held camera's background needs 5 to 7 dimensions
(``benchmarks/check_long_tracks.py``). Judged at a fixed dimension, such a
background misfits its subspace, and a segmentation that cuts it in two by
depth looks *more* separable than the true one.

:func:`group_dimensions` gives each group the smallest dimension that fits
its tracks to the noise level, capped so that it never absorbs another group:
a group's dimension stays below the dimension that the union of the group
with any other group needs. Without the cap, two nearly dependent motions (a
slowly moving camera and an object sliding slowly in front of it, the
``make_tracks`` "lab" scene) merged into one group fit one subspace of a
dimension or two more, and the merge is not seen.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._observed_subspaces import fit_observed_subspace, subspace_residuals

#: A group fits a subspace when its residual per degree of freedom is at most
#: this many times the noise variance (the coordinator's experiment, make_tracks
#: draws of the seven bench_segment settings, seeds 0-1; not tuned further).
FIT_FACTOR = 3.0
#: Dimensions tried above the rigid motions' (``subspace_dim``): 4 + 3 = 7.
EXTRA_DIMENSIONS = 3


def fitted_dimension(X0, mask, noise, dims, *, factor=FIT_FACTOR):
    """Smallest dimension in ``dims`` whose subspace fits the rows to the noise.

    Parameters
    ----------
    X0, mask : ndarray of shape (n_samples, n_features)
        Rows (zero where missing) and observed entries.
    noise : float
        Noise variance per coordinate, ``> 0``.
    dims : range
        Dimensions tried, increasing.
    factor : float, default=FIT_FACTOR
        Accepted residual per degree of freedom, in units of ``noise``.

    Returns
    -------
    dim : int
        The first ``d`` of ``dims`` with ``sum_p r_p <= factor * noise *
        sum_p dof_p`` (residuals on the observed entries); ``dims[-1] + 1``
        when none fits.
    """
    for dim in dims:
        basis, support = fit_observed_subspace(X0, mask, dim)
        residuals, dofs = subspace_residuals(X0, mask, [basis], [support])
        if residuals.sum() <= factor * noise * max(dofs.sum(), 1):
            return dim
    return dims[-1] + 1


def group_dimensions(X0, mask, labels, noise, *, min_dim, max_dim):
    """Dimension of each group: what it needs, below what any union needs.

    Group ``k`` needs ``d_k``, the smallest dimension in ``min_dim ..
    max_dim`` that fits it (:func:`fitted_dimension`; ``max_dim`` when none
    does). When the union of ``k`` with another group ``j`` fits a subspace
    of dimension ``d_kj <= d_k``, the dimensions of ``k`` above ``d_kj - 1``
    would hold ``j`` too, and ``k`` keeps ``max(d_kj - 1, min_dim)``.

    Parameters
    ----------
    X0, mask : ndarray of shape (n_samples, n_features)
        Tracks (zero where missing) and observed entries.
    labels : ndarray of shape (n_samples,)
        Non-negative group of each track.
    noise : float
        Noise variance per coordinate, ``> 0``.
    min_dim, max_dim : int
        Range of dimensions, ``1 <= min_dim <= max_dim``.

    Returns
    -------
    dims : ndarray of shape (n_groups,), dtype=intp
        One dimension per group, in the order of ``np.unique(labels)``.
    """
    if not 1 <= min_dim <= max_dim:
        raise ValueError(
            f"Need 1 <= min_dim <= max_dim, got min_dim={min_dim}, max_dim={max_dim}."
        )
    if not noise > 0:
        raise ValueError(f"noise must be > 0, got {noise}.")
    groups, index = np.unique(labels, return_inverse=True)
    needed = [
        fitted_dimension(
            X0[index == g], mask[index == g], noise, range(min_dim, max_dim + 1)
        )
        for g in range(groups.size)
    ]
    dims = np.minimum(needed, max_dim).astype(np.intp)
    for g in range(groups.size):
        for h in range(groups.size):
            if h == g or dims[g] <= min_dim:
                continue
            union = (index == g) | (index == h)
            joint = fitted_dimension(
                X0[union], mask[union], noise, range(min_dim, int(dims[g]) + 1)
            )
            if joint <= dims[g]:
                dims[g] = max(joint - 1, min_dim)
    return dims


def fitted_ambiguous_fraction(X0, mask, labels, noise, *, min_dim, max_dim):
    """:func:`ambiguous_fraction` with each group at its :func:`group_dimensions`.

    Parameters
    ----------
    X0, mask : ndarray of shape (n_samples, n_features)
        Tracks (zero where missing) and observed entries.
    labels : ndarray of shape (n_samples,)
        Non-negative group of each track; at least two groups.
    noise : float
        Noise variance per coordinate, ``> 0``.
    min_dim, max_dim : int
        Range of the groups' dimensions.

    Returns
    -------
    fraction : float
    """
    from sklearn_gpca._segment_selection import ambiguous_fraction

    dims = group_dimensions(X0, mask, labels, noise, min_dim=min_dim, max_dim=max_dim)
    return ambiguous_fraction(X0, mask, labels, noise, subspace_dim=dims)
