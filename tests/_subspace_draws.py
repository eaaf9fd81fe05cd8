"""Tracks on random subspaces, shared by the selection tests."""

import numpy as np


def subspace_tracks(sizes=(120, 60, 60), n_frames=12, missing=0.0, seed=0):
    """Tracks on random 4-D subspaces of R^{2F} (generic: far apart), unit
    noise, a fraction ``missing`` of each track's frames unseen."""
    rng = np.random.RandomState(seed)
    blocks, labels = [], []
    for k, size in enumerate(sizes):
        basis = np.linalg.qr(rng.standard_normal((2 * n_frames, 4)))[0]
        blocks.append(100.0 * rng.standard_normal((size, 4)) @ basis.T)
        labels.append(np.full(size, k))
    X = np.vstack(blocks) + rng.standard_normal((sum(sizes), 2 * n_frames))
    unseen = rng.rand(X.shape[0], n_frames) < missing
    X[np.repeat(unseen, 2, axis=1)] = np.nan
    return X, np.concatenate(labels)
