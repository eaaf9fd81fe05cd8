"""Batched least-squares fits of rows against a basis, over observed entries."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._chunks import row_chunks

# Relative Tikhonov damping added to every small normal-equation system, so
# that a numerically singular system never raises ``LinAlgError`` deep inside
# a batched solve. It is far below the accuracy of any measurement.
_RIDGE = 1e-12


def fit_rows(X0, mask, basis):
    """Least-squares coordinates of every row of ``X0`` in ``basis``.

    For each row ``i`` solve ``min_z sum_j mask[i, j] (X0[i, j] - z @ basis[:, j])**2``
    through its ``r x r`` normal equations, all rows in one batched solve.

    Parameters
    ----------
    X0 : ndarray of shape (n_rows, n_cols)
        Data with missing entries set to zero.
    mask : ndarray of shape (n_rows, n_cols) or None
        1.0 where observed, 0.0 where missing; None when nothing is missing.
    basis : ndarray of shape (r, n_cols)
        Rows span the fitted subspace.

    Returns
    -------
    Z : ndarray of shape (n_rows, r)
    """
    r, n_cols = basis.shape
    rhs = X0 @ basis.T
    if mask is None:
        gram = basis @ basis.T
        gram = gram + _RIDGE * np.trace(gram) / r * np.eye(r)
        return np.linalg.solve(gram, rhs.T).T
    # gram[i] = sum_j mask[i, j] basis[:, j] basis[:, j]^T, for all i at once,
    # over chunks of rows so that memory stays O(n_rows r)
    outer = (basis[:, None, :] * basis[None, :, :]).reshape(r * r, n_cols)
    Z = np.empty_like(rhs)
    for rows in row_chunks(X0.shape[0]):
        gram = (mask[rows] @ outer.T).reshape(-1, r, r)
        damping = _RIDGE * np.trace(gram, axis1=1, axis2=2) / r + np.finfo(float).tiny
        gram[:, np.arange(r), np.arange(r)] += damping[:, None]
        Z[rows] = np.linalg.solve(gram, rhs[rows][..., None])[..., 0]
    return Z
