"""Lossy coding length of a segmentation, to choose the number of subspaces.

Ma, Derksen, Hong and Wright, "Segmentation of multivariate mixed data via
lossy data coding and compression" (PAMI 2007): the number of bits needed to
code ``m`` vectors of :math:`R^D` up to a distortion ``eps``, when they are split
into groups each coded by its own Gaussian (here without mean: the subspaces
are linear), plus the bits of the group memberships. Splitting a subspace in
two costs more bits than it saves; merging two subspaces into one of higher
dimension also costs bits, so the minimum over the number of groups is a
model-selection criterion with no further penalty.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np


def coding_length(points, labels, distortion):
    """Bits to code ``points`` segmented by ``labels`` up to ``distortion``.

    Parameters
    ----------
    points : ndarray of shape (n_samples, n_features)
        Points (unit vectors for a scale-free distortion).
    labels : ndarray of shape (n_samples,)
        Non-negative integer group of each point.
    distortion : float
        Allowed mean squared error per point is ``distortion ** 2``.

    Returns
    -------
    bits : float
        ``sum_k (m_k + D) / 2 log2 det(I + D / (eps^2 m_k) X_k^T X_k)
        - m_k log2(m_k / m)`` over the non-empty groups ``k``.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._coding_length import coding_length
    >>> rng = np.random.RandomState(0)
    >>> X = np.vstack([np.c_[rng.randn(50), np.zeros(50)],
    ...                np.c_[np.zeros(50), rng.randn(50)]])
    >>> y = np.repeat([0, 1], 50)
    >>> bool(coding_length(X, y, 0.1) < coding_length(X, 0 * y, 0.1))
    True
    """
    n_samples, n_features = points.shape
    bits = 0.0
    for group in np.unique(labels):
        members = points[labels == group]
        size = members.shape[0]
        eigvals = np.maximum(np.linalg.eigvalsh(members.T @ members), 0.0)
        scale = n_features / (distortion**2 * size)
        bits += (size + n_features) / 2 * np.sum(np.log2(1.0 + scale * eigvals))
        bits -= size * np.log2(size / n_samples)
    return float(bits)
