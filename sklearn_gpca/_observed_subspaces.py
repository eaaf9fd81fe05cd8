"""Linear subspaces of the full trajectory space, fitted and scored on observed entries.

A rigid motion seen by an affine camera spans a linear subspace of dimension
at most 4 of ``R^{2F}`` (Vidal & Hartley, CVPR 2004, section 2). A tracker
sees each trajectory on some frames only, so every computation here uses the
observed entries of a row and nothing else:

- the residual of row ``p`` to a subspace with basis ``B`` (``D x d``) is
  ``min_z ||x_O - B_O z||^2`` over the coordinates ``O`` that ``p`` observes
  (and on which the subspace is determined), a ``d x d`` least-squares
  problem per row, all rows in one batched solve, in chunks: time
  ``O(P D d^2)``, memory ``O(chunk d^2)``;
- it leaves ``k_p - d`` residual degrees of freedom when ``p`` observes
  ``k_p > d`` coordinates; a row with ``k_p <= d`` fits every subspace
  exactly and carries no evidence about its motion;
- a subspace is fitted to a group of rows by alternating least squares on
  the observed entries (PowerFactorization, paper section 2.1.2, restricted to
  the group), started from the leading eigenvectors of the second-moment
  matrix estimated on co-observed pairs of coordinates.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._als import silent
from sklearn_gpca._chunks import row_chunks
from sklearn_gpca._least_squares import damp, masked_residual
from sklearn_gpca._rows import TINY
from sklearn_gpca._varpro import varpro

# Rows per chunk of the batched solves: their d x d temporaries stay small.
_CHUNK = 2**14
#: Most Levenberg-Marquardt steps of ``fit_observed_subspace(polish=True)``.
POLISH_ITERATIONS = 100


def observed_entries(X):
    """Zero-filled data and mask of observed entries.

    Parameters
    ----------
    X : ndarray of shape (n_samples, n_features)
        Data with NaN for missing entries.

    Returns
    -------
    X0 : ndarray of shape (n_samples, n_features), dtype=float64
        ``X`` with the missing entries set to 0.
    mask : ndarray of shape (n_samples, n_features), dtype=bool
        True where observed.
    """
    X = np.asarray(X, dtype=np.float64)
    mask = ~np.isnan(X)
    return np.where(mask, X, 0.0), mask


def _outer_columns(basis):
    """``(d * d, D)`` matrix whose column ``j`` is ``vec(b_j b_j^T)``.

    ``mask @ outer.T`` then gives every row's Gram matrix ``B_O^T B_O``.
    """
    d = basis.shape[1]
    return (basis.T[:, None, :] * basis.T[None, :, :]).reshape(d * d, -1)


def row_fits(X0, mask, basis, support=None):
    """Least-squares coordinates and residuals of every row in one subspace.

    Parameters
    ----------
    X0 : ndarray of shape (n_samples, n_features)
        Data, zero where missing.
    mask : ndarray of shape (n_samples, n_features), dtype=bool
        Observed entries.
    basis : ndarray of shape (n_features, d)
        Basis of the subspace (columns; orthonormal or not).
    support : ndarray of shape (n_features,), dtype=bool, default=None
        Coordinates on which the subspace is determined; the others are
        ignored. None uses all coordinates.

    Returns
    -------
    coefs : ndarray of shape (n_samples, d)
        ``argmin_z ||x_O - B_O z||^2`` over the observed coordinates ``O`` of
        each row (within ``support``).
    residuals : ndarray of shape (n_samples,)
        The minimum, ``>= 0``.
    counts : ndarray of shape (n_samples,), dtype=intp
        Number of coordinates ``k = |O|`` each row is fitted on.
    """
    return fitted_rows(masked_rows(X0, mask, support), basis)


def masked_rows(X0, mask, support=None):
    """The parts of :func:`row_fits` that do not depend on the basis.

    For fits of the same rows to many bases (the alternations of
    :func:`fit_observed_subspace`). It holds two float copies of the rows
    for as long as it is kept.

    Parameters
    ----------
    X0, mask, support
        As for :func:`row_fits`.

    Returns
    -------
    prepared : tuple
        ``(chunks, counts)``: per chunk of rows, its slice, the observed
        coordinates as floats, the rows zeroed off them and their squared
        norms; and each row's number of coordinates. For :func:`fitted_rows`.
    """
    weights = mask if support is None else mask & support
    chunks = []
    for rows in row_chunks(X0.shape[0], _CHUNK):
        w = weights[rows].astype(np.float64)
        x = X0[rows] * w
        chunks.append((rows, w, x, np.einsum("ij,ij->i", x, x)))
    return chunks, np.count_nonzero(weights, axis=1)


def fitted_rows(prepared, basis):
    """:func:`row_fits` of rows prepared by :func:`masked_rows`.

    Parameters
    ----------
    prepared : tuple
        What :func:`masked_rows` returns.
    basis : ndarray of shape (n_features, d)
        Basis of the subspace (columns; orthonormal or not).

    Returns
    -------
    coefs, residuals, counts
        As for :func:`row_fits`.
    """
    chunks, counts = prepared
    d = basis.shape[1]
    coefs = np.empty((counts.size, d))
    residuals = np.empty(counts.size)
    outer = _outer_columns(basis)
    for rows, w, x, squared in chunks:
        rhs = x @ basis
        gram = (w @ outer.T).reshape(-1, d, d)
        # damped, so that a row observing fewer coordinates than d never raises
        z = np.linalg.solve(damp(gram), rhs[..., None])[..., 0]
        coefs[rows] = z
        residuals[rows] = squared - np.einsum("ij,ij->i", rhs, z)
    return coefs, np.maximum(residuals, 0.0), counts


def subspace_residuals(X0, mask, bases, supports=None):
    """Residual of every row to every subspace, on the row's observed entries.

    Parameters
    ----------
    X0 : ndarray of shape (n_samples, n_features)
        Data, zero where missing.
    mask : ndarray of shape (n_samples, n_features), dtype=bool
        Observed entries.
    bases : sequence of ndarray of shape (n_features, d_k)
        One basis per subspace.
    supports : sequence of ndarray of shape (n_features,), dtype=bool, default=None
        Coordinates on which each subspace is determined (see
        :func:`fit_observed_subspace`); None: all.

    Returns
    -------
    residuals : ndarray of shape (n_samples, n_subspaces)
        Squared residuals ``min_z ||x_O - B_O z||^2``.
    dofs : ndarray of shape (n_samples, n_subspaces), dtype=intp
        Residual degrees of freedom ``max(k - d_k, 0)``, ``k`` the number of
        coordinates the row is fitted on. Zero means no evidence.
    """
    if supports is None:
        supports = [None] * len(bases)
    residuals = np.empty((X0.shape[0], len(bases)))
    dofs = np.empty((X0.shape[0], len(bases)), dtype=np.intp)
    for k, (basis, support) in enumerate(zip(bases, supports, strict=True)):
        _, residuals[:, k], counts = row_fits(X0, mask, basis, support)
        dofs[:, k] = np.maximum(counts - basis.shape[1], 0)
    return residuals, dofs


def comoment_matrix(X0, mask, weights=None):
    """Second-moment matrix of the rows, each entry over the rows observing both.

    ``C_ij = sum_p w_p x_pi x_pj / sum_p w_p m_pi m_pj`` (0 where no row
    observes both): an estimate of ``E[x x^T]`` that ignores missing entries
    instead of counting them as zeros. Its leading eigenvectors start
    :func:`fit_observed_subspace`.

    Returns
    -------
    moments : ndarray of shape (n_features, n_features)
    pair_counts : ndarray of shape (n_features, n_features)
        ``sum_p w_p m_pi m_pj``.
    """
    m = mask.astype(np.float64)
    if weights is not None:
        m = m * weights[:, None]
    pair_counts = m.T @ mask
    moments = (X0 * (m if weights is not None else 1.0)).T @ X0
    return moments / np.maximum(pair_counts, TINY), pair_counts


def fit_observed_subspace(
    X0, mask, dim, *, weights=None, init=None, max_iter=30, tol=1e-6, polish=False
):
    """Rank-``dim`` linear subspace best fitting rows with missing entries.

    Minimises ``sum_p w_p ||m_p * (x_p - B z_p)||^2`` over ``B`` (``D x dim``)
    and the coordinates ``z_p`` by alternating least squares (the
    PowerFactorization iteration of the paper, section 2.1.2, on this group of
    rows), from the leading eigenvectors of :func:`comoment_matrix` or from
    ``init``. With complete rows it is the truncated SVD (no iteration).

    Parameters
    ----------
    X0 : ndarray of shape (n_samples, n_features)
        Rows of the group, zero where missing.
    mask : ndarray of shape (n_samples, n_features), dtype=bool
        Observed entries.
    dim : int
        Dimension ``d >= 1``.
    weights : ndarray of shape (n_samples,), default=None
        Non-negative row weights; None weighs every row 1.
    init : ndarray of shape (n_features, dim), default=None
        Starting basis (e.g. the previous fit in K-subspaces).
    max_iter : int, default=30
        Maximum number of alternations.
    tol : float, default=1e-6
        Stop when the weighted residual decreases by less than this fraction.
    polish : bool, default=False
        Then minimise the same residual by variable projection
        (:func:`sklearn_gpca._varpro.varpro`, Levenberg-Marquardt on the
        basis alone, at most ``POLISH_ITERATIONS`` steps) from where the
        alternations stopped. With many entries missing, alternating least
        squares creeps: after 30 alternations the residual of 13 to 23 of the
        92 true motions of each ``make_tracks`` seed set was still more than
        1.5 times its least value, up to 15 times
        (``benchmarks/results/subspace_convergence.md``). For references such
        as :func:`sklearn_gpca.metrics.oracle_labels`; one to twenty times
        the time of the alternations (same page).

    Returns
    -------
    basis : ndarray of shape (n_features, dim)
        Orthonormal columns; zero rows outside ``support``.
    support : ndarray of shape (n_features,), dtype=bool
        Coordinates observed by at least ``dim`` rows of positive weight, on
        which the subspace is determined.
    """
    n_samples, n_features = X0.shape
    w = np.ones(n_samples) if weights is None else np.asarray(weights, float)
    active = w > 0
    X0, mask, w = X0[active], mask[active], w[active]
    support = np.count_nonzero(mask, axis=0) >= dim
    if X0.shape[0] == 0 or not support.any():
        return np.zeros((n_features, dim)), support
    sqrt_w = np.sqrt(w)[:, None]
    if mask[:, support].all():
        # complete on the support: truncated SVD of the weighted rows
        vt = np.linalg.svd(sqrt_w * X0[:, support], full_matrices=False)[2]
        basis = np.zeros((n_features, dim))
        found = vt[:dim].T
        basis[support, : found.shape[1]] = found
        return basis, support
    if init is None:
        moments, _ = comoment_matrix(X0[:, support], mask[:, support], w)
        _, vectors = np.linalg.eigh(moments)
        init = np.zeros((n_features, dim))
        # fewer coordinates in the support than dimensions: a partial basis
        found = vectors[:, ::-1][:, :dim]
        init[support, : found.shape[1]] = found
    basis = init * support[:, None]
    Xw, mw = X0[:, support], mask[:, support]
    # the same rows are fitted at every alternation: masked once
    by_row = masked_rows(Xw, mw)
    by_coordinate = masked_rows((Xw * sqrt_w).T, mw.T)
    previous = np.inf
    for _ in range(max_iter):
        coefs, residuals, _ = fitted_rows(by_row, basis[support])
        total = np.dot(w, residuals)
        # update the rows of B: coordinate j is fitted to the rows observing it
        weighted = coefs * sqrt_w
        rows_b, _, _ = fitted_rows(by_coordinate, weighted)
        q, _ = np.linalg.qr(rows_b)
        basis = np.zeros((n_features, dim))
        basis[support, : q.shape[1]] = q
        if previous < np.inf and previous - total <= tol * previous:
            break
        previous = total
    if polish and basis.shape[1] < support.sum():
        # row weights scale the rows: each row's coordinates are its own
        _, polished, _, _ = varpro(
            Xw * sqrt_w,
            mw.astype(np.float64),
            basis[support],
            max_iter=POLISH_ITERATIONS,
            tol=tol,
            log=silent,
        )
        basis = np.zeros((n_features, dim))
        basis[support, : polished.shape[1]] = np.linalg.qr(polished)[0]
    return basis, support


def _residual_direction(X0, mask, basis, support):
    """Leading eigenvector of the co-observed second moments of the residuals."""
    coefs, _, _ = row_fits(X0[:, support], mask[:, support], basis[support])
    residual = np.zeros_like(X0)
    residual[:, support] = masked_residual(
        X0[:, support], mask[:, support], coefs, basis[support]
    )
    moments, _ = comoment_matrix(residual, mask)
    _, vectors = np.linalg.eigh(moments)
    return vectors[:, -1]


def fit_adaptive_subspace(X0, mask, noise, *, max_dim=8, min_dim=1, tol=2.0):
    """Subspace of the smallest dimension that fits a group to the noise level.

    Dimensions ``d = min_dim, min_dim + 1, ...`` are fitted in turn (each
    alternating least squares started from the previous basis and the
    leading direction of its residuals) until the residual per degree of
    freedom, ``sum_p r_p / sum_p (k_p - d)``, is at most ``tol * noise``;
    ``max_dim`` otherwise. A rigid motion seen by an affine camera needs at
    most 4; a perspective camera bends the trajectories of a scene with
    depth out of that subspace, and more dimensions absorb the bend.

    Parameters
    ----------
    X0, mask : ndarray of shape (n_samples, n_features)
        Rows of the group (zero where missing) and observed entries.
    noise : float
        Variance of the noise per coordinate (e.g.
        :func:`local_noise_level`).
    max_dim, min_dim : int
        Range of dimensions.
    tol : float, default=2.0
        Accepted residual per degree of freedom, in units of ``noise``.

    Returns
    -------
    basis : ndarray of shape (n_features, d)
    support : ndarray of shape (n_features,), dtype=bool
    """
    support = np.count_nonzero(mask, axis=0) >= min_dim
    if support.any() and mask[:, support].all():
        # complete on the support: one SVD gives every dimension's residual
        _, values, vt = np.linalg.svd(X0[:, support], full_matrices=False)
        energy = np.sum(values**2) - np.cumsum(values**2)
        n_rows, n_cols = X0.shape[0], int(support.sum())
        dims = np.arange(1, values.size + 1)
        dofs = n_rows * np.maximum(n_cols - dims, 0)
        fits = energy <= tol * noise * np.maximum(dofs, 1)
        fits[: min_dim - 1] = False
        candidates = np.flatnonzero(fits[:max_dim])
        dim = int(dims[candidates[0]]) if candidates.size else min(max_dim, values.size)
        dim = max(dim, min_dim)
        basis = np.zeros((X0.shape[1], dim))
        found = vt[:dim].T
        basis[support, : found.shape[1]] = found
        return basis, support
    basis = support = None
    for dim in range(min_dim, max_dim + 1):
        init = None
        if basis is not None:
            extra = _residual_direction(X0, mask, basis, support)
            init = np.column_stack([basis, extra])
        basis, support = fit_observed_subspace(
            X0, mask, dim, init=init, max_iter=10 if init is not None else 30
        )
        residuals, dofs = subspace_residuals(X0, mask, [basis], [support])
        if residuals.sum() <= tol * noise * max(dofs.sum(), 1):
            break
    return basis, support
