"""Criteria to choose among candidate segmentations of the same tracks."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._observed_subspaces import comoment_matrix


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
