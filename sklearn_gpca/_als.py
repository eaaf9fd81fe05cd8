"""PowerFactorization: alternating least squares for low-rank fits with gaps.

Hartley & Schaffalitzky's PowerFactorization as described in section 2.1.2 of
Vidal & Hartley (CVPR 2004).
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._least_squares import fit_rows, fits_exactly, masked_residual


def silent(message):
    """The ``log`` of a solver run that reports nothing."""


def squared_residual(X0, mask, B, A, total):
    """Squared residual of ``X0 ~ B A^T`` over the observed entries.

    ``total`` is the squared norm of ``X0``. With complete data, ``B`` with
    orthonormal columns and ``A = X0^T B``, the residual is
    ``total - ||A||^2`` (Pythagoras), which avoids an n_samples x n_features
    temporary.
    """
    if mask is None:
        return max(total - np.einsum("ij,ij->", A, A), 0.0)
    residual = masked_residual(X0, mask, B, A)
    return np.einsum("ij,ij->", residual, residual)


def als(X0, mask, init, *, max_iter, tol, log):
    """Rank-r factorisation ``X ~ B A^T`` over observed entries, by ALS.

    Minimises equation (8) of the paper by the PowerFactorization iteration:
    from ``A = init``, (1) solve for ``B`` given ``A``, (2) orthonormalise
    ``B``, (3) solve for ``A`` given ``B``. With complete data steps (1) and
    (3) are the matrix products ``X A`` and ``X^T B`` (the power method). One
    iteration costs ``O(|observed| r^2 + (n_samples + n_features) r^3)``.

    Parameters
    ----------
    X0 : ndarray of shape (n_samples, n_features)
        Data, with missing entries set to zero.
    mask : ndarray of shape (n_samples, n_features) or None
        1.0 where observed, 0.0 where missing; None for complete data.
    init : ndarray of shape (n_features, r)
        Starting ``A``, orthonormal columns.
    max_iter : int
    tol : float
        Stop when the squared residual decreases by less than ``tol`` times
        its value in one iteration.
    log : callable
        Called with a message per iteration (verbose output) or a no-op.

    Returns
    -------
    B : ndarray of shape (n_samples, r)
        Orthonormal columns.
    A : ndarray of shape (n_features, r)
    n_iter : int
    converged : bool
    """
    return ALS(X0, mask, init, tol=tol, log=log).run(max_iter).result()


class ALS:
    """Alternating least squares from one starting basis, resumable.

    Same interface as :class:`sklearn_gpca._varpro.VarPro`: :meth:`run` with
    a budget of iterations (every iteration is an accepted step), ``cost``,
    ``done`` and :meth:`result`.
    """

    def __init__(self, X0, mask, init, *, tol, log):
        self.X0, self.mask, self.tol, self.log = X0, mask, tol, log
        self.total = np.einsum("ij,ij->", X0, X0)
        self.A, self.B = init, None
        self.cost = np.inf
        self.n_iter = 0
        self.done = self.converged = False

    def run(self, max_iter, max_accepted=None):
        """Iterate until convergence, ``max_iter`` iterations in all or
        ``max_accepted`` more."""
        stop = max_iter if max_accepted is None else self.n_iter + max_accepted
        X0, mask = self.X0, self.mask
        while not self.done and self.n_iter < min(max_iter, stop):
            self.n_iter += 1
            if mask is None:
                B = X0 @ self.A
            else:
                B = fit_rows(X0, mask, self.A.T)
            self.B, _ = np.linalg.qr(B)
            if mask is None:
                self.A = X0.T @ self.B
            else:
                self.A = fit_rows(X0.T, mask.T, self.B.T)
            previous = self.cost
            self.cost = squared_residual(X0, mask, self.B, self.A, self.total)
            self.log(f"iteration {self.n_iter}, squared residual {self.cost:.6g}")
            stalled = self.n_iter > 1 and previous - self.cost <= self.tol * previous
            if stalled or fits_exactly(self.cost, self.total):
                self.done = self.converged = True
        return self

    def result(self):
        return self.B, self.A, self.n_iter, self.converged
