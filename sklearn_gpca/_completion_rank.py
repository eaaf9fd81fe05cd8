"""Choice of the rank at which trajectories with gaps are completed.

``n`` rigid motions span up to ``4 n`` dimensions, more than the ``r = 5`` of
the projection. Least-squares coordinates in a rank-5 basis computed from a
few observed entries are not the projection of the complete trajectory, so
:class:`~sklearn_gpca.PowerFactorization` completes the data at a rank ``q``
chosen by held-out error and then projects on the leading ``r`` directions.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._als import als, silent
from sklearn_gpca._multistart import random_basis

# Entries held out to compare ranks, and the rows used for the comparison.
_HELD_OUT = 0.1
_MAX_ROWS = 2000
# The smallest rank whose held-out error is within this factor of the best.
_SLACK = 1.05


def max_completion_rank(mask, n_components, max_rank):
    """Largest rank worth trying: enough rows and columns must determine it.

    Every column must be observed ``q`` times, and at least ``q`` rows must
    be observed in ``q`` entries or more (the rows that inform a rank-``q``
    basis).
    """
    n_samples, n_features = mask.shape
    col_counts = mask.sum(axis=0)
    row_counts = np.sort(mask.sum(axis=1))[::-1]
    # the largest q with q rows observed in at least q entries (an h-index)
    rows_limit = np.count_nonzero(row_counts >= np.arange(1, n_samples + 1))
    limit = min(max_rank, n_features, n_samples, col_counts.min(), rows_limit)
    return int(max(n_components, limit))


def select_completion_rank(X0, mask, n_components, max_rank, random_state):
    """Rank in ``[n_components, max_rank]`` with the best held-out error.

    A tenth of the observed entries of (at most 2000) well-observed rows are
    held out; a rank-``q`` fit (alternating least squares, the cheap solver:
    near the right rank the data are nearly exactly low rank) predicts them
    for each candidate ``q``, and the smallest ``q`` whose root mean square
    held-out error is within 5 % of the best is returned, so that exactly
    low-rank data are not over-fitted. The search stops after two ranks in
    a row fall short of the best.

    Returns
    -------
    rank : int
    errors : dict
        Held-out RMS error of every candidate rank.
    """
    counts = mask.sum(axis=1)
    candidates = np.flatnonzero(counts >= max_rank + 2)
    if candidates.size > _MAX_ROWS:
        candidates = np.sort(random_state.choice(candidates, _MAX_ROWS, replace=False))
    if candidates.size < 2 * max_rank:
        return n_components, {}
    X_rows, M_rows = X0[candidates], mask[candidates]

    # Hold out entries at random but keep max_rank + 1 observed per row.
    scores = np.where(M_rows > 0, random_state.random_sample(M_rows.shape), np.inf)
    order = np.argsort(np.argsort(scores, axis=1), axis=1)
    allowed = np.minimum(
        np.ceil(_HELD_OUT * M_rows.sum(axis=1)), M_rows.sum(axis=1) - max_rank - 1
    )
    held_out = (order < allowed[:, None]) & (M_rows > 0)
    train = M_rows * ~held_out
    if train.sum(axis=0).min() < max_rank or not held_out.any():
        return n_components, {}

    errors = {}
    X_train = X_rows * train
    for rank in range(n_components, max_rank + 1):
        best = min(errors.values(), default=np.inf)
        if len(errors) >= 2 and min(list(errors.values())[-2:]) > _SLACK * best:
            break  # two ranks in a row worse than the best: past the true rank
        init = random_basis(X_train.shape[1], rank, random_state)
        B, A, _, _ = als(X_train, train, init, max_iter=100, tol=1e-6, log=silent)
        residual = (X_rows - B @ A.T)[held_out]
        errors[rank] = float(np.sqrt(np.mean(residual**2)))
    best = min(errors.values())
    rank = min(q for q, error in errors.items() if error <= _SLACK * best + 1e-12)
    return rank, errors
