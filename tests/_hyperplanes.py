"""Points on hyperplanes drawn by hypothesis, shared by the property tests."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
from hypothesis.extra.numpy import arrays


def draw_points_on_hyperplanes(draw, normals, design, elements):
    """Points ``(design + 0.5 * moves) @ basis_k`` on each hyperplane ``k``.

    ``moves`` are drawn (``elements`` per entry) for each hyperplane, whose
    orthonormal basis comes from the SVD of its unit normal. Points within a
    sine of 0.1 of another hyperplane, or of norm below 0.1, are ambiguous and
    left out.

    Returns
    -------
    X : ndarray of shape (n_kept, n_features)
    y : ndarray of shape (n_kept,)
        Index of each point's hyperplane.
    """
    X, y = [], []
    for k, normal in enumerate(normals):
        basis = np.linalg.svd(normal[None, :])[2][1:]
        moves = draw(arrays(np.float64, design.shape, elements=elements))
        X.append((design + 0.5 * moves) @ basis)
        y.append(np.full(design.shape[0], k))
    X, y = np.vstack(X), np.concatenate(y)
    norms = np.linalg.norm(X, axis=1)
    sines = np.abs(X @ normals.T) / np.maximum(norms, 1e-300)[:, None]
    sines[np.arange(len(y)), y] = np.inf
    keep = (sines.min(axis=1) >= 0.1) & (norms > 0.1)
    return X[keep], y[keep]
