"""Each motion's model, fitted to its tracks; every track's residual to each.

A motion of a segmentation is modelled by the subspace of its tracks (the
affine camera of section 2 of the paper, fitted on observed entries) and, for
the largest motion (the background of a tracker's output), also by a
perspective camera per frame (:mod:`sklearn_gpca._projective_motion`). A
track's residual to the largest motion is the smaller of the two where both
count the same frames.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._model_consistency import _per_dof
from sklearn_gpca._observed_subspaces import fit_observed_subspace, subspace_residuals
from sklearn_gpca._projective_motion import fit_projective_motion, projective_residuals


class MotionModels:
    """The models of the motions of ``labels``.

    Parameters
    ----------
    X0 : ndarray of shape (n_samples, 2 * n_frames)
        Tracks, zero where missing.
    mask : ndarray of shape (n_samples, 2 * n_frames), dtype=bool
        Observed entries.
    labels : ndarray of shape (n_samples,)
        Motion of each track in ``0 .. n_motions - 1``, ``-1`` for none.
    n_motions : int
    subspace_dim : int
        Dimension of every motion's subspace.
    perspective : bool
        Also model the largest motion by a perspective camera per frame.
    min_tracks : int
        Fewest tracks of a modelled motion; the others explain nothing.

    Attributes
    ----------
    modelled : ndarray of int
        The motions with a model.
    largest : int
        The motion with the most tracks.
    """

    def __init__(
        self, X0, mask, labels, n_motions, *, subspace_dim, perspective, min_tracks
    ):
        sizes = np.bincount(labels[labels >= 0], minlength=n_motions)
        self.n_motions = n_motions
        self.largest = int(np.argmax(sizes))
        self.modelled = np.flatnonzero(sizes >= max(min_tracks, 1))
        self.subspaces = {}
        self.cameras = None
        for k in self.modelled:
            members = labels == k
            self.subspaces[k] = fit_observed_subspace(
                X0[members], mask[members], subspace_dim
            )
            if perspective and k == self.largest:
                self.cameras = fit_projective_motion(X0[members], mask[members])

    def residuals(self, X0, mask):
        """Squared residual and degrees of freedom of every track to every model.

        Returns
        -------
        residuals : ndarray of shape (n_samples, n_motions)
            Infinite for a motion without a model.
        dofs : ndarray of shape (n_samples, n_motions), dtype=intp
        """
        n_samples = X0.shape[0]
        residuals = np.full((n_samples, self.n_motions), np.inf)
        dofs = np.zeros((n_samples, self.n_motions), dtype=np.intp)
        for k in self.modelled:
            basis, support = self.subspaces[k]
            r, d = subspace_residuals(X0, mask, [basis], [support])
            residuals[:, k], dofs[:, k] = r[:, 0], d[:, 0]
            if self.cameras is not None and k == self.largest:
                r, d = projective_residuals(X0, mask, *self.cameras)
                # the same frames counted by both models: the better fit is kept
                better = (d == dofs[:, k]) & (r < residuals[:, k])
                residuals[better, k] = r[better]
        return residuals, dofs

    def per_dof(self, X0, mask):
        """Every track's residual per degree of freedom to every model
        (``inf`` without a model or a degree of freedom)."""
        return _per_dof(*self.residuals(X0, mask))
