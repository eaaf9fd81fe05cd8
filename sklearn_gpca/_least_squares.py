"""Batched least-squares fits of rows against a basis, over observed entries.

Every small ``r x r`` system of the factorisation (one per row or per column)
is damped and solved here, and the floor below which a residual counts as an
exact fit is defined here too.
"""

# SPDX-License-Identifier: BSD-3-Clause

import functools

import numpy as np

from sklearn_gpca._chunks import row_chunks
from sklearn_gpca._rows import TINY

# Relative Tikhonov damping added to every small normal-equation system, so
# that a numerically singular system never raises ``LinAlgError`` deep inside
# a batched solve. It is far below the accuracy of any measurement. For a row
# observed in fewer entries than the basis has directions it picks the
# minimum-norm solution.
_RIDGE = 1e-12

# A squared residual below this fraction of the squared norm of the data is an
# exact fit (round-off): iterations stop there.
_EXACT_FIT = 1e-28


def fits_exactly(cost, total):
    """Whether the squared residual ``cost`` is round-off for data of squared
    norm ``total``."""
    return cost <= _EXACT_FIT * total


def damp(gram):
    """Add the relative ridge to the diagonal of each ``r x r`` matrix, in place."""
    r = gram.shape[-1]
    diagonal = np.arange(r)
    ridge = _RIDGE * np.trace(gram, axis1=-2, axis2=-1) / r + TINY
    gram[..., diagonal, diagonal] += ridge[..., None]
    return gram


def masked_residual(X0, mask, U, V):
    """Residual ``X0 - U V^T`` on the observed entries, zero on the missing ones.

    Parameters
    ----------
    X0 : ndarray of shape (n_rows, n_cols)
        Data with missing entries set to zero.
    mask : ndarray of shape (n_rows, n_cols) or None
        1.0 (or True) where observed; None when nothing is missing.
    U : ndarray of shape (n_rows, r)
    V : ndarray of shape (n_cols, r)

    Returns
    -------
    residual : ndarray of shape (n_rows, n_cols)

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._least_squares import masked_residual
    >>> X0 = np.array([[3.0, 0.0], [2.0, 5.0]])
    >>> mask = np.array([[1.0, 0.0], [1.0, 1.0]])
    >>> masked_residual(X0, mask, np.ones((2, 1)), np.array([[1.0], [-1.0]]))
    array([[2., 0.],
           [1., 6.]])
    """
    residual = X0 - U @ V.T
    if mask is not None:
        residual *= mask
    return residual


def row_grams(mask, basis):
    """Gram matrices ``basis diag(mask[i]) basis^T`` of every row, undamped.

    Parameters
    ----------
    mask : ndarray of shape (n_rows, n_cols)
        1.0 where observed, 0.0 where missing (or any weights).
    basis : ndarray of shape (r, n_cols)

    Returns
    -------
    gram : ndarray of shape (n_rows, r, r)
    """
    r = basis.shape[0]
    upper, lower = _upper_triangle(r)
    # one product per pair k <= l: the matrices are symmetric
    sums = mask @ (basis[upper] * basis[lower]).T
    gram = np.empty((mask.shape[0], r, r))
    gram[:, upper, lower] = sums
    gram[:, lower, upper] = sums
    return gram


@functools.cache
def _upper_triangle(r):
    """``np.triu_indices(r)``, computed once per ``r`` (it costs more than the
    small products it indexes)."""
    indices = np.triu_indices(r)
    for index in indices:
        index.flags.writeable = False
    return indices


def fit_rows(X0, mask, basis):
    """Least-squares coordinates of every row of ``X0`` in ``basis``.

    For each row ``i`` solve ``min_z sum_j mask[i, j] (X0[i, j] - z @ basis[:, j])**2``
    through its damped ``r x r`` normal equations, all rows in one batched
    solve (over chunks of rows, so that memory stays ``O(n_rows r^2)``).

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
    rhs = X0 @ basis.T
    if mask is None:
        gram = damp(basis @ basis.T)
        return np.linalg.solve(gram, rhs.T).T
    Z = np.empty_like(rhs)
    for rows in row_chunks(X0.shape[0]):
        gram = damp(row_grams(mask[rows], basis))
        Z[rows] = np.linalg.solve(gram, rhs[rows][..., None])[..., 0]
    return Z


def inverse_row_grams(mask, basis):
    """Inverses of the damped Gram matrices of :func:`row_grams`.

    Used where the same systems are solved for many right-hand sides.
    """
    return np.linalg.inv(damp(row_grams(mask, basis)))
