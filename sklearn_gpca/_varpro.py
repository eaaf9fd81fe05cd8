"""Variable projection for low-rank fits with missing entries.

Damped Gauss-Newton (Levenberg-Marquardt) on the reduced problem in which the
per-trajectory coordinates are eliminated in closed form, as in Ruhe & Wedin
(1980), Okatani & Deguchi's Wiberg algorithm (2007) and the unified
variable-projection algorithm of Hong & Fitzgibbon (ICCV 2015) and Hong,
Zach & Fitzgibbon (CVPR 2017). Same calling convention as
:func:`sklearn_gpca._als.power_factorization`.
"""

# SPDX-License-Identifier: BSD-3-Clause

import itertools

import numpy as np
from scipy import linalg, sparse

from sklearn_gpca import _als
from sklearn_gpca._chunks import row_chunks
from sklearn_gpca._least_squares import _RIDGE

# Floats per temporary of shape (rows in a chunk, n_features, n_features) in
# the dense accumulation of J^T J: 2**22 float64 are 32 MiB, whatever the
# number of rows.
_CHUNK_FLOATS = 2**22
# Pairs of observed entries of a row per chunk in the sparse accumulation,
# and the most pairs whose indices are kept from one iteration to the next.
_CHUNK_PAIRS = 2**19
_CACHED_PAIRS = 2**22
# The sparse accumulation is used when the pairs of observed entries in a
# row are fewer than this fraction of all pairs of columns.
_SPARSE_DENSITY = 0.3

# Levenberg-Marquardt damping lambda * I, relative to the mean diagonal of
# J^T J, divided by 10 after a successful step and multiplied by 10 after a
# failed one, as in Hong & Fitzgibbon's DRW2P (whose absolute 1e-4 is nearly
# undamped Gauss-Newton on pixel data). The starting value makes little
# difference to where a start ends (4/10 on Dino_trimmed from 1e2 to 1e-12).
_LAMBDA_START = 1e-4
# Random starts raced for _RACE_STEPS accepted steps, the best one pursued;
# no race when max_iter < _RACE_MIN_ITER.
_RACE = 4
_RACE_STEPS = 20
_RACE_MIN_ITER = 100
_LAMBDA_MIN = 1e-15
_LAMBDA_MAX = 1e16


def power_factorization(X0, mask, n_components, *, max_iter, tol, random_state, log):
    """Rank-``n_components`` factorisation ``X ~ B A^T`` by variable projection.

    For a basis ``A`` of the feature space, the coordinates of every row are
    the least-squares solution over its observed entries, so the squared
    residual is a function ``f(A)`` of ``A`` alone (in fact of its span). It
    is minimised by Levenberg-Marquardt with the Ruhe-Wedin (RW2)
    approximation of the Jacobian of the reduced residual, steps restricted
    to the orthogonal complement of the gauge directions ``A K`` and ``A``
    re-orthonormalised (retracted) after every step: Hong & Fitzgibbon's
    DRW2P.

    From a random start the iteration ends in a poor local minimum more
    often than not on real tracks (about 6 starts in 10 on Dino_trimmed).
    Those starts are told apart early: after ``_RACE_STEPS`` accepted steps
    their residual is well above that of starts heading for the optimum. So
    ``_RACE`` random starts are run for that many steps and only the one with
    the lowest residual is pursued (when ``max_iter`` leaves room for it).

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
        Maximum number of Levenberg-Marquardt trials, accepted or not, of
        the returned start; each costs one evaluation of the residual, like
        one ALS iteration. The starts dropped after the race are not
        counted.
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
    layout = _Layout(mask, n_components)
    n_race = _RACE if max_iter >= _RACE_MIN_ITER else 1
    starts = []
    for k in range(n_race):
        V, _ = np.linalg.qr(random_state.standard_normal((n_features, n_components)))
        start = _Start(X0, mask, V, layout, tol, log)
        if n_race > 1:
            log(f"race, start {k + 1} of {n_race}")
            start.run(max_iter, max_accepted=_RACE_STEPS)
        starts.append(start)
    best = min(starts, key=lambda start: start.cost)
    if n_race > 1:
        log(f"race won by start {starts.index(best) + 1}")
    best.run(max_iter)
    return best.result()


class _Start:
    """Levenberg-Marquardt iterations from one starting basis."""

    def __init__(self, X0, mask, V, layout, tol, log):
        self.X0, self.mask, self.layout, self.tol, self.log = X0, mask, layout, tol, log
        self.V = V
        self.U, self.inv_gram, self.cost = _project(X0, mask, V)
        self.total = np.einsum("ij,ij->", X0, X0)
        self.damping = _LAMBDA_START
        self.system = None
        self.n_iter = 0
        self.done = False
        self.converged = False

    def run(self, max_iter, max_accepted=None):
        n_features, r = self.V.shape
        diagonal = np.arange(n_features * r)
        accepted = 0
        while not self.done and self.n_iter < max_iter:
            if max_accepted is not None and accepted >= max_accepted:
                return
            self.n_iter += 1
            V = self.V
            if self.system is None:
                hessian, self.gradient = self.layout.normal_equations(
                    self.X0, V, self.U, self.inv_gram
                )
                self.scale = max(
                    np.trace(hessian) / hessian.shape[0], np.finfo(float).tiny
                )
                # Projection constraint: J^T J vanishes on the gauge
                # directions V K; adding (V V^T) kron I makes the system
                # definite there and leaves the step orthogonal to them.
                hessian4 = hessian.reshape(n_features, r, n_features, r)
                hessian4 += self.scale * (
                    (V @ V.T)[:, None, :, None] * np.eye(r)[None, :, None, :]
                )
                self.system = hessian
            system = self.system.copy()
            system[diagonal, diagonal] += self.damping * self.scale
            step = _solve(system, self.gradient)
            if step is not None:
                step = step.reshape(n_features, r)
                step -= V @ (V.T @ step)  # round-off along span(V)
                V_new, _ = np.linalg.qr(V + step)
                U_new, inv_new, cost_new = _project(self.X0, self.mask, V_new)
            if step is not None and cost_new < self.cost:
                self.log(
                    f"iteration {self.n_iter}, squared residual {cost_new:.6g}, "
                    f"damping {self.damping:.1e}"
                )
                accepted += 1
                stalled = self.cost - cost_new <= self.tol * self.cost
                self.V, self.U = V_new, U_new
                self.inv_gram, self.cost = inv_new, cost_new
                self.system = None
                self.damping = max(self.damping / 10, _LAMBDA_MIN)
                if stalled or self.cost <= 1e-28 * self.total:
                    self.done = self.converged = True
            else:
                self.log(
                    f"iteration {self.n_iter}, step rejected, "
                    f"damping {self.damping:.1e}"
                )
                self.damping *= 10
                if self.damping > _LAMBDA_MAX:
                    # no descent direction left at machine precision: a
                    # stationary point
                    self.done = self.converged = True
        if not self.done:
            self.converged = self.cost <= 1e-28 * self.total

    def result(self):
        # X ~ U V^T = Q (V R^T)^T with U = Q R.
        B, R = np.linalg.qr(self.U)
        return B, self.V @ R.T, self.n_iter, self.converged


def _solve(system, gradient):
    try:
        factor = linalg.cho_factor(system, check_finite=False)
        step = linalg.cho_solve(factor, gradient.reshape(-1), check_finite=False)
    except (np.linalg.LinAlgError, ValueError):
        return None
    if not np.all(np.isfinite(step)):
        return None
    return step


def _project(X0, mask, V):
    """Coordinates of every row in the basis ``V``, the inverses of the
    per-row Gram matrices ``V^T diag(m_i) V`` and the squared residual."""
    r = V.shape[1]
    outer = (V.T[:, None, :] * V.T[None, :, :]).reshape(r * r, -1)
    gram = (mask @ outer.T).reshape(-1, r, r)
    ridge = _RIDGE * np.trace(gram, axis1=1, axis2=2) / r + np.finfo(float).tiny
    gram[:, np.arange(r), np.arange(r)] += ridge[:, None]
    inv_gram = np.linalg.inv(gram)
    U = np.einsum("ikl,il->ik", inv_gram, X0 @ V)
    residual = X0 - U @ V.T
    residual *= mask
    return U, inv_gram, np.einsum("ij,ij->", residual, residual)


class _Layout:
    """Accumulation of ``J^T J`` over the observed entries.

    Row ``i`` has residual ``e_i = P_i x_i`` with ``P_i`` the projector on
    the orthogonal complement of ``diag(m_i) V`` among its observed entries,
    ``P_i = diag(m_i) - diag(m_i) V G_i^{-1} V^T diag(m_i)``. Its Ruhe-Wedin
    (RW2) Jacobian with respect to ``V`` is ``-P_i (u_i^T kron I)``, so

    ``J^T J = sum_i (u_i u_i^T) kron P_i``, ``-J^T e = E^T U``.

    The identity part of ``P_i`` gives the block diagonal
    ``sum_i m_ij u_i u_i^T``; the other part is nonzero only for pairs
    ``(j, l)`` of columns both observed in row ``i``. With sparse masks
    (tracks seen in a few frames) these pairs are far fewer than
    ``n_samples * n_features**2`` and are summed as a sparse product.
    """

    def __init__(self, mask, r):
        self.mask = mask
        self.r = r
        n_samples, n_features = mask.shape
        counts = mask.sum(axis=1).astype(np.int64)
        pairs = counts * (counts + 1) // 2
        self.sparse = pairs.sum() < _SPARSE_DENSITY * n_samples * n_features**2 / 2
        self.chunks = []
        if self.sparse:
            bounds = [0]
            cumulative = np.cumsum(pairs)
            while bounds[-1] < n_samples:
                done = cumulative[bounds[-1] - 1] if bounds[-1] else 0
                stop = np.searchsorted(cumulative, done + _CHUNK_PAIRS, side="right")
                bounds.append(min(max(stop, bounds[-1] + 1), n_samples))
            self.chunks = [slice(a, b) for a, b in itertools.pairwise(bounds)]
            self.cache = {} if pairs.sum() <= _CACHED_PAIRS else None

    def _pairs(self, k):
        if self.cache is not None and k in self.cache:
            return self.cache[k]
        rows_slice = self.chunks[k]
        m = self.mask[rows_slice]
        n_features = m.shape[1]
        rows, cols = np.nonzero(m)
        counts = np.bincount(rows, minlength=m.shape[0])
        starts = np.concatenate(([0], np.cumsum(counts)[:-1]))
        # entry e pairs with the entries of its row at or after it
        later = (starts + counts)[rows] - np.arange(rows.size)
        first = np.repeat(np.arange(rows.size), later)
        offsets = np.arange(first.size) - np.repeat(np.cumsum(later) - later, later)
        second = first + offsets
        key = cols[first] * n_features + cols[second]
        product = sparse.coo_matrix(
            (np.arange(1.0, first.size + 1), (key, rows[first])),
            shape=(n_features * n_features, m.shape[0]),
        ).tocsr()
        # the CSR arrays hold the pairs in another order: find it once
        order = product.data.astype(np.intp) - 1
        result = (rows, cols, first[order], second[order], product)
        if self.cache is not None:
            self.cache[k] = result
        return result

    def normal_equations(self, X0, V, U, inv_gram):
        """``J^T J`` indexed by ``j * r + k`` for ``V[j, k]``, and ``-J^T e``."""
        n_samples, n_features = X0.shape
        r = self.r
        UU = (U[:, :, None] * U[:, None, :]).reshape(n_samples, r * r)
        if self.sparse:
            upper = np.zeros((n_features * n_features, r * r))
            for k, rows_slice in enumerate(self.chunks):
                rows, cols, first, second, product = self._pairs(k)
                rows = rows + rows_slice.start
                # K_i[j, l] = y_j^T G_i^{-1} y_l for the rows y_j of V observed
                # in row i, one value per pair (first, second) of entries
                Y = V[cols]
                Z = np.einsum("ea,eab->be", Y, inv_gram[rows])
                Y = Y.T.copy()
                data = Z[0][first] * Y[0][second]
                for a in range(1, r):
                    data += Z[a][first] * Y[a][second]
                product.data = -data
                upper += product @ UU[rows_slice]
            upper = upper.reshape(n_features, n_features, r * r)
            hessian4 = upper + upper.transpose(1, 0, 2)
            idx = np.arange(n_features)
            hessian4[idx, idx] -= upper[idx, idx]
        else:
            hessian4 = np.zeros((n_features, n_features, r * r))
            # each row holds an (n_features, n_features) block
            size = max(1, _CHUNK_FLOATS // (n_features * n_features))
            for rows in row_chunks(n_samples, size):
                m = self.mask[rows]
                VC = np.einsum("jk,ikl->ijl", V, inv_gram[rows])
                K = VC @ V.T
                K *= m[:, :, None]
                K *= m[:, None, :]
                hessian4 -= (K.reshape(K.shape[0], -1).T @ UU[rows]).reshape(
                    hessian4.shape
                )
        idx = np.arange(n_features)
        hessian4[idx, idx] += self.mask.T @ UU
        hessian = (
            hessian4.reshape(n_features, n_features, r, r)
            .transpose(0, 2, 1, 3)
            .reshape(n_features * r, n_features * r)
        )
        residual = X0 - U @ V.T
        residual *= self.mask
        gradient = residual.T @ U
        return hessian, gradient
