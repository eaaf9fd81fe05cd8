"""One linear subspace per cluster, and the distances of points to subspaces.

Every per-cluster fit of the library goes through :func:`fit_subspaces`, with
one rule for a cluster without members: it has no subspace (a basis with no
column), so every point is at sine distance 1 from it and none is assigned to
it by a nearest-subspace rule.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._rows import canonical_sign


def fit_subspace(points, subspace_dim, subspace_dim_tol):
    """Orthonormal basis of the linear subspace best fitting ``points``.

    Parameters
    ----------
    points : ndarray of shape (n_points, n_features)
        Unit vectors of one cluster.
    subspace_dim : int or "auto"
        Dimension ``d``, clipped to ``n_features - 1``; ``"auto"`` keeps the
        singular directions with ``s_l > subspace_dim_tol * s_1``, at least 1
        and at most ``n_features - 1``.
    subspace_dim_tol : float
        Relative singular-value threshold for ``"auto"``.

    Returns
    -------
    basis : ndarray of shape (n_features, d)
        Leading right singular vectors of ``points``.
    """
    return _fit_one(points, subspace_dim, subspace_dim_tol)[0]


def _fit_one(points, subspace_dim, subspace_dim_tol):
    """Basis of the best subspace, and the least singular direction."""
    n_features = points.shape[1]
    # eigen-decomposition of the K x K scatter: O(n_points K^2), no U factor
    eigvals, eigvecs = np.linalg.eigh(points.T @ points)
    values = np.sqrt(np.maximum(eigvals[::-1], 0.0))
    vt = eigvecs[:, ::-1].T
    if subspace_dim == "auto":
        dim = int(np.count_nonzero(values > subspace_dim_tol * values[0]))
        dim = min(max(dim, 1), n_features - 1)
    else:
        dim = min(subspace_dim, n_features - 1)
    return vt[:dim].T, vt[-1]


def fit_subspaces(points, labels, n_clusters, subspace_dim, subspace_dim_tol):
    """The subspace of each cluster, and its least singular direction.

    Parameters
    ----------
    points : ndarray of shape (n_points, n_features)
        Unit vectors.
    labels : ndarray of shape (n_points,)
        Cluster of each point, in ``0 .. n_clusters - 1``.
    n_clusters : int
        Number of clusters.
    subspace_dim, subspace_dim_tol
        See :func:`fit_subspace`.

    Returns
    -------
    bases : list of ndarray of shape (n_features, d_k)
        Orthonormal basis of each cluster's subspace; ``d_k = 0`` for a cluster
        without members.
    normals : ndarray of shape (n_clusters, n_features)
        The least singular direction of each cluster's points (its normal when
        the subspace is a hyperplane), signed so that its largest-magnitude
        entry is positive; zero for a cluster without members.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._subspaces import fit_subspaces
    >>> points = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    >>> bases, normals = fit_subspaces(points, np.array([0, 0, 1]), 3, 2, 0.05)
    >>> [basis.shape for basis in bases]
    [(3, 2), (3, 2), (3, 0)]
    >>> np.abs(normals[0])
    array([0., 0., 1.])
    """
    n_features = points.shape[1]
    bases, normals = [], np.zeros((n_clusters, n_features))
    for k in range(n_clusters):
        members = points[labels == k]
        if members.shape[0] == 0:
            bases.append(np.zeros((n_features, 0)))
            continue
        basis, normals[k] = _fit_one(members, subspace_dim, subspace_dim_tol)
        bases.append(basis)
    return bases, canonical_sign(normals)


def hyperplanes_from_normals(point_normals, labels, n_clusters):
    """Hyperplanes of the clusters from their points' normals (the paper).

    The normal of cluster ``k`` is the leading eigenvector of ``sum_i n_i
    n_i^T`` over the unit normals ``n_i`` of its points; its hyperplane is the
    orthogonal complement.

    Parameters
    ----------
    point_normals : ndarray of shape (n_points, n_features)
        Unit normal at each point.
    labels : ndarray of shape (n_points,)
        Cluster of each point.
    n_clusters : int
        Number of clusters.

    Returns
    -------
    bases : list of ndarray of shape (n_features, n_features - 1)
        Orthonormal basis of each hyperplane; no column for a cluster without
        members.
    normals : ndarray of shape (n_clusters, n_features)
        Unit normals, signed so that the largest-magnitude entry is positive;
        zero for a cluster without members.
    """
    n_features = point_normals.shape[1]
    normals = np.zeros((n_clusters, n_features))
    for k in range(n_clusters):
        members = point_normals[labels == k]
        if members.shape[0]:
            normals[k] = np.linalg.eigh(members.T @ members)[1][:, -1]
    normals = canonical_sign(normals)
    bases = [
        np.linalg.svd(normal[None, :], full_matrices=True)[2][1:].T
        if np.any(labels == k)
        else np.zeros((n_features, 0))
        for k, normal in enumerate(normals)
    ]
    return bases, normals


def sine_residuals(points, bases):
    """Squared sine distance ``1 - ||U_k^T x||^2`` of unit points to subspaces.

    Parameters
    ----------
    points : ndarray of shape (n_points, n_features)
        Unit vectors.
    bases : list of ndarray of shape (n_features, d_k)
        Orthonormal bases.

    Returns
    -------
    residuals : ndarray of shape (n_points, n_subspaces)
        In ``[0, 1]``; 1 for a basis with no column.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca.stages import (
    ...     unit_rows, fit_subspaces, sine_residuals)
    >>> rng = np.random.RandomState(0)
    >>> # two planes of R^3: z = 0 and x = 0
    >>> unit = unit_rows(np.vstack([rng.randn(20, 3) * [1, 1, 0],
    ...                             rng.randn(20, 3) * [0, 1, 1]]))
    >>> bases, _ = fit_subspaces(unit, np.repeat([0, 1], 20), 2, 2, 0.05)
    >>> sine_residuals(unit[[0, -1]], bases).round(3)
    array([[0.   , 0.951],
           [0.693, 0.   ]])
    """
    return np.column_stack(
        [np.maximum(1.0 - np.sum((points @ U) ** 2, axis=1), 0.0) for U in bases]
    )


def own_residuals(points, labels, bases):
    """Squared sine distance of each unit point to its own cluster's subspace.

    Parameters
    ----------
    points : ndarray of shape (n_points, n_features)
        Unit vectors.
    labels : ndarray of shape (n_points,)
        Cluster of each point, an index into ``bases``.
    bases : list of ndarray of shape (n_features, d_k)
        Orthonormal bases.

    Returns
    -------
    residuals : ndarray of shape (n_points,)
        ``sine_residuals(points, bases)[i, labels[i]]``.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._subspaces import own_residuals
    >>> points = np.array([[1.0, 0.0], [0.6, 0.8]])
    >>> bases = [np.array([[1.0], [0.0]]), np.array([[0.0], [1.0]])]
    >>> own_residuals(points, np.array([0, 0]), bases).round(2)
    array([0.  , 0.64])
    >>> own_residuals(points, np.array([1, 1]), bases).round(2)
    array([1.  , 0.36])
    """
    return sine_residuals(points, bases)[np.arange(points.shape[0]), labels]


def residual_energy(points, labels, bases):
    """Sum of the squared sine distances of unit points to their own subspace."""
    energy = 0.0
    for k, basis in enumerate(bases):
        members = points[labels == k]
        if members.shape[0]:
            energy += np.sum(sine_residuals(members, [basis]))
    return float(energy)
