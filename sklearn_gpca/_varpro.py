"""Variable projection for low-rank fits with missing entries.

Damped Gauss-Newton (Levenberg-Marquardt) on the reduced problem in which the
per-trajectory coordinates are eliminated in closed form, as in Ruhe & Wedin
(1980), Okatani & Deguchi's Wiberg algorithm (2007) and the unified
variable-projection algorithm of Hong & Fitzgibbon (ICCV 2015) and Hong,
Zach & Fitzgibbon (CVPR 2017). Same calling convention as
:func:`sklearn_gpca._als.power_factorization`.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca import _als
from sklearn_gpca._least_squares import _RIDGE, fit_rows

# Floats per temporary of shape (rows in a chunk, n_features, n_features):
# 2**22 float64 are 32 MiB, whatever the number of rows.
_CHUNK_FLOATS = 2**22

# Levenberg-Marquardt damping, relative to the mean diagonal of J^T J.
# It starts large, so that the first steps from a random start are short
# gradient steps rather than wild Gauss-Newton jumps.
_LAMBDA_START = 1e2
_LAMBDA_MIN = 1e-15
_LAMBDA_MAX = 1e16


def power_factorization(X0, mask, n_components, *, max_iter, tol, random_state, log):
    """Rank-``n_components`` factorisation ``X ~ B A^T`` by variable projection.

    For a basis ``A`` of the feature space, the coordinates of every row are
    the least-squares solution over its observed entries, so the squared
    residual is a function ``f(A)`` of ``A`` alone (in fact of its span). It
    is minimised by Levenberg-Marquardt with the Ruhe-Wedin / Wiberg
    approximation of the Jacobian of the reduced residual, steps restricted
    to the orthogonal complement of the gauge directions ``A K`` and ``A``
    re-orthonormalised (retracted) after every step.

    Parameters
    ----------
    X0 : ndarray of shape (n_samples, n_features)
        Data, with missing entries set to zero.
    mask : ndarray of shape (n_samples, n_features) or None
        1.0 where observed, 0.0 where missing; None for complete data, which
        is handed to the power method of :mod:`sklearn_gpca._als` (the
        optimum is then the truncated SVD and there is nothing to gain).
    n_components : int
    max_iter : int
        Maximum number of Levenberg-Marquardt trials, accepted or not; each
        costs one evaluation of the residual, like one ALS iteration.
    tol : float
        Stop when an accepted step decreases the squared residual by less
        than ``tol`` times its value.
    random_state : numpy.random.RandomState
    log : callable
        Called with a message per iteration (verbose output) or a no-op.

    Returns
    -------
    B : ndarray of shape (n_samples, n_components)
        Orthonormal columns.
    A : ndarray of shape (n_features, n_components)
    n_iter : int
    converged : bool
    """
    if mask is None:
        return _als.power_factorization(
            X0,
            mask,
            n_components,
            max_iter=max_iter,
            tol=tol,
            random_state=random_state,
            log=log,
        )
    n_features = X0.shape[1]
    V, _ = np.linalg.qr(random_state.standard_normal((n_features, n_components)))
    total = np.einsum("ij,ij->", X0, X0)
    U, cost = _project(X0, mask, V)
    converged = False
    damping = None
    hessian = None
    n_iter = 0
    for n_iter in range(1, max_iter + 1):
        if hessian is None:
            hessian, gradient = _normal_equations(X0, mask, V, U)
            scale = max(np.trace(hessian) / hessian.shape[0], np.finfo(float).tiny)
            if damping is None:
                damping = _LAMBDA_START
        step = _damped_step(hessian, gradient, V, damping * scale)
        if step is not None:
            V_new, _ = np.linalg.qr(V + step)
            U_new, cost_new = _project(X0, mask, V_new)
        if step is not None and cost_new < cost:
            log(
                f"iteration {n_iter}, squared residual {cost_new:.6g}, "
                f"damping {damping:.1e}"
            )
            stalled = cost - cost_new <= tol * cost
            V, U, cost = V_new, U_new, cost_new
            hessian = None
            damping = max(damping / 10, _LAMBDA_MIN)
            if stalled or cost <= 1e-28 * total:
                converged = True
                break
        else:
            log(f"iteration {n_iter}, step rejected, damping {damping:.1e}")
            damping *= 10
            if damping > _LAMBDA_MAX:
                # No descent direction left at machine precision: a
                # stationary point.
                converged = True
                break
    else:
        converged = cost <= 1e-28 * total

    # X ~ U V^T = Q (V R^T)^T with U = Q R.
    B, R = np.linalg.qr(U)
    return B, V @ R.T, n_iter, converged


def _project(X0, mask, V):
    """Coordinates of every row in the basis ``V`` and the squared residual."""
    U = fit_rows(X0, mask, V.T)
    return U, _als.squared_residual(X0, mask, U, V, None)


def _chunks(n_samples, n_features):
    size = max(1, _CHUNK_FLOATS // (n_features * n_features))
    for start in range(0, n_samples, size):
        yield slice(start, min(start + size, n_samples))


def _normal_equations(X0, mask, V, U):
    """Gauss-Newton matrix ``J^T J`` and ``-J^T e`` of the reduced residual.

    Row ``i`` has residual ``e_i = P_i x_i`` with ``P_i`` the projector on
    the orthogonal complement of ``diag(m_i) V`` among its observed entries,
    ``P_i = diag(m_i) - diag(m_i) V G_i^{-1} V^T diag(m_i)`` and
    ``G_i = V^T diag(m_i) V``. Its Ruhe-Wedin (Wiberg) Jacobian with respect
    to ``V`` is ``-P_i (u_i^T kron I)``, so

    ``J^T J = sum_i (u_i u_i^T) kron P_i``, ``-J^T e = E^T U``,

    the latter being minus the exact gradient of ``f / 2``. Both are sums over
    rows, accumulated over chunks of rows: the Jacobian itself, with one row
    per observed entry, is never formed.

    Returns
    -------
    hessian : ndarray of shape (n_features * n_components,) * 2
        Indexed by ``j * n_components + k`` for ``V[j, k]``.
    gradient : ndarray of shape (n_features, n_components)
    """
    n_samples, n_features = X0.shape
    r = V.shape[1]
    UU = (U[:, :, None] * U[:, None, :]).reshape(n_samples, r * r)
    # hessian4[j, l, k, m] = sum_i P_i[j, l] u_ik u_im
    hessian4 = np.zeros((n_features, n_features, r * r))
    outer = (V.T[:, None, :] * V.T[None, :, :]).reshape(r * r, n_features)
    for rows in _chunks(n_samples, n_features):
        m = mask[rows]
        gram = (m @ outer.T).reshape(-1, r, r)
        damping = _RIDGE * np.trace(gram, axis1=1, axis2=2) / r + np.finfo(float).tiny
        gram[:, np.arange(r), np.arange(r)] += damping[:, None]
        # V G_i^{-1}, shape (chunk, n_features, r)
        VC = np.linalg.solve(gram, np.broadcast_to(V.T, (gram.shape[0], r, n_features)))
        VC = VC.transpose(0, 2, 1)
        K = VC @ V.T
        K *= m[:, :, None]
        K *= m[:, None, :]
        hessian4 -= (K.reshape(K.shape[0], -1).T @ UU[rows]).reshape(hessian4.shape)
    diagonal = mask.T @ UU  # sum_i m_ij u_ik u_im, shape (n_features, r * r)
    idx = np.arange(n_features)
    hessian4[idx, idx] += diagonal
    hessian = (
        hessian4.reshape(n_features, n_features, r, r)
        .transpose(0, 2, 1, 3)
        .reshape(n_features * r, n_features * r)
    )
    residual = X0 - U @ V.T
    residual *= mask
    gradient = residual.T @ U
    return hessian, gradient


def _damped_step(hessian, gradient, V, damping):
    """Levenberg-Marquardt step, orthogonal to the gauge directions ``V K``.

    The reduced residual depends on ``V`` only through its span, so
    ``J^T J`` vanishes on ``{V K}``; adding the projector ``(V V^T) kron I``
    onto those directions (Hong & Fitzgibbon's projection constraint) makes
    the system definite there and the step has no component along them.
    Returns None if the system cannot be solved.
    """
    n_features, r = V.shape
    scale = np.trace(hessian) / hessian.shape[0]
    system = hessian + damping * np.eye(n_features * r)
    gauge = np.kron(V @ V.T, np.eye(r))
    system += max(scale, np.finfo(float).tiny) * gauge
    try:
        step = np.linalg.solve(system, gradient.reshape(-1))
    except np.linalg.LinAlgError:
        return None
    if not np.all(np.isfinite(step)):
        return None
    step = step.reshape(n_features, r)
    # remove any round-off component along span(V)
    return step - V @ (V.T @ step)
