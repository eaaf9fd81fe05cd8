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
    # one product per pair k <= l: the matrices are symmetric; one gather
    # then fills both triangles (faster than two scattered assignments)
    sums = mask @ (basis[upper] * basis[lower]).T
    return np.take(sums, _symmetric_index(r), axis=1).reshape(-1, r, r)


@functools.cache
def _upper_triangle(r):
    """``np.triu_indices(r)``, computed once per ``r`` (it costs more than the
    small products it indexes)."""
    indices = np.triu_indices(r)
    for index in indices:
        index.flags.writeable = False
    return indices


@functools.cache
def _symmetric_index(r):
    """Position in the upper triangle (:func:`_upper_triangle`) of every entry
    ``(k, l)`` of an ``r x r`` symmetric matrix, flattened."""
    upper, lower = _upper_triangle(r)
    index = np.empty((r, r), dtype=np.intp)
    index[upper, lower] = index[lower, upper] = np.arange(upper.size)
    index = index.ravel()
    index.flags.writeable = False
    return index


def _cholesky_factors(gram):
    """Lower Cholesky factors ``G = L L^T`` of ``r x r`` matrices, batched.

    Each entry is computed for all matrices at once, in the layout ``(r, r,
    n)`` (the matrices in the last, contiguous axis): a few dozen vector
    operations for ``r = 5`` instead of one LAPACK call per matrix.

    Returns
    -------
    L : ndarray of shape (r, r, n)
    ok : ndarray of shape (n,), dtype=bool
        False where a pivot is not positive in floating point (the matrix is
        not numerically positive definite): ``L`` is then meaningless.
    """
    r = gram.shape[-1]
    A = np.ascontiguousarray(np.moveaxis(gram, 0, -1))
    L = np.zeros_like(A)
    # a non-positive pivot gives NaN; ``ok`` flags those matrices
    with np.errstate(invalid="ignore", divide="ignore"):
        for j in range(r):
            pivot = A[j, j] - np.einsum("kp,kp->p", L[j, :j], L[j, :j])
            L[j, j] = np.sqrt(pivot)
            for i in range(j + 1, r):
                dot = np.einsum("kp,kp->p", L[i, :j], L[j, :j])
                L[i, j] = (A[i, j] - dot) / L[j, j]
    diagonal = L[np.arange(r), np.arange(r)]
    ok = np.all(np.isfinite(diagonal) & (diagonal > 0), axis=0)
    ok &= np.all(np.isfinite(L), axis=(0, 1))
    return L, ok


def _cholesky_inverses(gram):
    """Inverses of symmetric positive definite ``r x r`` matrices, batched.

    ``G^{-1} = L^{-T} L^{-1}`` from :func:`_cholesky_factors`, in chunks of
    rows; matrices that are not numerically positive definite (rank-deficient
    up to the ridge) are inverted by ``np.linalg.inv`` instead.
    """
    inverses = np.empty_like(gram)
    r = gram.shape[-1]
    for rows in row_chunks(gram.shape[0]):
        L, ok = _cholesky_factors(gram[rows])
        # M = L^{-1}, lower triangular, by forward substitution
        M = np.zeros_like(L)
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            for j in range(r):
                M[j, j] = 1.0 / L[j, j]
                for i in range(j + 1, r):
                    M[i, j] = -np.einsum("kp,kp->p", L[i, j:i], M[j:i, j]) / L[i, i]
            chunk = np.einsum("kip,kjp->pij", M, M)
        bad = ~ok | ~np.all(np.isfinite(chunk), axis=(1, 2))
        if bad.any():
            chunk[bad] = np.linalg.inv(gram[rows][bad])
        inverses[rows] = chunk
    return inverses


def _cholesky_solve(gram, rhs):
    """``np.linalg.solve(gram, rhs[..., None])[..., 0]`` for symmetric positive
    definite ``gram`` of shape ``(n, r, r)`` and ``rhs`` of shape ``(n, r)``:
    :func:`_cholesky_factors`, then forward and back substitution, all
    matrices at once; ``np.linalg.solve`` where the factor fails."""
    r = gram.shape[-1]
    L, ok = _cholesky_factors(gram)
    b = np.ascontiguousarray(rhs.T)
    w = np.empty_like(b)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        for i in range(r):  # L w = b
            w[i] = (b[i] - np.einsum("kp,kp->p", L[i, :i], w[:i])) / L[i, i]
        z = np.empty_like(b)
        for i in reversed(range(r)):  # L^T z = w
            z[i] = (w[i] - np.einsum("kp,kp->p", L[i + 1 :, i], z[i + 1 :])) / L[i, i]
    z = z.T.copy()
    bad = ~ok | ~np.all(np.isfinite(z), axis=1)
    if bad.any():
        z[bad] = np.linalg.solve(gram[bad], rhs[bad][..., None])[..., 0]
    return z


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
        Z[rows] = _cholesky_solve(damp(row_grams(mask[rows], basis)), rhs[rows])
    return Z


def inverse_row_grams(mask, basis):
    """Inverses of the damped Gram matrices of :func:`row_grams`.

    Used where the same systems are solved for many right-hand sides.
    """
    return _cholesky_inverses(damp(row_grams(mask, basis)))
