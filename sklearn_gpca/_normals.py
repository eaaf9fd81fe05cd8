"""The normal subspace at each point: step 3 of Algorithm 1 and two variants.

A point ``x`` on a subspace ``S`` of :math:`R^K` has as normal subspace the
orthogonal complement of ``S``. Three estimators, chosen by
``GPCAClustering(point_normals=...)``:

- ``"one_polynomial"`` (the paper, section 2.2.3): the unit gradient of the
  fitted polynomial, one normal per point;
- ``"all_polynomials"`` (section 2.2.4): the span of the gradients of all the
  vanishing polynomials, for subspaces of lower dimension;
- ``"local"`` (beyond the paper): the least singular directions of the point
  and its nearest neighbours, with the local codimension estimated.

Each returns zero-padded orthonormal bases and their codimensions, the input
of the affinities in :mod:`sklearn_gpca._affinity`.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._polynomials import polynomial_normal_bases, unit_gradients

POINT_NORMALS = ("local", "one_polynomial", "all_polynomials")


def point_normal_bases(method, unit, *, points, polynomials, degree, neighbors, tol):
    """Normal subspace at each point, by one of the three estimators.

    Parameters
    ----------
    method : {"local", "one_polynomial", "all_polynomials"}
        The estimator (see the module docstring).
    unit : ndarray of shape (n_samples, n_features)
        The points scaled to unit norm.
    points : ndarray of shape (n_samples, n_features)
        The points the polynomials were fitted to (``unit`` when normalised);
        the gradient of ``"one_polynomial"`` is taken there, as in the paper.
    polynomials : ndarray of shape (n_polynomials, n_monomials)
        The vanishing polynomials (:func:`~sklearn_gpca._polynomials.
        vanishing_polynomials`), the first being the best-fitting one.
    degree : int
        Their degree.
    neighbors : ndarray of shape (n_samples, n_local) or None
        The neighbourhood of each point for ``"local"``.
    tol : float
        Relative singular-value threshold below which a direction counts as
        normal: against the widest tangent direction ``s_2`` of a
        neighbourhood (``"local"``, :func:`local_normal_bases`), against the
        strongest gradient ``s_1`` (``"all_polynomials"``,
        :func:`~sklearn_gpca._polynomials.polynomial_normal_bases`); unused by
        ``"one_polynomial"``.

    Returns
    -------
    bases : ndarray of shape (n_samples, n_features, n_columns)
        ``bases[i][:, l]`` for ``l < codims[i]`` is an orthonormal basis of the
        normal subspace at point ``i``, strongest (or only) normal first; the
        remaining columns are zero. ``n_columns`` is 1 for
        ``"one_polynomial"``, ``n_features`` otherwise.
    codims : ndarray of shape (n_samples,), dtype=intp
        The dimension of each normal subspace, ``>= 1``.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca.stages import (
    ...     unit_rows, sign_invariant_neighbors, point_normal_bases)
    >>> rng = np.random.RandomState(0)
    >>> # two planes of R^3: z = 0 and x = 0
    >>> unit = unit_rows(np.vstack([rng.randn(20, 3) * [1, 1, 0],
    ...                             rng.randn(20, 3) * [0, 1, 1]]))
    >>> neighbors = sign_invariant_neighbors(unit, 3)
    >>> bases, codims = point_normal_bases(
    ...     "local", unit, points=unit, polynomials=None, degree=2,
    ...     neighbors=neighbors, tol=0.05)
    >>> codims[[0, -1]], np.abs(bases[[0, -1], :, 0]).round(3)
    (array([1, 1]), array([[0., 0., 1.],
           [1., 0., 0.]]))
    """
    if method == "one_polynomial":
        normals = unit_gradients(points, polynomials[0], degree)
        return normals[:, :, None], np.ones(points.shape[0], dtype=np.intp)
    if method == "all_polynomials":
        return polynomial_normal_bases(unit, polynomials.T, degree, tol)
    return local_normal_bases(unit, neighbors, tol)


def local_normal_bases(points, neighbors, tol):
    """Normal subspace of a hyperplane (or lower subspace) fitted at each point.

    Parameters
    ----------
    points : ndarray of shape (n_samples, n_features)
        Unit vectors.
    neighbors : ndarray of shape (n_samples, n_local)
        Neighbours of each point (from :func:`sign_invariant_neighbors`).
    tol : float
        Relative threshold on singular values. With ``s_1 >= ... >= s_K`` the
        singular values of the ``(n_local + 1, K)`` matrix of the point and its
        neighbours, direction ``l >= 3`` is a normal direction when ``s_l <=
        tol * s_2`` (``s_1`` is the radial direction of the patch, ``s_2``
        its widest tangent direction); the last direction always is. Zero keeps
        exactly one normal (hyperplanes).

    Returns
    -------
    bases : ndarray of shape (n_samples, n_features, n_features)
        ``bases[i][:, l]`` for ``l < codims[i]`` is an orthonormal basis of the
        estimated normal subspace at point ``i``, smallest singular value
        first; the remaining columns are zero.
    codims : ndarray of shape (n_samples,), dtype=intp
        Estimated codimension of the local subspace, ``>= 1``.
    """
    n_features = points.shape[1]
    patches = np.concatenate([points[:, None, :], points[neighbors]], axis=1)
    _, values, vt = np.linalg.svd(patches, full_matrices=True)
    # vt rows sorted by decreasing singular value; pad missing values with 0
    values = np.pad(values, ((0, 0), (0, n_features - values.shape[1])))
    reference = values[:, min(1, n_features - 1)][:, None]
    small = values <= tol * reference
    small[:, : min(2, n_features - 1)] = False
    small[:, -1] = True
    codims = np.count_nonzero(small, axis=1).astype(np.intp)
    normals = vt[:, ::-1, :].transpose(0, 2, 1)  # columns: smallest first
    bases = np.where(np.arange(n_features) < codims[:, None, None], normals, 0.0)
    return bases, codims
