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


def fit_subspace(points, subspace_dim, rank_tol):
    """Orthonormal basis of the linear subspace best fitting ``points``.

    Parameters
    ----------
    points : ndarray of shape (n_points, n_features)
        Unit vectors of one cluster.
    subspace_dim : int or "auto"
        Dimension ``d``; ``"auto"`` keeps the singular directions with
        ``s_l > rank_tol * s_1``, at least 1 and at most ``n_features - 1``.
    rank_tol : float
        Relative singular-value threshold for ``"auto"``.

    Returns
    -------
    basis : ndarray of shape (n_features, d)
    """
    n_features = points.shape[1]
    # eigen-decomposition of the K x K scatter: O(n_points K^2), no U factor
    eigvals, eigvecs = np.linalg.eigh(points.T @ points)
    values = np.sqrt(np.maximum(eigvals[::-1], 0.0))
    vt = eigvecs[:, ::-1].T
    if subspace_dim == "auto":
        dim = int(np.count_nonzero(values > rank_tol * values[0])) if values.size else 1
        dim = min(max(dim, 1), n_features - 1)
    else:
        dim = min(subspace_dim, n_features - 1)
    return vt[:dim].T


def sine_residuals(points, bases):
    """Squared sine distance ``1 - ||U_k^T x||^2`` of unit points to subspaces.

    Returns
    -------
    residuals : ndarray of shape (n_points, n_subspaces)
    """
    return np.column_stack(
        [np.maximum(1.0 - np.sum((points @ U) ** 2, axis=1), 0.0) for U in bases]
    )


def smoothed_cost(residuals, scale, neighbor_labels, smoothing):
    """Cost of giving each point each label in smoothed K-subspaces.

    Parameters
    ----------
    residuals : ndarray of shape (n_points, n_subspaces)
        Squared sine distances of the points to the subspaces.
    scale : float
        Their typical size (the median over the points of the distance to
        their own subspace).
    neighbor_labels : ndarray of shape (n_points, n_local)
        Current labels of each point's neighbours.
    smoothing : float
        Weight of one disagreeing neighbour, in units of ``scale``.

    Returns
    -------
    cost : ndarray of shape (n_points, n_subspaces)
        ``residuals / scale + smoothing * #{neighbours with another label}``.
    """
    cost = residuals / max(scale, np.finfo(np.float64).tiny)
    if smoothing > 0:
        classes = np.arange(residuals.shape[1])
        agree = (neighbor_labels[:, :, None] == classes).sum(axis=1)
        cost = cost + smoothing * (neighbor_labels.shape[1] - agree)
    return cost


def refine_ksubspaces(
    points,
    labels,
    n_clusters,
    *,
    neighbors,
    smoothing,
    subspace_dim,
    rank_tol,
    max_iter,
    random_state,
):
    """Smoothed K-subspaces from initial labels.

    Parameters
    ----------
    points : ndarray of shape (n_points, n_features)
        Unit vectors.
    labels : ndarray of shape (n_points,)
        Initial labels in ``0 .. n_clusters - 1``.
    n_clusters : int
        Number of subspaces.
    neighbors : ndarray of shape (n_points, n_local)
        Neighbourhood of each point for the smoothing term.
    smoothing : float
        Weight ``lambda`` of one disagreeing neighbour, in units of the median
        squared sine distance of the points to their own subspace.
    subspace_dim : int or "auto"
        See :func:`fit_subspace`.
    rank_tol : float
        See :func:`fit_subspace`.
    max_iter : int
        Maximum number of fit/assign rounds.
    random_state : RandomState instance
        Reseeds a cluster that lost too many points to fit its subspace.

    Returns
    -------
    labels : ndarray of shape (n_points,), dtype=intp
    bases : list of ndarray of shape (n_features, d_k)
    n_iter : int
        Number of assignment rounds run.
    converged : bool
        Whether the labels stopped changing (or alternated between two
        labellings, a 2-cycle of the synchronous updates) before ``max_iter``.
    """
    labels = np.asarray(labels, dtype=np.intp).copy()
    n_points, n_features = points.shape
    classes = np.arange(n_clusters)
    converged = False
    previous = None
    n_iter = 0
    while n_iter < max_iter:
        n_iter += 1
        bases = []
        for k in classes:
            members = points[labels == k]
            if members.shape[0] < n_features - 1:
                members = points[random_state.choice(n_points, n_features - 1)]
            bases.append(fit_subspace(members, subspace_dim, rank_tol))
        residuals = sine_residuals(points, bases)
        scale = np.median(residuals[np.arange(n_points), labels])
        neighbor_labels = labels[neighbors] if smoothing > 0 else None
        cost = smoothed_cost(residuals, scale, neighbor_labels, smoothing)
        new_labels = np.argmin(cost, axis=1).astype(np.intp)
        # synchronous updates of the Potts term can settle into a 2-cycle
        if np.array_equal(new_labels, labels) or np.array_equal(new_labels, previous):
            converged = True
            break
        previous, labels = labels, new_labels
    return labels, bases, n_iter, converged
