"""Two-view geometry, batched: fundamental matrices and homographies.

A rigid motion seen by a perspective (pinhole) camera in two frames relates
the images ``x`` and ``x'`` of each of its points (homogeneous, third
coordinate 1) by the epipolar constraint ``x'^T F x = 0`` with a fundamental
matrix ``F`` of rank 2; if the points also lie on a plane (or the motion is a
pure rotation), by a homography ``x' ~ H x`` (Hartley & Zisserman, *Multiple
View Geometry*, 2nd ed., chapters 4, 9 and 11). Both are estimated here by
the normalised direct linear transform on many small samples at once:

- every sample is translated and scaled so that its points have centroid 0
  and mean distance ``sqrt(2)`` from it, in each view (Hartley's
  normalisation, HZ algorithm 4.2), which makes the linear system well
  conditioned;
- ``F`` is the right singular vector of the ``m x 9`` system ``x'^T F x = 0``
  (the 8-point algorithm, HZ algorithm 11.1), projected to rank 2;
- ``H`` is the right singular vector of the ``2m x 9`` system ``x' x H x = 0``
  (HZ algorithm 4.2, two equations per point).

Residuals are Sampson distances, the first-order approximation of the
geometric (reprojection) error (HZ sections 4.2.6 and 11.4.3), in the units
of the input coordinates, for every hypothesis and every point pair at once:
time ``O(n_hypotheses * n_points)``, no Python loop over either.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._rows import TINY

#: Smallest number of point pairs each model is estimated from.
MIN_SAMPLE = {"fundamental": 8, "homography": 4}


def _homogeneous(points):
    return np.concatenate([points, np.ones((*points.shape[:-1], 1))], axis=-1)


def normalizing_transforms(points):
    """Hartley's similarity transforms of batches of 2-D points.

    Parameters
    ----------
    points : ndarray of shape (..., n_points, 2)
        Batches of points.

    Returns
    -------
    T : ndarray of shape (..., 3, 3)
        For each batch, the similarity ``T`` (translation and isotropic
        scale) such that the points ``T [x; 1]`` have centroid 0 and mean
        distance ``sqrt(2)`` to it. A batch of coincident points gets the
        scale 1.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._two_view import normalizing_transforms
    >>> normalizing_transforms(np.array([[0.0, 0.0], [2.0, 2.0]]))
    array([[ 1.,  0., -1.],
           [ 0.,  1., -1.],
           [ 0.,  0.,  1.]])
    """
    points = np.asarray(points, dtype=np.float64)
    centroid = points.mean(axis=-2)
    spread = np.linalg.norm(points - centroid[..., None, :], axis=-1).mean(axis=-1)
    scale = np.where(spread > 0, np.sqrt(2.0) / np.where(spread > 0, spread, 1), 1.0)
    T = np.zeros((*points.shape[:-2], 3, 3))
    T[..., 0, 0] = T[..., 1, 1] = scale
    T[..., :2, 2] = -scale[..., None] * centroid
    T[..., 2, 2] = 1.0
    return T


def _apply(T, points):
    """``T [x; 1]`` for batches of points (affine ``T``), shape (..., n, 2)."""
    return np.einsum("...ij,...nj->...ni", T[..., :2, :2], points) + T[..., None, :2, 2]


def _null_vectors(A):
    """Right singular vector of the smallest singular value of each ``A``."""
    # Vt of a (k, m, 9) batch with m < 9 needs full_matrices to reach row 9;
    # with m >= 9 the reduced SVD has all 9 rows and no (m, m) factor.
    _, _, vt = np.linalg.svd(A, full_matrices=A.shape[-2] < A.shape[-1])
    return vt[..., -1, :].reshape((*A.shape[:-2], 3, 3))


def _unit_frobenius(M):
    norms = np.linalg.norm(M, axis=(-2, -1), keepdims=True)
    return M / np.maximum(norms, TINY)


def fit_fundamental(points1, points2):
    """Normalised 8-point estimates of fundamental matrices, batched.

    Parameters
    ----------
    points1, points2 : ndarray of shape (n_hypotheses, n_points, 2)
        Corresponding points in the first and second view, ``n_points >= 8``
        per sample (8 is the minimal sample of the linear algorithm).

    Returns
    -------
    F : ndarray of shape (n_hypotheses, 3, 3)
        Rank-2 fundamental matrices with unit Frobenius norm, such that
        ``[x2; 1]^T F [x1; 1] ~ 0`` on the samples. Degenerate samples (fewer
        than 8 points in general position) give some matrix of the solution
        space; their hypotheses simply fit few points.

    Notes
    -----
    HZ algorithm 11.1: normalise each view (``x -> T x``), solve ``A f = 0``
    with rows ``kron(x2, x1)`` in the least-squares sense, replace the
    smallest singular value of ``F`` by 0 (closest rank-2 matrix in Frobenius
    norm), and denormalise ``F = T2^T F_n T1``.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._two_view import fit_fundamental, sampson_fundamental
    >>> rng = np.random.RandomState(0)
    >>> X = rng.uniform(-1, 1, (20, 3)) + [0, 0, 5]      # 3-D points
    >>> R = np.array([[0.99, -0.14, 0], [0.14, 0.99, 0], [0, 0, 1.0]])
    >>> x1 = X[:, :2] / X[:, 2:]
    >>> Y = X @ R.T + [0.3, 0.1, 0.2]
    >>> x2 = Y[:, :2] / Y[:, 2:]
    >>> F = fit_fundamental(x1[None], x2[None])
    >>> float(sampson_fundamental(F, x1, x2).max()) < 1e-12
    True
    """
    points1 = np.asarray(points1, dtype=np.float64)
    points2 = np.asarray(points2, dtype=np.float64)
    T1, T2 = normalizing_transforms(points1), normalizing_transforms(points2)
    h1 = _homogeneous(_apply(T1, points1))
    h2 = _homogeneous(_apply(T2, points2))
    A = (h2[..., :, None] * h1[..., None, :]).reshape((*h1.shape[:-1], 9))
    F = _null_vectors(A)
    u, s, vt = np.linalg.svd(F)
    s[..., 2] = 0.0
    F = np.einsum("...ij,...j,...jk->...ik", u, s, vt)
    F = np.einsum("...ji,...jk,...kl->...il", T2, F, T1)
    return _unit_frobenius(F)


def fit_homography(points1, points2):
    """Normalised DLT estimates of homographies ``x2 ~ H x1``, batched.

    Parameters
    ----------
    points1, points2 : ndarray of shape (n_hypotheses, n_points, 2)
        Corresponding points, ``n_points >= 4`` per sample (4 is minimal).

    Returns
    -------
    H : ndarray of shape (n_hypotheses, 3, 3)
        Homographies with unit Frobenius norm.

    Notes
    -----
    HZ algorithm 4.2: each normalised correspondence gives the two equations
    ``[0^T, -x1^T, y2 x1^T] h = 0`` and ``[x1^T, 0^T, -x2 x1^T] h = 0``
    (rows of ``x2 x (H x1) = 0``); ``h`` is the least-squares null vector,
    and ``H = T2^{-1} H_n T1``.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._two_view import fit_homography, sampson_homography
    >>> rng = np.random.RandomState(0)
    >>> H = np.array([[1.1, 0.1, 0.2], [-0.05, 0.9, 0.1], [0.02, 0.01, 1.0]])
    >>> x1 = rng.uniform(-1, 1, (10, 2))
    >>> y = np.c_[x1, np.ones(10)] @ H.T
    >>> x2 = y[:, :2] / y[:, 2:]
    >>> H_hat = fit_homography(x1[None], x2[None])
    >>> float(sampson_homography(H_hat, x1, x2).max()) < 1e-12
    True
    """
    points1 = np.asarray(points1, dtype=np.float64)
    points2 = np.asarray(points2, dtype=np.float64)
    T1, T2 = normalizing_transforms(points1), normalizing_transforms(points2)
    h1 = _homogeneous(_apply(T1, points1))
    n2 = _apply(T2, points2)
    zeros = np.zeros_like(h1)
    rows_y = np.concatenate([zeros, -h1, n2[..., 1:2] * h1], axis=-1)
    rows_x = np.concatenate([h1, zeros, -n2[..., 0:1] * h1], axis=-1)
    A = np.concatenate([rows_y, rows_x], axis=-2)
    H = _null_vectors(A)
    T2_inv = np.linalg.inv(T2)
    H = np.einsum("...ij,...jk,...kl->...il", T2_inv, H, T1)
    return _unit_frobenius(H)


def _transform_all(M, points):
    """``M[h] @ [x_n; 1]`` for every matrix and point: three (n, h) arrays.

    Written out rather than as a matrix product: an inner dimension of 3 is
    far below what a threaded BLAS call is worth.
    """
    x = points[:, :1]
    y = points[:, 1:2]
    return [M[:, i, 0] * x + M[:, i, 1] * y + M[:, i, 2] for i in range(3)]


def sampson_fundamental(F, points1, points2):
    """Sampson distance of every point pair to every fundamental matrix.

    Parameters
    ----------
    F : ndarray of shape (n_hypotheses, 3, 3)
        Fundamental matrices.
    points1, points2 : ndarray of shape (n_points, 2)
        Corresponding points in the two views.

    Returns
    -------
    distances : ndarray of shape (n_points, n_hypotheses)
        ``|x2^T F x1| / sqrt((F x1)_1^2 + (F x1)_2^2 + (F^T x2)_1^2 +
        (F^T x2)_2^2)`` (HZ equation 11.9, square root taken), the
        first-order distance in the units of the points; 0 exactly on the
        epipolar constraint.
    """
    points1 = np.asarray(points1, dtype=np.float64)
    points2 = np.asarray(points2, dtype=np.float64)
    Fx1 = _transform_all(F, points1)
    Ftx2 = _transform_all(np.swapaxes(F, 1, 2), points2)
    algebraic = Fx1[0] * points2[:, :1] + Fx1[1] * points2[:, 1:2] + Fx1[2]
    gradient = Fx1[0] ** 2 + Fx1[1] ** 2 + Ftx2[0] ** 2 + Ftx2[1] ** 2
    return np.abs(algebraic) / np.sqrt(np.maximum(gradient, TINY))


def sampson_homography(H, points1, points2):
    """Sampson distance of every point pair to every homography.

    Parameters
    ----------
    H : ndarray of shape (n_hypotheses, 3, 3)
        Homographies mapping the first view to the second.
    points1, points2 : ndarray of shape (n_points, 2)
        Corresponding points.

    Returns
    -------
    distances : ndarray of shape (n_points, n_hypotheses)
        ``sqrt(e^T (J J^T)^{-1} e)`` with ``e`` the two algebraic errors
        ``x2 (h3 . x1) - h1 . x1`` and ``y2 (h3 . x1) - h2 . x1`` and ``J``
        their Jacobian in ``(x1, y1, x2, y2)`` (HZ section 4.2.6): the
        first-order distance of the 4-vector ``(x1, x2)`` to the variety of
        ``H``, in the units of the points; 0 exactly on ``x2 ~ H x1``.
    """
    points2 = np.asarray(points2, dtype=np.float64)
    Hx1 = _transform_all(H, np.asarray(points1, dtype=np.float64))
    x2 = points2[:, None, 0]
    y2 = points2[:, None, 1]
    w = Hx1[2]
    e1 = x2 * w - Hx1[0]
    e2 = y2 * w - Hx1[1]
    # Jacobian rows: d e1 = (x2 h31 - h11, x2 h32 - h12, w, 0),
    #                d e2 = (y2 h31 - h21, y2 h32 - h22, 0, w).
    a1 = x2 * H[None, :, 2, 0] - H[None, :, 0, 0]
    b1 = x2 * H[None, :, 2, 1] - H[None, :, 0, 1]
    a2 = y2 * H[None, :, 2, 0] - H[None, :, 1, 0]
    b2 = y2 * H[None, :, 2, 1] - H[None, :, 1, 1]
    w2 = w**2
    g11 = a1**2 + b1**2 + w2
    g22 = a2**2 + b2**2 + w2
    g12 = a1 * a2 + b1 * b2
    det = np.maximum(g11 * g22 - g12**2, TINY)
    quadratic = (g22 * e1**2 - 2 * g12 * e1 * e2 + g11 * e2**2) / det
    return np.sqrt(np.maximum(quadratic, 0.0))
