"""The normal subspace at each point: step 3 of Algorithm 1 and two variants.

A point ``x`` on a subspace ``S`` of ``R^K`` has as normal subspace the
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


def local_normal_bases(points, neighbors, rank_tol):
    """Normal subspace of a hyperplane (or lower subspace) fitted at each point.

    Parameters
    ----------
    points : ndarray of shape (n_samples, n_features)
        Unit vectors.
    neighbors : ndarray of shape (n_samples, n_local)
        Neighbours of each point (from :func:`sign_invariant_neighbors`).
    rank_tol : float
        Relative threshold on singular values. With ``s_1 >= ... >= s_K`` the
        singular values of the ``(n_local + 1, K)`` matrix of the point and its
        neighbours, direction ``l >= 3`` is a normal direction when ``s_l <=
        rank_tol * s_2`` (``s_1`` is the radial direction of the patch, ``s_2``
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
    small = values <= rank_tol * reference
    small[:, : min(2, n_features - 1)] = False
    small[:, -1] = True
    codims = np.count_nonzero(small, axis=1).astype(np.intp)
    normals = vt[:, ::-1, :].transpose(0, 2, 1)  # columns: smallest first
    bases = np.where(np.arange(n_features) < codims[:, None, None], normals, 0.0)
    return bases, codims
