"""The anchored reassignment of GPCAClustering in the width of its input.

``GPCAClustering(segmentation_dim=k, input_subspace_dim=d)`` segments its
points in their ``k`` leading principal directions, where the polynomial of
degree ``n`` has few monomials, then gives every point one more chance in
the input's own width: a ``d``-dimensional subspace is fitted to each group
(:func:`~sklearn_gpca._full_space.fit_full_space`: on a subsample of at most
``MAX_FIT_SAMPLES`` points, refitted once without the points another group
fits better), and each point takes the group minimising

``rho_pk / s + ANCHOR * [k != l_p]``

with ``rho_pk`` its squared residual to subspace ``k`` per residual degree of
freedom, ``s`` the median of ``rho`` over the points' own groups and ``l_p``
its label in the segmentation space
(:func:`~sklearn_gpca._full_space.assign_full_space`). ``n`` subspaces of
dimension ``d`` span up to ``n d`` dimensions: projected to ``k < n d`` they
meet, and points near an intersection are ambiguous there while they need
not be in the wider input (the ``R^5`` projection of rigid motions, Vidal &
Hartley, CVPR 2004, section 2.1). The anchor keeps what the smoothed
segmentation got right: a point moves only when another subspace fits it
better by more than one typical misfit. Time ``O(P D d^2 n)`` for ``P``
points of width ``D``.
"""

# SPDX-License-Identifier: BSD-3-Clause

from sklearn_gpca._full_space import assign_full_space, fit_full_space
from sklearn_gpca._observed_subspaces import observed_entries

#: Cost of leaving the segmentation space's label, in typical misfits: the
#: default of :func:`~sklearn_gpca.stages.reassign_full_space` (chosen there
#: on the scaling draws, ``benchmarks/results/scaling_stages.md``).
ANCHOR = 1.0

#: Most points the subspaces are fitted to (a uniform random subsample).
MAX_FIT_SAMPLES = 20000


def fit_input_reassignment(X, labels, n_clusters, subspace_dim, random_state):
    """Subspaces of the groups in the input width, and the reassigned labels.

    Parameters
    ----------
    X : ndarray of shape (n_samples, n_features)
        Points in the input's width, NaN where missing (each point is then
        fitted on its observed entries).
    labels : ndarray of shape (n_samples,)
        Their segmentation, ``0 .. n_clusters - 1``.
    n_clusters : int
    subspace_dim : int
        Dimension of every subspace, less than ``n_features``.
    random_state : RandomState instance
        Seeds the subsample of the fit.

    Returns
    -------
    labels : ndarray of shape (n_samples,), dtype=intp
    bases : list of ndarray of shape (n_features, subspace_dim) or None
        None for a group too small to fit (it keeps its points).
    scale : float
        The typical misfit ``s``.
    typical : float
        The median residual degrees of freedom of a point.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._input_reassignment import fit_input_reassignment
    >>> rng = np.random.RandomState(0)
    >>> X = np.vstack([np.c_[rng.randn(50, 2), np.zeros((50, 2))],
    ...                np.c_[np.zeros((50, 2)), rng.randn(50, 2)]])
    >>> start = np.repeat([0, 1], 50)
    >>> start[:5] = 1  # five points of the first plane in the wrong group
    >>> labels, bases, scale, typical = fit_input_reassignment(X, start, 2, 2, rng)
    >>> bool(np.array_equal(labels, np.repeat([0, 1], 50)))
    True
    """
    X0, mask = observed_entries(X)
    bases, supports = fit_full_space(
        X0,
        mask,
        labels,
        n_clusters,
        subspace_dim,
        max_fit_samples=MAX_FIT_SAMPLES,
        random_state=random_state,
    )
    labels, scale, typical = assign_full_space(
        X0, mask, labels, bases, supports, anchor=ANCHOR
    )
    return labels, bases, scale, typical


def input_reassignment(X, labels, bases, scale, typical):
    """The labels of :func:`fit_input_reassignment` for new points.

    Parameters
    ----------
    X : ndarray of shape (n_samples, n_features)
        Points, NaN where missing.
    labels : ndarray of shape (n_samples,)
        Their labels in the segmentation space.
    bases : list of ndarray or None
        The fitted subspaces.
    scale, typical : float
        The typical misfit and evidence of the fit.

    Returns
    -------
    labels : ndarray of shape (n_samples,), dtype=intp
    """
    X0, mask = observed_entries(X)
    # a fitted basis is zero on the coordinates it is not determined on
    supports = [None if basis is None else basis.any(axis=1) for basis in bases]
    labels, *_ = assign_full_space(
        X0, mask, labels, bases, supports, anchor=ANCHOR, scale=scale, typical=typical
    )
    return labels
