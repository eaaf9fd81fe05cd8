"""PowerFactorization: alternating least squares for low-rank fits with gaps.

Hartley & Schaffalitzky's PowerFactorization as described in section 2.1.2 of
Vidal & Hartley (CVPR 2004).
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._least_squares import fit_rows


def squared_residual(X0, mask, B, A, total):
    """Squared residual of ``X0 ~ B A^T`` over the observed entries.

    ``total`` is the squared norm of ``X0``. With complete data, ``B`` with
    orthonormal columns and ``A = X0^T B``, the residual is
    ``total - ||A||^2`` (Pythagoras), which avoids an n_samples x n_features
    temporary.
    """
    if mask is None:
        return max(total - np.einsum("ij,ij->", A, A), 0.0)
    residual = X0 - B @ A.T
    residual *= mask
    return np.einsum("ij,ij->", residual, residual)


def power_factorization(
    X0, mask, n_components, *, max_iter, tol, random_state, log, init=None
):
    """Rank-``n_components`` factorisation ``X ~ B A^T`` over observed entries.

    Minimises equation (8) of the paper by the PowerFactorization iteration:
    from a random ``A_0``, (1) solve for ``B`` given ``A``, (2) orthonormalise
    ``B``, (3) solve for ``A`` given ``B``. With complete data steps (1) and
    (3) are the matrix products ``X A`` and ``X^T B`` (the power method).

    Parameters
    ----------
    X0 : ndarray of shape (n_samples, n_features)
        Data, with missing entries set to zero.
    mask : ndarray of shape (n_samples, n_features) or None
        1.0 where observed, 0.0 where missing; None for complete data.
    n_components : int
    max_iter : int
    tol : float
        Stop when the squared residual decreases by less than ``tol`` times
        its value in one iteration.
    random_state : numpy.random.RandomState
    log : callable
        Called with a message per iteration (verbose output) or a no-op.
    init : ndarray of shape (n_features, n_components), default=None
        Starting ``A``; None draws a random orthonormal one.

    Returns
    -------
    B : ndarray of shape (n_samples, n_components)
        Orthonormal columns.
    A : ndarray of shape (n_features, n_components)
    n_iter : int
    converged : bool
    """
    n_features = X0.shape[1]
    if init is None:
        A, _ = np.linalg.qr(random_state.standard_normal((n_features, n_components)))
    else:
        A = init
    total = np.einsum("ij,ij->", X0, X0)
    previous = np.inf
    for n_iter in range(1, max_iter + 1):
        if mask is None:
            B = X0 @ A
        else:
            B = fit_rows(X0, mask, A.T)
        B, _ = np.linalg.qr(B)
        if mask is None:
            A = X0.T @ B
        else:
            A = fit_rows(X0.T, mask.T, B.T)
        current = squared_residual(X0, mask, B, A, total)
        log(f"iteration {n_iter}, squared residual {current:.6g}")
        stalled = n_iter > 1 and previous - current <= tol * previous
        if stalled or current <= 1e-28 * total:
            return B, A, n_iter, True
        previous = current
    return B, A, max_iter, False
