"""Random restarts of a factorisation solver.

Hong & Fitzgibbon's meta-algorithm (ICCV 2015): run random starts until the
lowest residual has been reached twice. Starts heading for poor local minima
are told apart early, so every start first gets a few steps; the promising
ones get a bounded number more at once, and the unfinished starts are
pursued to the end only once all have been drawn.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._least_squares import fits_exactly

# Accepted steps every start gets before the unfinished starts are ranked.
TRIAL_STEPS = 20
# Further accepted steps a promising start gets before the next start is
# drawn (on Dinosaur, starts reaching the optimum take 20-60 in all).
PURSUIT_STEPS = 40
# Two residuals are the same minimum when they agree to this relative margin.
_SAME_MINIMUM = 1e-4


def random_basis(n_features, rank, random_state):
    """A uniformly random orthonormal ``n_features x rank`` basis."""
    basis, _ = np.linalg.qr(random_state.standard_normal((n_features, rank)))
    return basis


def best_of_starts(
    make_start, n_features, rank, *, n_init, max_iter, random_state, log
):
    """Best of up to ``n_init`` random starts of one solver.

    Every start first runs for :data:`TRIAL_STEPS` accepted steps. One whose
    residual is then the lowest of all trial residuals so far is pursued at
    once for :data:`PURSUIT_STEPS` more accepted steps (not to convergence:
    a start crawling along a poor valley would hold up the others for
    hundreds of steps); the others wait. Once ``n_init`` starts have been
    drawn, the unfinished ones are pursued to convergence (or ``max_iter``
    iterations), lowest residual first. Starts stop as soon as the lowest
    residual of the converged ones has been reached by another start too (to
    a relative ``1e-4``; a waiting start counts, since its residual only
    decreases) and no waiting start is lower, or is an exact fit. With
    ``n_init=1`` this is a plain run of the solver.

    Parameters
    ----------
    make_start : callable
        ``make_start(init)`` returns a solver object (``ALS`` or ``VarPro``)
        started from the orthonormal basis ``init``.
    n_features, rank : int
    n_init : int
    max_iter : int
        Iterations per start.
    random_state : numpy.random.RandomState
    log : callable

    Returns
    -------
    best : solver object
        The start with the lowest residual.
    n_starts : int
        Number of starts run.
    """
    finished, pending = [], []

    def enough():
        # the lowest residual of a finished start, reached by another start
        # (a waiting one already that low will end there or lower) and not
        # already beaten by a waiting one
        if not finished:
            return False
        lowest = _lowest(finished)
        if fits_exactly(lowest.cost, lowest.total):
            return True
        costs = np.array([start.cost for start in finished + pending])
        if np.any(costs < lowest.cost * (1 - _SAME_MINIMUM)):
            return False
        return np.sum(costs <= lowest.cost * (1 + _SAME_MINIMUM)) >= 2

    lowest_trial = np.inf
    for k in range(1, n_init + 1):
        start = make_start(random_basis(n_features, rank, random_state))
        start.run(max_iter, max_accepted=TRIAL_STEPS)
        log(f"start {k}, squared residual {start.cost:.6g} after {start.n_iter} steps")
        promising = start.cost <= lowest_trial
        lowest_trial = min(lowest_trial, start.cost)
        if promising and not start.done:
            start.run(max_iter, max_accepted=PURSUIT_STEPS)
            log(f"pursued start {k} to squared residual {start.cost:.6g}")
        finishes = start.done or start.n_iter >= max_iter
        (finished if finishes else pending).append(start)
        if enough():
            return _lowest(finished), k
    for start in sorted(pending, key=lambda start: start.cost):
        start.run(max_iter)
        pending.remove(start)
        finished.append(start)
        log(f"pursued a waiting start to squared residual {start.cost:.6g}")
        if enough():
            break
    return _lowest(finished), n_init


def _lowest(starts):
    return min(starts, key=lambda start: start.cost)
