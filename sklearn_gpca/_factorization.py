"""The stages of PowerFactorization, on validated arrays.

:func:`factorise` turns trajectories with missing entries into an orthonormal
basis of the fitted subspace and its singular values; :func:`project` gives
the coordinates of any rows in that basis. Both the public function
:func:`sklearn_gpca.power_factorization` and the estimator
:class:`sklearn_gpca.PowerFactorization` are short orchestrations of them.
"""

# SPDX-License-Identifier: BSD-3-Clause

import functools
import warnings
from typing import NamedTuple

import numpy as np
from sklearn.exceptions import ConvergenceWarning
from sklearn.utils.extmath import svd_flip

from sklearn_gpca._als import ALS
from sklearn_gpca._completion_rank import max_completion_rank, select_completion_rank
from sklearn_gpca._least_squares import fit_rows
from sklearn_gpca._mask_graph import determinable, n_connected_blocks
from sklearn_gpca._missing import describe_indices
from sklearn_gpca._multistart import best_of_starts
from sklearn_gpca._threads import one_thread
from sklearn_gpca._varpro import VarPro

# The solvers run many small BLAS calls: one BLAS thread is faster than the
# default pool, several times so on a busy machine
# (benchmarks/results/frames.md, measured both ways).
LIMIT_BLAS_THREADS = True


def _blas_threads_limited(function):
    """Run ``function`` with one BLAS thread (if ``LIMIT_BLAS_THREADS``)."""

    @functools.wraps(function)
    def wrapper(*args, **kwargs):
        if not LIMIT_BLAS_THREADS:
            return function(*args, **kwargs)
        with one_thread("blas"):
            return function(*args, **kwargs)

    return wrapper


class Factorization(NamedTuple):
    """What :func:`factorise` returns."""

    components: np.ndarray  # (q, n_features), orthonormal rows
    singular_values: np.ndarray  # (q,), in the units of X
    completion_errors: dict
    n_iter: int
    n_polish_iter: int
    n_init: int


@_blas_threads_limited
def factorise(
    X,
    n_components,
    *,
    solver,
    completion_rank,
    n_init,
    max_iter,
    tol,
    max_init_samples,
    random_state,
    log,
):
    """Fit ``X ~ Z diag(s) V`` at rank ``q`` over the observed entries of ``X``.

    ``X`` is a validated float array with NaN for missing entries. Features
    observed in fewer than ``n_components`` usable rows are left out of the
    fit (with a warning); rows observed in fewer than ``q`` entries do not
    inform the basis. The data are divided by the root mean square of their
    observed entries during the fit, so that results do not depend on the
    units.
    """
    X0, mask, scale = _rescaled(X)
    rows, columns = _determinable_part(X0, mask, n_components)
    X_core = X0[rows][:, columns]
    mask_core = None if mask is None else mask[rows][:, columns]
    rank, errors = _choose_rank(
        X_core, mask_core, n_components, completion_rank, random_state
    )
    fitted = rows.copy()
    if mask is not None:
        fitted[rows] = mask_core.sum(axis=1) >= rank
        mask_core = mask[fitted][:, columns]
    B, A, n_iter, n_polish_iter, n_starts, converged = _fit_basis(
        X0[fitted][:, columns],
        mask_core,
        rank,
        solver=solver,
        n_init=n_init,
        max_iter=max_iter,
        tol=tol,
        max_init_samples=max_init_samples,
        random_state=random_state,
        log=log,
    )
    if not converged:
        warnings.warn(
            f"PowerFactorization did not converge in max_iter={max_iter} "
            "iterations; increase max_iter or tol.",
            ConvergenceWarning,
            stacklevel=4,
        )
    A = _extend_basis(X0[fitted], None if mask is None else mask[fitted], B, A, columns)
    # B has orthonormal columns, so the SVD of the fit B A^T is B u s vt with
    # u s vt the SVD of the small rank x n_features matrix A^T.
    u, s, vt = np.linalg.svd(A.T, full_matrices=False)
    u, vt = svd_flip(u, vt, u_based_decision=False)
    vt[:, ~A.any(axis=1)] = 0.0  # features never observed: exactly zero
    return Factorization(vt, s * scale, errors, n_iter, n_polish_iter, n_starts)


@_blas_threads_limited
def project(X, components, singular_values):
    """Whitened coordinates of the rows of ``X`` in a fitted basis.

    Each row gets the least-squares coordinates of its observed entries in
    the basis ``diag(singular_values) components``: a row observed in
    ``k < q`` entries is fitted on the leading ``k`` directions (zeros
    beyond), a row with no observed entry gets zeros. Computed in units of the
    largest singular value, so that neither tiny nor huge data under- or
    overflow.

    Returns
    -------
    Z : ndarray of shape (n_samples, q)
    rms : float
        Root mean square residual over the observed entries, in the units of
        ``X`` (NaN if nothing is observed).
    """
    singular_values = np.asarray(singular_values, dtype=np.float64)
    unit = singular_values[0] if singular_values[0] > 0 else 1.0
    X0, mask = _zero_filled(X, unit)
    basis = (singular_values / unit)[:, None] * components.astype(np.float64)
    if mask is None:
        Z = fit_rows(X0, None, basis)
        n_observed = X0.size
    else:
        Z = np.zeros((X0.shape[0], basis.shape[0]))
        supported = np.minimum(mask.sum(axis=1), basis.shape[0]).astype(int)
        for k in np.unique(supported[supported > 0]):
            rows = supported == k
            Z[rows, :k] = fit_rows(X0[rows], mask[rows], basis[:k])
        n_observed = mask.sum()
    residual = X0 - Z @ basis
    if mask is not None:
        residual *= mask
    with np.errstate(invalid="ignore", divide="ignore"):
        rms = unit * np.sqrt(np.einsum("ij,ij->", residual, residual) / n_observed)
    return Z, float(rms)


def _zero_filled(X, unit):
    """``X / unit`` in float64 with NaN set to 0, and the observed mask (None
    when nothing is missing)."""
    X0 = X.astype(np.float64) / unit
    missing = np.isnan(X0)
    if not missing.any():
        return X0, None
    X0[missing] = 0.0
    return X0, (~missing).astype(np.float64)


def _rescaled(X):
    """``X`` zero-filled in units of the root mean square of its observed
    entries, the mask and that unit (1 for all-zero data)."""
    peak = np.nanmax(np.abs(X), initial=0.0)
    if not peak > 0:
        return (*_zero_filled(X, 1.0), 1.0)
    # the root mean square of X / peak (entries at most 1) neither under- nor
    # overflows
    scale = peak * np.sqrt(np.nanmean((X.astype(np.float64) / peak) ** 2))
    return (*_zero_filled(X, scale), scale)


def _determinable_part(X0, mask, n_components):
    """Rows and features that take part in the fit; warns about the others.

    Raises a ``ValueError`` when nothing is left.
    """
    n_samples, n_features = X0.shape
    if mask is None:
        return np.ones(n_samples, dtype=bool), np.ones(n_features, dtype=bool)
    rows, columns = determinable(mask, n_components)
    if not columns.any():
        raise ValueError(
            f"The observed entries do not determine any rank-{n_components} fit: "
            f"no set of features is each observed in at least "
            f"n_components={n_components} trajectories that are themselves "
            f"observed in at least {n_components} of these features. Lower "
            "n_components or observe more entries."
        )
    left_out = np.flatnonzero(~columns)
    if left_out.size:
        never = np.count_nonzero(mask[:, left_out].sum(axis=0) == 0)
        warnings.warn(
            f"{describe_indices(left_out)} of the {n_features} features are "
            f"observed in fewer than n_components={n_components} trajectories "
            f"usable for the fit ({never} of them in none): they are left out "
            "of the fit, and their entries of the basis are the minimum-norm "
            "fit to the few entries they have (zero for none).",
            UserWarning,
            stacklevel=5,
        )
    n_blocks = n_connected_blocks(mask[rows][:, columns])
    if n_blocks > 1:
        warnings.warn(
            f"The observed entries fall apart into {n_blocks} groups of "
            "trajectories and features that share no observed entry, so the "
            "fit does not determine how the groups relate: the completion of "
            "the entries between groups (inverse_transform) is arbitrary. Fit "
            "each group on its own, or observe entries that link them.",
            UserWarning,
            stacklevel=5,
        )
    return rows, columns


def _choose_rank(X0, mask, n_components, completion_rank, random_state):
    """Completion rank and the held-out errors that chose it."""
    if completion_rank is None:
        return n_components, {}
    auto = completion_rank == "auto"
    if mask is None:
        return (n_components if auto else completion_rank), {}
    limit = 3 * n_components if auto else completion_rank
    supported = max_completion_rank(mask, n_components, limit)
    if auto:
        return select_completion_rank(X0, mask, n_components, supported, random_state)
    if supported < completion_rank:
        warnings.warn(
            f"completion_rank={completion_rank} lowered to {supported}: a "
            "rank-q fit needs every feature observed in q trajectories and q "
            "trajectories observed in q entries, which the observed entries "
            f"give only up to q={supported}.",
            UserWarning,
            stacklevel=5,
        )
    return supported, {}


def _fit_basis(
    X0,
    mask,
    rank,
    *,
    solver,
    n_init,
    max_iter,
    tol,
    max_init_samples,
    random_state,
    log,
):
    """Orthonormal ``B`` and ``A`` with ``X0 ~ B A^T``.

    The best of the random starts (on a subsample of the rows when there are
    many), polished on all rows by the same solver.
    """
    Solver = ALS if solver == "als" or mask is None else VarPro
    X_start, mask_start = X0, mask
    subsample = _subsample(mask, rank, max_init_samples, random_state)
    if subsample is not None:
        X_start, mask_start = X0[subsample], mask[subsample]
    best, n_starts = best_of_starts(
        lambda init: Solver(X_start, mask_start, init, tol=tol, log=log),
        X0.shape[1],
        rank,
        n_init=n_init,
        max_iter=max_iter,
        random_state=random_state,
        log=log,
    )
    B, A, n_iter, converged = best.result()
    if subsample is None:
        return B, A, n_iter, 0, n_starts, converged
    log(f"polishing the best start on all {X0.shape[0]} rows")
    init, _ = np.linalg.qr(A)
    B, A, n_polish_iter, converged = (
        Solver(X0, mask, init, tol=tol, log=log).run(max_iter).result()
    )
    return B, A, n_iter, n_polish_iter, n_starts, converged


def _subsample(mask, rank, max_init_samples, random_state):
    """Rows on which the random starts run, or None for all rows.

    The ``max_init_samples`` rows with the most observed entries (ties in
    random order), provided they observe every feature ``rank`` times.
    """
    if mask is None or max_init_samples is None:
        return None
    n_rows = mask.shape[0]
    if n_rows <= max_init_samples:
        return None
    counts = mask.sum(axis=1)
    order = np.lexsort((random_state.permutation(n_rows), -counts))
    rows = np.sort(order[:max_init_samples])
    if mask[rows].sum(axis=0).min() < rank:
        return None  # a feature too rarely observed in the subsample
    return rows


def _extend_basis(X0, mask, B, A, columns):
    """The basis ``A`` on all features: the features left out of the fit get
    the minimum-norm least-squares fit to their entries in the fitted rows."""
    if columns.all():
        return A
    A_all = np.zeros((columns.size, A.shape[1]))
    A_all[columns] = A
    left_out = ~columns
    A_all[left_out] = fit_rows(X0[:, left_out].T, mask[:, left_out].T, B.T)
    return A_all
