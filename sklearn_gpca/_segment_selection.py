"""Criteria to choose among candidate segmentations of the same tracks.

- :func:`coding_length`: the lossy coding length of the segmented tracks;
- :func:`ambiguous_fraction`: the share of tracks that another motion fits
  nearly as well as their own (how separable the segmentation's motions are);
- :func:`select_segmentation`: the rules of
  :func:`sklearn_gpca.segment_motions` (``selection``) that combine them and
  :func:`sklearn_gpca._model_consistency.model_consistency`.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._observed_subspaces import (
    comoment_matrix,
    fit_observed_subspace,
    subspace_residuals,
)


def coding_length(X0, labels, noise, mask=None):
    """Bits to code the tracks, segmented by ``labels``, up to the noise.

    The lossy coding length of Ma, Derksen, Hong & Wright (PAMI 2007) of the
    rows of ``X0`` in ``R^D``, each group coded by its own zero-mean
    Gaussian, at the distortion ``eps^2 = D * noise`` (the noise variance per
    coordinate), plus the bits of the memberships::

        sum_k (m_k + D) / 2 log2 det(I + X_k^T X_k / (noise m_k))
              - m_k log2(m_k / m)

    A segmentation that merges two motions needs more dimensions in one
    group; one that splits a motion pays its subspace twice and the
    memberships: the true segmentation is usually the shortest even where
    the fit alone prefers a wrong one (a scene whose perspective bend is
    spread over two halves of the background). Missing entries count as
    zeros, so compare candidates of the same data only.

    Parameters
    ----------
    X0 : ndarray of shape (n_samples, n_features)
        Tracks, zero where missing.
    labels : ndarray of shape (n_samples,)
        Non-negative group of each track.
    noise : float
        Noise variance per coordinate, ``> 0``.
    mask : ndarray of shape (n_samples, n_features), dtype=bool, default=None
        Observed entries; None when nothing is missing.

    Returns
    -------
    bits : float
    """
    n_samples = X0.shape[0]
    bits = 0.0
    for group in np.unique(labels):
        members = X0[labels == group]
        size = members.shape[0]
        if mask is None or mask[labels == group].all():
            scatter = members.T @ members
        else:
            scatter = size * comoment_matrix(members, mask[labels == group])[0]
        eigvals = np.maximum(np.linalg.eigvalsh(scatter), 0.0)
        bits += (
            (size + X0.shape[1]) / 2 * np.sum(np.log2(1.0 + eigvals / (noise * size)))
        )
        bits -= size * np.log2(size / n_samples)
    return float(bits)


def ambiguous_fraction(X0, mask, labels, noise, *, subspace_dim=4, ratio=2.0):
    """Share of tracks that another motion fits nearly as well as their own.

    Each group of ``labels`` gets its ``subspace_dim``-dimensional subspace,
    fitted on its tracks' observed entries (:func:`fit_observed_subspace`);
    ``rho_pk`` is track ``p``'s residual to subspace ``k`` per residual degree
    of freedom. A track is ambiguous when

        rho_{p,other} + noise < ratio * (rho_{p,own} + noise)

    with ``other`` the best subspace but its own: the segmentation leaves it
    no clearer in one motion than in another. A segmentation that cuts one
    motion in two leaves the tracks of both halves ambiguous (the halves span
    the same subspace), one that puts two motions in one group leaves those
    tracks far from their own subspace; the true segmentation of separable
    motions leaves few (``benchmarks/results/segment_tracks.md`` measures how
    well this ranks candidates). Tracks without a residual degree of freedom
    in some subspace (too few observed coordinates) are not counted.

    Parameters
    ----------
    X0 : ndarray of shape (n_samples, n_features)
        Tracks, zero where missing.
    mask : ndarray of shape (n_samples, n_features), dtype=bool
        Observed entries.
    labels : ndarray of shape (n_samples,)
        Non-negative group of each track; at least two groups.
    noise : float
        Noise variance per coordinate, ``>= 0``: residuals below it are
        not told apart.
    subspace_dim : int or array-like of shape (n_groups,), default=4
        Dimension of every group's subspace, or one per group in the order
        of ``np.unique(labels)`` (e.g.
        :func:`sklearn_gpca._fitted_dimensions.group_dimensions`).
    ratio : float, default=2.0
        How much better the own subspace must fit, ``> 1``.

    Returns
    -------
    fraction : float
        In ``[0, 1]``; 0 when no track can be tested.
    """
    groups, index = np.unique(labels, return_inverse=True)
    if groups.size < 2:
        raise ValueError(
            f"ambiguous_fraction needs at least two groups, got {groups.size}."
        )
    dims = np.asarray(subspace_dim)
    if dims.ndim == 0:
        dims = np.full(groups.size, dims)
    if (
        dims.shape != (groups.size,)
        or not np.issubdtype(dims.dtype, np.integer)
        or dims.min() < 1
    ):
        raise ValueError(
            "subspace_dim must be a positive integer or one per group "
            f"({groups.size}), got {subspace_dim!r}."
        )
    fits = [
        fit_observed_subspace(X0[index == g], mask[index == g], int(dims[g]))
        for g in range(groups.size)
    ]
    residuals, dofs = subspace_residuals(
        X0, mask, [b for b, _ in fits], [s for _, s in fits]
    )
    rows = np.arange(labels.size)
    per_dof = np.where(dofs > 0, residuals / np.maximum(dofs, 1), np.inf)
    own = per_dof[rows, index]
    per_dof[rows, index] = np.inf
    other = per_dof.min(axis=1)
    testable = np.isfinite(own) & np.isfinite(other)
    if not testable.any():
        return 0.0
    ambiguous = other[testable] + noise < ratio * (own[testable] + noise)
    return float(np.mean(ambiguous))


def _least_within(primary, secondary, tolerance):
    """Least ``secondary`` among the ``primary`` within ``tolerance`` of the
    least (NaN ``primary``: not eligible unless all are NaN)."""
    judged = ~np.isnan(primary)
    if not judged.any():
        return int(np.argmin(secondary))
    eligible = judged & (primary <= primary[judged].min() + tolerance)
    return int(np.argmin(np.where(eligible, secondary, np.inf)))


def select_segmentation(
    coding_lengths,
    ambiguity,
    *,
    selection,
    tolerance,
    inconsistency=None,
    residual=None,
    misfit_cost=None,
    n_tracks=None,
):
    """Index of the segmentation kept among refined candidates.

    Parameters
    ----------
    coding_lengths : array-like of shape (n_candidates,)
        :func:`coding_length` of each candidate.
    ambiguity : array-like of shape (n_candidates,)
        :func:`ambiguous_fraction` of each candidate; NaN for a candidate
        that cannot be judged (fewer than two motions left after its
        refinement): ``"separability"`` keeps it only when no candidate can
        be judged.
    selection : {"coding_length", "separability", "consistency"}
        ``"coding_length"``: the shortest coding length. ``"separability"``:
        the shortest coding length among the candidates whose ambiguous
        fraction is within ``tolerance`` of the smallest. ``"consistency"``:
        the smallest penalised fit ``residual + misfit_cost * inconsistency
        * n_tracks`` (each track nearer another group's model costs
        ``misfit_cost``) among the candidates whose ``inconsistency`` is
        within ``tolerance`` of the smallest (NaN: not eligible, as for
        ``"separability"``).
    tolerance : float
        Slack on the ambiguous fraction or the inconsistency (a share of the
        tracks); ``1`` makes every judged candidate eligible.
    inconsistency, residual : array-like of shape (n_candidates,), default=None
        :func:`sklearn_gpca._model_consistency.model_consistency` of each
        candidate; needed by ``"consistency"`` only.
    misfit_cost : float, default=None
        Cost of one inconsistent track, in the units of ``residual``; None
        (or 0): ``residual`` alone.
    n_tracks : int, default=None
        Number of tracks the candidates were judged on; needed with
        ``misfit_cost``.

    Returns
    -------
    chosen : int
    """
    coding_lengths = np.asarray(coding_lengths, dtype=float)
    ambiguity = np.asarray(ambiguity, dtype=float)
    if coding_lengths.shape != ambiguity.shape or coding_lengths.size == 0:
        raise ValueError(
            "coding_lengths and ambiguity must be non-empty and of one shape, got "
            f"{coding_lengths.shape} and {ambiguity.shape}."
        )
    if selection == "coding_length":
        return int(np.argmin(coding_lengths))
    if selection == "separability":
        return _least_within(ambiguity, coding_lengths, tolerance)
    if selection != "consistency":
        raise ValueError(
            "selection must be 'coding_length', 'separability' or 'consistency', "
            f"got {selection!r}."
        )
    if inconsistency is None or residual is None:
        raise ValueError("selection='consistency' needs inconsistency and residual.")
    inconsistency = np.asarray(inconsistency, dtype=float)
    residual = np.asarray(residual, dtype=float)
    if not inconsistency.shape == residual.shape == coding_lengths.shape:
        raise ValueError(
            "inconsistency and residual must have one value per candidate "
            f"({coding_lengths.size}), got shapes {inconsistency.shape} and "
            f"{residual.shape}."
        )
    fit = np.where(np.isnan(residual), np.inf, residual)
    if misfit_cost:
        if n_tracks is None:
            raise ValueError("misfit_cost needs n_tracks.")
        fit = fit + misfit_cost * n_tracks * np.nan_to_num(inconsistency)
    # a candidate without a judgement has no residual either: never the least
    return _least_within(inconsistency, fit, tolerance)
