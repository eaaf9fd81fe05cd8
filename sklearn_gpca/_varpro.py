"""Variable projection for low-rank fits with missing entries, matrix-free.

Damped Gauss-Newton (Levenberg-Marquardt) on the reduced problem in which the
per-trajectory coordinates are eliminated in closed form, as in Ruhe & Wedin
(1980), Okatani & Deguchi's Wiberg algorithm (2007) and the unified
variable-projection algorithm of Hong & Fitzgibbon (ICCV 2015), with the
linear system of every step solved by preconditioned conjugate gradients on
the manifold of bases (as in Boumal & Absil's RTRMC, 2011), so that nothing
of size ``(n_features r)^2`` is formed. Same calling convention as
:func:`sklearn_gpca._als.als`.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
from scipy import linalg

from sklearn_gpca._als import als
from sklearn_gpca._gauss_newton import GaussNewtonMatrix, factorisation_flops
from sklearn_gpca._least_squares import (
    fits_exactly,
    inverse_row_grams,
    masked_residual,
    row_grams,
)

# Levenberg-Marquardt damping lambda * I, relative to the mean diagonal of
# J^T J, divided by 10 after a successful step and multiplied by 10 after a
# failed one, as in Hong & Fitzgibbon's DRW2P.
_LAMBDA_START = 1e-4
_LAMBDA_MIN = 1e-15
_LAMBDA_MAX = 1e16
# Gauss-Newton steps until an accepted, nearly undamped step lowers the cost by
# less than this fraction; Newton steps (exact Hessian) from then on, which
# converge quadratically where Gauss-Newton converges linearly (large
# residuals). Far from a minimum, or while the damping is still at work,
# Newton steps lead random starts to poorer minima more often (a switch at 1e-2
# without the damping condition halved the starts reaching the optimum of
# Dino_trimmed; these values were set on it and on make_tracks sequences).
_NEWTON_SWITCH = 1e-2
_NEWTON_DAMPING = 1e-10
# Conjugate gradients stop at this residual relative to the gradient, for
# Gauss-Newton and for Newton steps (inexact Newton: a small forcing term
# keeps the fast local convergence).
_FORCING = 1e-1
_NEWTON_FORCING = 1e-2
# At most this many unknowns (n_features * r) for the dense Gauss-Newton
# matrix (128 MiB), used as preconditioner once conjugate gradients cost more
# than assembling and factorising it.
_MAX_DENSE_UNKNOWNS = 2**12


def varpro(X0, mask, init, *, max_iter, tol, log):
    """Rank-r factorisation ``X ~ B A^T`` by variable projection.

    For a basis ``A`` of the feature space, the coordinates of every row are
    the least-squares solution over its observed entries, so the squared
    residual is a function ``f(A)`` of ``A`` alone (in fact of its span). It
    is minimised by Levenberg-Marquardt: Ruhe-Wedin (RW2) Gauss-Newton steps,
    then Newton steps once the decrease slows down, restricted to the
    orthogonal complement of the gauge directions ``A K``, with ``A``
    re-orthonormalised (retracted) after every step. Each step solves its
    linear system by preconditioned conjugate gradients whose products cost
    ``O(|observed| r)``; the preconditioner is the block diagonal of the
    Gauss-Newton matrix (``O(|observed| r^2 + n_features r^3)``), or the
    whole dense matrix when conjugate gradients turn out to cost more than
    its factorisation (few features and ill-conditioned problems).

    Parameters
    ----------
    X0 : ndarray of shape (n_samples, n_features)
        Data, with missing entries set to zero.
    mask : ndarray of shape (n_samples, n_features) or None
        1.0 where observed, 0.0 where missing; None for complete data, which
        is handed to the power method of :func:`sklearn_gpca._als.als` (the
        optimum is then the truncated SVD).
    init : ndarray of shape (n_features, r)
        Starting basis, orthonormal columns.
    max_iter : int
        Maximum number of Levenberg-Marquardt trials, accepted or not; each
        costs one evaluation of the residual, like one ALS iteration, plus
        the conjugate-gradient products.
    tol : float
        Stop when an accepted step decreases the squared residual by less
        than ``tol`` times its value, or when a nearly undamped step is
        predicted to.
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
    if mask is None:
        return als(X0, None, init, max_iter=max_iter, tol=tol, log=log)
    return VarPro(X0, mask, init, tol=tol, log=log).run(max_iter).result()


class _Projection:
    """Coordinates, inverse Gram matrices and residual of every row for ``V``."""

    def __init__(self, X0, mask, V):
        self.V = V
        self.inv_gram = inverse_row_grams(mask, V.T)
        self.U = _apply(self.inv_gram, X0 @ V)
        self.residual = masked_residual(X0, mask, self.U, V)
        self.cost = np.einsum("ij,ij->", self.residual, self.residual)


def _apply(matrices, vectors):
    """``matrices[i] @ vectors[i]`` for every row ``i``."""
    return np.matmul(matrices, vectors[:, :, None])[:, :, 0]


class VarPro:
    """Levenberg-Marquardt iterations from one starting basis.

    Resumable: :meth:`run` may be called again with a larger budget.
    """

    def __init__(self, X0, mask, V, *, tol, log):
        self.X0, self.mask, self.tol, self.log = X0, mask, tol, log
        self.total = np.einsum("ij,ij->", X0, X0)
        self.state = _Projection(X0, mask, V)
        self.damping = _LAMBDA_START
        self.newton = False
        self.dense = None  # GaussNewtonMatrix once the dense route is taken
        self.cg_flops = 0.0  # cost of the last conjugate-gradient solve
        self.linearisation = None
        self.n_iter = 0
        self.n_products = 0
        self._buffers = None  # two n_samples x n_features work arrays
        self.done = self.converged = False

    @property
    def cost(self):
        return self.state.cost

    def run(self, max_iter, max_accepted=None):
        """Iterate until convergence, ``max_iter`` trials in all or
        ``max_accepted`` more accepted steps."""
        accepted = 0
        while not self.done and self.n_iter < max_iter:
            if max_accepted is not None and accepted >= max_accepted:
                break
            self.n_iter += 1
            accepted += self._trial()
        if not self.done:
            self.converged = fits_exactly(self.cost, self.total)
        return self

    def result(self):
        # X ~ U V^T = Q (V R^T)^T with U = Q R.
        B, R = np.linalg.qr(self.state.U)
        return B, self.state.V @ R.T, self.n_iter, self.converged

    def _trial(self):
        """One damped step; returns whether it was accepted."""
        if self.linearisation is None:
            self.linearisation = self._linearise()
        step = self._step()
        candidate, predicted = None, np.inf
        if step is not None:
            V_new, _ = np.linalg.qr(self.state.V + step)
            candidate = _Projection(self.X0, self.mask, V_new)
            # decrease of the cost promised by the damped quadratic model
            gradient, _, scale, _ = self.linearisation
            predicted = np.vdot(gradient, step)
            predicted += self.damping * scale * np.vdot(step, step)
        # a nearly undamped step promising less than tol: converged
        promised_little = (
            self.damping <= _NEWTON_DAMPING and predicted <= self.tol * self.cost
        )
        if candidate is not None and candidate.cost < self.cost:
            decrease = self.cost - candidate.cost
            self.state, self.linearisation = candidate, None
            self.log(
                f"iteration {self.n_iter}, squared residual {self.cost:.6g}, "
                f"damping {self.damping:.1e}" + (", Newton" if self.newton else "")
            )
            self.damping = max(self.damping / 10, _LAMBDA_MIN)
            self.newton = self.newton or (
                decrease < _NEWTON_SWITCH * self.cost
                and self.damping <= _NEWTON_DAMPING
            )
            if (
                decrease <= self.tol * self.cost
                or promised_little
                or fits_exactly(self.cost, self.total)
            ):
                self.done = self.converged = True
            return True
        self.log(f"iteration {self.n_iter}, step rejected, damping {self.damping:.1e}")
        self.damping *= 10
        if promised_little or self.damping > _LAMBDA_MAX:
            # no descent direction left at the tolerance (or at machine
            # precision): a stationary point
            self.done = self.converged = True
        return False

    def _linearise(self):
        """Gradient, preconditioner blocks and damping scale at the current basis."""
        state, mask = self.state, self.mask
        V, U = state.V, state.U
        n_features, r = V.shape
        gradient = state.residual.T @ U  # minus half the gradient of the cost
        gradient -= V @ (V.T @ gradient)
        # block diagonal of J^T J without its rank-r corrections: the column
        # Gram matrices sum_i m_ij u_i u_i^T of alternating least squares
        blocks = row_grams(mask.T, U.T)
        scale = np.trace(blocks, axis1=1, axis2=2).sum() / (n_features * r)
        scale = max(scale, np.finfo(float).tiny)
        hessian = None
        if (
            self.dense is None
            and n_features * r <= _MAX_DENSE_UNKNOWNS
            and self.cg_flops > factorisation_flops(mask, r)
        ):
            self.log("conjugate gradients cost more than the dense system")
            self.dense = GaussNewtonMatrix(mask, r)
        if self.dense is not None:
            hessian = self.dense.assemble(V, U, state.inv_gram)
            # gauge directions V K: J^T J vanishes there; (V V^T) kron I makes
            # the matrix definite without changing it on the tangent space
            hessian.reshape(n_features, r, n_features, r)[...] += scale * (
                (V @ V.T)[:, None, :, None] * np.eye(r)[None, :, None, :]
            )
        return gradient, blocks, scale, hessian

    def _step(self):
        """Damped (Gauss-)Newton step by preconditioned conjugate gradients."""
        gradient, blocks, scale, hessian = self.linearisation
        V = self.state.V
        n_features, r = V.shape
        shift = self.damping * scale
        if hessian is not None:
            system = hessian.copy()
            system[np.diag_indices_from(system)] += shift
            try:
                factor = linalg.cho_factor(system, check_finite=False)
            except (np.linalg.LinAlgError, ValueError):
                return None

            def precondition(residual):
                z = linalg.cho_solve(factor, residual.ravel(), check_finite=False)
                return _tangent(V, z.reshape(n_features, r))

        else:
            damped = blocks.copy()
            damped[:, np.arange(r), np.arange(r)] += shift
            inverse = np.linalg.inv(damped)

            def precondition(residual):
                return _tangent(V, _apply(inverse, residual))

        products = self.n_products
        newton = self.newton
        if newton:
            step, negative = self._solve(gradient, shift, precondition, newton=True)
            newton = not negative  # negative curvature: a Gauss-Newton step
        if not newton and hessian is not None:
            step = precondition(gradient)  # the damped Gauss-Newton matrix: exact
        elif not newton:
            step, _ = self._solve(gradient, shift, precondition, newton=False)
        matvec = (12 if newton else 8) * self.mask.size * r
        self.cg_flops = (self.n_products - products) * matvec
        if step is None or not np.all(np.isfinite(step)):
            return None
        return _tangent(V, step)

    def _solve(self, gradient, shift, precondition, *, newton):
        n_features, r = gradient.shape
        return _conjugate_gradients(
            lambda D: self._product(D, shift, newton),
            gradient,
            precondition,
            rtol=_NEWTON_FORCING if newton else _FORCING,
            max_iter=n_features * r,
        )

    def _product(self, D, shift, newton):
        """``(H + shift I) D`` for a tangent ``D``, with ``H`` the Gauss-Newton
        matrix ``J^T J`` or, if ``newton``, the Hessian of half the cost.

        With ``T = M o (U D^T)`` and ``C`` the change of the coordinates,
        ``C_i = G_i^{-1} (V^T T_i - [Newton] D^T e_i)`` up to sign, the change
        of the residual is ``-(T + M o (C V^T))``; the Newton Hessian adds the
        term ``-E^T C`` from the change of ``U`` in the gradient ``E^T U``.
        """
        self.n_products += 1
        state, mask = self.state, self.mask
        U, V = state.U, state.V
        if self._buffers is None:
            self._buffers = np.empty_like(mask), np.empty_like(mask)
        T, W = self._buffers
        np.matmul(U, D.T, out=T)
        T *= mask
        C = -(T @ V)
        if newton:
            C += state.residual @ D
        C = _apply(state.inv_gram, C)
        T += np.matmul(C, V.T, out=W)
        T *= mask
        product = T.T @ U
        if newton:
            product -= state.residual.T @ C
        product += shift * D
        return _tangent(V, product)


def _tangent(V, D):
    """``D`` projected on the tangent space at ``V``: ``V^T D = 0``."""
    return D - V @ (V.T @ D)


def _conjugate_gradients(operator, rhs, precondition, *, rtol, max_iter):
    """Preconditioned conjugate gradients for ``operator(x) = rhs``.

    Stops when the residual is below ``rtol`` times ``rhs``, or at the first
    direction of non-positive curvature (Steihaug). Returns the iterate and
    whether that happened at the very first direction (no step at all).
    """
    x = np.zeros_like(rhs)
    norm = np.linalg.norm(rhs)
    if norm == 0:
        return x, False
    residual = rhs.copy()
    z = precondition(residual)
    direction = z.copy()
    rz = np.vdot(residual, z)
    for k in range(max_iter):
        product = operator(direction)
        curvature = np.vdot(direction, product)
        if curvature <= 0:
            # the iterate so far is still a descent direction (Steihaug)
            return x, k == 0
        alpha = rz / curvature
        x += alpha * direction
        residual -= alpha * product
        if np.linalg.norm(residual) <= rtol * norm:
            break
        z = precondition(residual)
        rz_new = np.vdot(residual, z)
        direction = z + (rz_new / rz) * direction
        rz = rz_new
    return x, False
