"""K-subspaces refinement with neighbourhood smoothing.

Alternates between fitting one linear subspace to each cluster (leading right
singular vectors) and reassigning every point to the subspace that minimises
its squared sine distance plus a Potts penalty for disagreeing with its nearest
neighbours (iterated conditional modes on the k-nearest-neighbour graph). With
zero smoothing this is plain K-subspaces (Bradley & Mangasarian 2000; Ho et al.
2003). Each iteration costs ``O(P K^2 n)``: linear in the number of points.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._rows import TINY
from sklearn_gpca._subspaces import fit_subspaces, own_residuals, sine_residuals


def smoothed_cost(residuals, scale, neighbor_labels, smoothing):
    """Cost of giving each point each label in smoothed K-subspaces.

    Parameters
    ----------
    residuals : ndarray of shape (n_points, n_subspaces)
        Squared sine distances of the points to the subspaces.
    scale : float
        Their typical size (the median over the points of the distance to
        their own subspace).
    neighbor_labels : ndarray of shape (n_points, n_local) or None
        Current labels of each point's neighbours; None without smoothing.
    smoothing : float
        Weight of one disagreeing neighbour, in units of ``scale``.

    Returns
    -------
    cost : ndarray of shape (n_points, n_subspaces)
        ``residuals / scale + smoothing * #{neighbours with another label}``.
    """
    cost = residuals / max(scale, TINY)
    if smoothing > 0:
        # one count per class: no (n_points, n_local, n_subspaces) temporary
        n_local = neighbor_labels.shape[1]
        for k in range(residuals.shape[1]):
            agree = np.count_nonzero(neighbor_labels == k, axis=1)
            cost[:, k] += smoothing * (n_local - agree)
    return cost


def smoothed_assignment(unit, bases, scale, neighbor_labels, smoothing):
    """Each point's label minimising the smoothed K-subspaces cost.

    Parameters
    ----------
    unit : ndarray of shape (n_points, n_features)
        Unit points to label.
    bases : list of ndarray of shape (n_features, d_k)
        The subspaces.
    scale : float
        Typical squared sine distance of a point to its own subspace.
    neighbor_labels : ndarray of shape (n_points, n_local) or None
        Labels of each point's neighbours; None without smoothing.
    smoothing : float
        Weight of one disagreeing neighbour, in units of ``scale``.

    Returns
    -------
    labels : ndarray of shape (n_points,), dtype=intp
    """
    residuals = sine_residuals(unit, bases)
    cost = smoothed_cost(residuals, scale, neighbor_labels, smoothing)
    return np.argmin(cost, axis=1).astype(np.intp)


def refill_small_clusters(
    points, labels, n_clusters, subspace_dim, subspace_dim_tol, *, clusters=None
):
    """Reseed every cluster too small to fit a hyperplane where the fit is worst.

    A cluster with fewer than ``n_features - 1`` points cannot determine a
    hyperplane, and one fitted to a few stray points attracts none: left alone,
    it ends empty. It is given instead the point worst fitted by its own
    cluster's subspace together with its nearest lines through the origin
    (largest ``|cos|``), ``2 (n_features - 1)`` points in all, taken from
    clusters large enough to spare them: a patch of the subspace that the
    current fit explains least (the relocation of emptied clusters of
    k-means, for subspaces). The cluster also takes every point that the
    subspace of this patch fits better than its own cluster's does.

    Parameters
    ----------
    points : ndarray of shape (n_points, n_features)
        Unit vectors.
    labels : ndarray of shape (n_points,)
        Labels in ``0 .. n_clusters - 1``.
    n_clusters : int
        Number of clusters.
    subspace_dim, subspace_dim_tol
        Dimension of the subspaces (see
        :func:`~sklearn_gpca._subspaces.fit_subspace`).
    clusters : iterable of int, default=None
        The clusters that may be reseeded; None means all.

    Returns
    -------
    labels : ndarray of shape (n_points,), dtype=intp
        The labels, reseeded where a cluster was too small and another could
        spare points.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._ksubspaces import refill_small_clusters
    >>> rng = np.random.RandomState(0)
    >>> X = np.vstack([np.c_[rng.randn(20, 2), np.zeros(20)],
    ...                np.c_[np.zeros(20), rng.randn(20, 2)]])
    >>> X /= np.linalg.norm(X, axis=1, keepdims=True)
    >>> labels = refill_small_clusters(X, np.zeros(40, dtype=int), 2, 2, 0.05)
    >>> labels.reshape(2, 20).std(axis=1)  # one plane each
    array([0., 0.])
    """
    min_size = points.shape[1] - 1
    seed_size = 2 * min_size
    if np.all(np.bincount(labels, minlength=n_clusters) >= min_size):
        return labels
    labels = np.array(labels, dtype=np.intp)
    for k in range(n_clusters) if clusters is None else clusters:
        counts = np.bincount(labels, minlength=n_clusters)
        donors = (counts >= min_size + seed_size)[labels]
        if counts[k] >= min_size or not np.any(donors):
            continue
        bases, _ = fit_subspaces(
            points, labels, n_clusters, subspace_dim, subspace_dim_tol
        )
        own = own_residuals(points, labels, bases)
        worst = np.argmax(np.where(donors, own, -np.inf))
        closeness = np.where(donors, np.abs(points @ points[worst]), -np.inf)
        seed = np.argsort(-closeness, kind="stable")[:seed_size]
        # the points the seed's subspace explains better than their own do
        basis, _ = fit_subspaces(
            points[seed],
            np.zeros(seed_size, np.intp),
            1,
            subspace_dim,
            subspace_dim_tol,
        )
        closer = donors & (sine_residuals(points, basis)[:, 0] < own)
        closer[seed] = True
        labels[closer] = k
    return labels


def k_subspaces(
    points,
    labels,
    n_clusters,
    *,
    neighbors=None,
    smoothing=5.0,
    subspace_dim=None,
    subspace_dim_tol=0.05,
    max_iter=50,
):
    """Smoothed K-subspaces from initial labels.

    Minimises, by iterated conditional modes, ``sum_i r_{i,l_i} / sigma^2 +
    smoothing * #{j in neighbors[i] : l_j != l_i}`` over the labels ``l``,
    with ``r_ik`` the squared sine distance of point ``i`` to the subspace
    fitted to cluster ``k`` and ``sigma^2`` the median of ``r_{i,l_i}``.

    Parameters
    ----------
    points : ndarray of shape (n_points, n_features)
        Unit vectors.
    labels : ndarray of shape (n_points,)
        Initial labels in ``0 .. n_clusters - 1``.
    n_clusters : int
        Number of subspaces.
    neighbors : ndarray of shape (n_points, n_local), default=None
        Neighbourhood of each point for the smoothing term; needed when
        ``smoothing > 0``.
    smoothing : float, default=5.0
        Weight ``lambda`` of one disagreeing neighbour, in units of the median
        squared sine distance of the points to their own subspace.
    subspace_dim : int, "auto" or None, default=None
        Dimension of the subspaces; None fits hyperplanes (``n_features - 1``).
        See :func:`sklearn_gpca._subspaces.fit_subspace`.
    subspace_dim_tol : float, default=0.05
        Relative singular-value threshold of ``subspace_dim="auto"``.
    max_iter : int, default=50
        Maximum number of fit/assign rounds. Before each round a cluster with
        too few points to fit a hyperplane is reseeded
        (:func:`refill_small_clusters`), once: a cluster that the assignments
        empty again has no subspace the points support, and stays empty.

    Returns
    -------
    labels : ndarray of shape (n_points,), dtype=intp
    bases : list of ndarray of shape (n_features, d_k)
        The subspaces the last labels were assigned to.
    n_iter : int
        Number of assignment rounds run.
    converged : bool
        Whether the labels stopped changing (or alternated between two
        labellings, a 2-cycle of the synchronous updates) before ``max_iter``.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._ksubspaces import k_subspaces
    >>> rng = np.random.RandomState(0)
    >>> X = np.vstack([np.c_[rng.randn(20, 2), np.zeros(20)],
    ...                np.c_[np.zeros(20), rng.randn(20, 2)]])
    >>> X /= np.linalg.norm(X, axis=1, keepdims=True)
    >>> start = np.r_[np.zeros(15), np.ones(25)].astype(int)
    >>> labels, bases, n_iter, converged = k_subspaces(X, start, 2, smoothing=0.0)
    >>> labels.reshape(2, 20).std(axis=1), converged
    (array([0., 0.]), True)
    """
    labels = np.asarray(labels, dtype=np.intp).copy()
    n_features = points.shape[1]
    fit = (n_clusters, n_features - 1 if subspace_dim is None else subspace_dim)
    fit += (subspace_dim_tol,)
    converged = False
    previous = None
    n_iter = 0
    reseedable = set(range(n_clusters))
    while n_iter < max_iter:
        n_iter += 1
        refilled = refill_small_clusters(points, labels, *fit, clusters=reseedable)
        reseedable -= set(np.unique(refilled[refilled != labels]).tolist())
        labels = refilled
        bases, _ = fit_subspaces(points, labels, *fit)
        # the residuals give both the scale and the assignment (as
        # own_residuals and smoothed_assignment would, computed once)
        residuals = sine_residuals(points, bases)
        scale = np.median(residuals[np.arange(labels.size), labels])
        neighbor_labels = labels[neighbors] if smoothing > 0 else None
        cost = smoothed_cost(residuals, scale, neighbor_labels, smoothing)
        new_labels = np.argmin(cost, axis=1).astype(np.intp)
        # synchronous updates of the Potts term can settle into a 2-cycle
        if np.array_equal(new_labels, labels) or np.array_equal(new_labels, previous):
            converged = True
            break
        previous, labels = labels, new_labels
    return labels, bases, n_iter, converged
