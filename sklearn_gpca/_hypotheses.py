"""Subspace hypotheses from small sets of co-visible tracks.

Beyond the paper (issues 16 and 17): a hypothesis is the ``d``-dimensional
linear subspace of ``R^{2F}`` spanned by a track and its nearest tracks, on the
coordinates all of them observe. Every track is scored against every
hypothesis on its own observed entries within the hypothesis's support
(residual per residual degree of freedom). Cost: ``O(P H D d^2)`` time for the
residuals, linear in ``P`` for a bounded number ``H`` of hypotheses.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._chunks import row_chunks
from sklearn_gpca._least_squares import damp
from sklearn_gpca._rows import TINY


def local_hypotheses(
    X0, mask, neighbors, seeds, dim, size, *, min_support, return_noise=False
):
    """Subspaces spanned by each seed and its nearest co-visible tracks.

    Neighbours are taken in order (nearest first) while the coordinates
    observed by all members stay at least ``min_support``; the subspace is
    the span of the ``dim`` leading right singular vectors of the members
    restricted to those coordinates.

    Parameters
    ----------
    X0, mask : ndarray of shape (n_samples, n_features)
        Tracks (zero where missing) and observed entries.
    neighbors : ndarray of shape (n_samples, n_neighbors)
        Nearest tracks, ``-1`` for none.
    seeds : ndarray of shape (n_hypotheses,)
        Track each hypothesis starts from.
    dim : int
        Dimension of the hypotheses.
    size : int
        Largest number of tracks per hypothesis (seed included).
    min_support : int
        Fewest coordinates a hypothesis is defined on.
    return_noise : bool, default=False
        Also return each hypothesis's residual energy per residual degree
        of freedom of its members (NaN without any).

    Returns
    -------
    bases : ndarray of shape (n_hypotheses, n_features, dim)
        Orthonormal columns, zero rows outside the support.
    supports : ndarray of shape (n_hypotheses, n_features), dtype=bool
    n_members : ndarray of shape (n_hypotheses,), dtype=intp
    """
    n_hyp = seeds.shape[0]
    members = np.full((n_hyp, size), -1, dtype=np.intp)
    members[:, 0] = seeds
    support = mask[seeds].copy()
    count = np.ones(n_hyp, dtype=np.intp)
    for j in range(neighbors.shape[1]):
        candidate = neighbors[seeds, j]
        valid = (candidate >= 0) & (count < size)
        new_support = support & mask[np.maximum(candidate, 0)]
        take = valid & (new_support.sum(axis=1) >= min_support)
        members[take, count[take]] = candidate[take]
        support[take] = new_support[take]
        count[take] += 1
    stacked = np.where(members[:, :, None] >= 0, X0[np.maximum(members, 0)], 0.0)
    stacked *= support[:, None, :]
    _, values, vt = np.linalg.svd(stacked, full_matrices=False)
    bases = np.zeros((n_hyp, X0.shape[1], dim))
    n_dir = min(dim, vt.shape[1])
    bases[:, :, :n_dir] = vt[:, :n_dir].transpose(0, 2, 1)
    # a hypothesis with fewer than dim members keeps zero columns beyond them
    bases *= (np.arange(dim) < count[:, None])[:, None, :]
    if return_noise:
        # residual energy per residual degree of freedom of the members
        energy = np.sum(values[:, dim:] ** 2, axis=1)
        dofs = (count - dim) * (support.sum(axis=1) - dim)
        noise = np.where(dofs > 0, energy / np.maximum(dofs, 1), np.nan)
        return bases, support, count, noise
    return bases, support, count


def local_noise_level(
    X0, mask, neighbors, *, dim=4, size=8, n_samples=200, random_state
):
    """Noise variance per coordinate, from small sets of neighbouring tracks.

    A track and its nearest co-visible tracks almost always share a motion,
    so the residual of their best ``dim``-dimensional subspace (per residual
    degree of freedom, ``(n - dim)(D_h - dim)`` for ``n`` tracks on ``D_h``
    coordinates) measures the noise; the median over ``n_samples`` random
    seeds is robust to the few mixed sets. Returns a float ``> 0``.
    """
    n_samples_total, n_features = X0.shape
    min_support = min(2 * (dim + 2), n_features)
    eligible = np.flatnonzero(np.count_nonzero(mask, axis=1) >= min_support)
    if eligible.size == 0:
        eligible = np.arange(n_samples_total)
    seeds = random_state.choice(eligible, min(n_samples, eligible.size), replace=False)
    *_, noise = local_hypotheses(
        X0,
        mask,
        neighbors,
        seeds,
        dim,
        size,
        min_support=min_support,
        return_noise=True,
    )
    noise = noise[np.isfinite(noise) & (noise > 0)]
    if noise.size == 0:
        observed = X0[mask]
        return float(max(np.mean(observed**2) * 1e-6, TINY))
    return float(np.median(noise))


def hypothesis_residuals(X0, mask, bases, supports):
    """Residual of every track to every hypothesis on its observed support.

    Parameters
    ----------
    X0, mask : ndarray of shape (n_samples, n_features)
        Tracks and observed entries.
    bases : ndarray of shape (n_hypotheses, n_features, dim)
        Zero rows outside each support.
    supports : ndarray of shape (n_hypotheses, n_features), dtype=bool

    Returns
    -------
    residuals : ndarray of shape (n_samples, n_hypotheses)
        ``min_z ||x_O - B_O z||^2`` over ``O`` = observed and in the support.
    dofs : ndarray of shape (n_samples, n_hypotheses), dtype=intp
        ``max(|O| - rank, 0)`` with ``rank`` the number of non-zero columns.
    """
    n_samples, n_features = X0.shape
    n_hyp, _, dim = bases.shape
    ranks = np.count_nonzero(np.any(bases != 0, axis=1), axis=1)
    flat = bases.transpose(1, 0, 2).reshape(n_features, n_hyp * dim)
    m = mask.astype(np.float64)
    counts = (m @ supports.T.astype(np.float64)).astype(np.intp)
    complete = bool(mask.all()) and bool(supports.all())
    if not complete:
        outer = (bases[:, :, :, None] * bases[:, :, None, :]).transpose(1, 0, 2, 3)
        outer = outer.reshape(n_features, n_hyp * dim * dim)
    residuals = np.empty((n_samples, n_hyp))
    sq = X0 * X0
    for rows in row_chunks(n_samples, max(1, 2**22 // max(n_hyp * dim * dim, 1))):
        norms = sq[rows] @ supports.T
        rhs = (X0[rows] @ flat).reshape(-1, n_hyp, dim)
        if complete:
            fitted = np.einsum("phd,phd->ph", rhs, rhs)
        else:
            gram = (m[rows] @ outer).reshape(-1, n_hyp, dim, dim)
            coefs = np.linalg.solve(damp(gram), rhs[..., None])[..., 0]
            fitted = np.einsum("phd,phd->ph", rhs, coefs)
        residuals[rows] = np.maximum(norms - fitted, 0.0)
    dofs = np.maximum(counts - ranks[None, :], 0)
    return residuals, dofs
