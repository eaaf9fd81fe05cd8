"""The whitened leading directions in which GPCAClustering segments wide inputs.

``GPCAClustering(segmentation_dim=k)`` takes points of any width (e.g. the
unwhitened rank-20 projection of the trajectories, in which
``n_clusters="auto"`` counts the motions) and segments them in the ``k``
leading principal directions of the points, not centred and whitened: for
complete trajectories, the coordinates ``PowerFactorization(k)`` returns.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._rows import canonical_sign


def fit_segmentation_space(X, n_components):
    """Leading right singular vectors of ``X`` and their singular values.

    Parameters
    ----------
    X : ndarray of shape (n_samples, n_features)
        Points, not centred.
    n_components : int
        Number of directions kept, at most ``min(n_samples, n_features)``.

    Returns
    -------
    components : ndarray of shape (n_components, n_features)
        Orthonormal rows, signed so that the largest-magnitude entry of each
        is positive.
    scale : ndarray of shape (n_components,)
        The singular values of ``X`` along them (zeros replaced by 1).

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._segmentation_space import fit_segmentation_space
    >>> X = np.diag([3.0, 2.0, 1.0])
    >>> components, scale = fit_segmentation_space(X, 2)
    >>> components
    array([[1., 0., 0.],
           [0., 1., 0.]])
    >>> scale
    array([3., 2.])
    """
    _, singular_values, components = np.linalg.svd(X, full_matrices=False)
    components = canonical_sign(components[:n_components])
    scale = singular_values[:n_components]
    return components, np.where(scale > 0, scale, 1.0)


def to_segmentation_space(X, components, scale):
    """Whitened coordinates ``X V / s`` of points in the kept directions.

    Parameters
    ----------
    X : ndarray of shape (n_samples, n_features)
    components : ndarray of shape (n_components, n_features)
    scale : ndarray of shape (n_components,)

    Returns
    -------
    Z : ndarray of shape (n_samples, n_components)
        For the training points, their left singular vectors.
    """
    return (X @ components.T) / scale
