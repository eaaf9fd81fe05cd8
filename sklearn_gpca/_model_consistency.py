"""How well a segmentation's own motion models explain its tracks.

:func:`model_consistency` fits one model per group of a candidate
segmentation (a perspective camera per frame for the largest group, the
background of tracker output; a linear subspace for the others) and measures

- the share of tracks that another group's model fits better than their own
  (per residual degree of freedom): a segmentation that merges two motions
  or cuts one in two leaves tracks nearer another group's model than their
  own, the true one leaves few;
- the fit: ``sum log(1 + rho / noise)`` over the tracks, ``rho`` a track's
  residual per degree of freedom to its own model (the Cauchy loss: about
  ``rho / noise`` near the noise level, logarithmic beyond, so that a few
  tracks that fit no model cannot decide the comparison, and still a
  measure, not a count, where the noise is underestimated).

:func:`sklearn_gpca.segment_motions` (``selection="consistency"``) keeps the
candidate of least fit plus a fixed cost per track nearer another group's
model (``MISFIT_COST``).
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._observed_subspaces import fit_observed_subspace, subspace_residuals
from sklearn_gpca._projective_motion import (
    affine_cameras,
    fit_projective_motion,
    projective_residuals,
)
from sklearn_gpca._refine_observed import MIN_PROJECTIVE_TRACKS


def model_consistency(
    X0,
    mask,
    labels,
    noise,
    *,
    subspace_dim=4,
    perspective_background=True,
    cameras=None,
    per_track=False,
):
    """Share of tracks nearer another group's model, and the robust fit.

    Parameters
    ----------
    X0 : ndarray of shape (n_samples, n_features)
        Tracks, zero where missing.
    mask : ndarray of shape (n_samples, n_features), dtype=bool
        Observed entries.
    labels : ndarray of shape (n_samples,)
        Non-negative group of each track.
    noise : float
        Noise variance per coordinate, ``> 0``.
    subspace_dim : int, default=4
        Dimension of the subspace of every group but the perspective one.
    perspective_background : bool, default=True
        Model the largest group (when it holds at least
        ``MIN_PROJECTIVE_TRACKS`` tracks, as the refinement needs; a smaller
        one gets a subspace) by one ``3 x 4`` camera per frame
        (:func:`sklearn_gpca._projective_motion.fit_projective_motion`); False:
        every group by a subspace.
    cameras : ndarray of shape (n_frames, 3, 4), default=None
        A start for the perspective cameras (e.g. those of a refinement of
        the same tracks): a few alternations from it instead of the
        sequential fit.
    per_track : bool, default=False
        Also return what each track adds to both.

    Returns
    -------
    inconsistency : float
        Share of the testable tracks (a residual degree of freedom in their
        own model) whose residual per degree of freedom is smaller in another
        group's model; NaN when fewer than two groups can be modelled (more
        than ``subspace_dim`` tracks each). A smaller group fits its tracks
        exactly: each of them counts as nearer another group's model, and
        its residual is that of the nearest modelled group's model.
    residual : float
        Sum over the testable tracks of ``log(1 + rho / noise)``, ``rho``
        their residual per degree of freedom in their own model (for the
        tracks of a group too small to be modelled, the nearest model).
    tracks : ndarray of shape (n_samples, 2)
        Only with ``per_track``: each track's ``log(1 + rho / noise)`` and
        whether another group's model fits it better (1.0 or 0.0); NaN for a
        track that is not testable.
    """
    groups, index = np.unique(labels, return_inverse=True)
    sizes = np.bincount(index, minlength=groups.size)
    modelled = np.flatnonzero(sizes > subspace_dim)
    untested = (np.nan, np.nan, np.full((labels.size, 2), np.nan))
    if modelled.size < 2:
        return untested if per_track else untested[:2]
    largest = int(np.argmax(sizes))
    per_dof = np.full((labels.size, groups.size), np.inf)
    for g in modelled:
        members = index == g
        if (
            perspective_background
            and g == largest
            and sizes[g] >= MIN_PROJECTIVE_TRACKS
        ):
            per_dof[:, g] = _perspective_per_dof(X0, mask, members, cameras, noise)
        else:
            basis, support = fit_observed_subspace(
                X0[members], mask[members], subspace_dim
            )
            residuals, dofs = subspace_residuals(X0, mask, [basis], [support])
            per_dof[:, g] = _per_dof(residuals[:, 0], dofs[:, 0])
    own = per_dof[np.arange(labels.size), index]
    # a group of subspace_dim tracks or fewer fits them exactly, so it cannot
    # be tested: its tracks are judged by the nearest modelled group's model
    # and count as nearer another group's model (otherwise a candidate gains
    # by setting its worst-fitting tracks apart in such a group)
    unmodelled = ~np.isin(index, modelled)
    own = np.where(unmodelled, per_dof.min(axis=1), own)
    testable = np.isfinite(own)
    if not testable.any():
        return untested if per_track else untested[:2]
    misfit = unmodelled[testable] | (
        np.argmin(per_dof[testable], axis=1) != index[testable]
    )
    inconsistency = float(np.mean(misfit))
    scores = inconsistency, _robust_fit(own[testable], noise)
    if not per_track:
        return scores
    tracks = np.full((labels.size, 2), np.nan)
    tracks[testable, 0] = np.log1p(own[testable] / noise)
    tracks[testable, 1] = misfit
    return (*scores, tracks)


def _per_dof(residuals, dofs):
    """Residual per degree of freedom, ``inf`` for a track without one."""
    return np.where(dofs > 0, residuals / np.maximum(dofs, 1), np.inf)


def _robust_fit(per_dof, noise):
    """``sum log(1 + rho / noise)`` over the tracks with a residual."""
    return float(np.sum(np.log1p(per_dof[np.isfinite(per_dof)] / noise)))


def _perspective_per_dof(X0, mask, members, cameras, noise):
    """Every track's residual per degree of freedom to the members' perspective motion.

    The motion is fitted twice, from ``cameras`` (or frame by frame) and
    from the members' affine cameras (an affine camera is a perspective one:
    started there, the fit can end no worse than the affine model, where the
    sequential fit can settle in a poor reconstruction); the fit that
    explains the members better (:func:`_robust_fit`) is kept.
    """
    columns = [
        _per_dof(
            *projective_residuals(
                X0,
                mask,
                *fit_projective_motion(X0[members], mask[members], cameras=start),
            )
        )
        for start in (cameras, affine_cameras(X0[members], mask[members]))
    ]
    return min(columns, key=lambda column: _robust_fit(column[members], noise))
