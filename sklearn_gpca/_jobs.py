"""Independent computations of one segmentation run in parallel processes."""

# SPDX-License-Identifier: BSD-3-Clause

import logging
from functools import partial

from joblib import Parallel, delayed, effective_n_jobs

from sklearn_gpca._threads import one_thread

#: The library's loggers (``sklearn_gpca._segment`` and the others).
_LOGGER = logging.getLogger("sklearn_gpca")


class _Records(logging.Handler):
    """Keeps the records it is given, their messages formatted."""

    def __init__(self):
        super().__init__()
        self.records = []

    def emit(self, record):
        record.msg, record.args = record.getMessage(), None
        record.exc_info = record.exc_text = None
        self.records.append(record)


def _with_one_thread(function, item):
    with one_thread("blas"), one_thread("openmp"):
        return function(item)


def _in_worker(function, level, item):
    """``function(item)`` and the records the library logged at ``level``
    (kept for the caller, not handled in the worker)."""
    handler = _Records()
    level_before, propagate_before = _LOGGER.level, _LOGGER.propagate
    _LOGGER.addHandler(handler)
    _LOGGER.setLevel(level)
    _LOGGER.propagate = False
    try:
        return _with_one_thread(function, item), handler.records
    finally:
        _LOGGER.removeHandler(handler)
        _LOGGER.setLevel(level_before)
        _LOGGER.propagate = propagate_before


def map_jobs(function, items, n_jobs):
    """``[function(item) for item in items]``, in up to ``n_jobs`` processes.

    Every call runs with one BLAS and one OpenMP thread, in this process as
    in a worker (whose threads joblib limits to the cores per job): sums
    taken by another number of threads differ in their last bits, and a
    close choice downstream (a refinement, a spectral clustering) then moves
    a few tracks. With one thread everywhere the results do not depend on
    ``n_jobs`` nor on the machine's core count; the calls are many small
    computations that gain nothing from a second thread
    (``benchmarks/results/segment_speed.md``). What the calls log under the
    ``sklearn_gpca`` loggers, at the level enabled here, is logged here too,
    after them, in the order of ``items``.

    Parameters
    ----------
    function : callable
        Of one item; closures are fine (joblib's loky backend pickles them
        with cloudpickle).
    items : iterable
    n_jobs : int or None
        As for scikit-learn's estimators: None means 1 unless in a
        :func:`joblib.parallel_config` context, -1 every core. With one job
        the calls run in order in this process.

    Returns
    -------
    results : list
        In the order of ``items``; the same whatever ``n_jobs`` when
        ``function`` is deterministic.
    """
    items = list(items)
    n_jobs = min(effective_n_jobs(n_jobs), len(items))
    if n_jobs <= 1:
        return [_with_one_thread(function, item) for item in items]
    call = partial(_in_worker, function, _LOGGER.getEffectiveLevel())
    results = []
    for result, records in Parallel(n_jobs=n_jobs)(
        delayed(call)(item) for item in items
    ):
        for record in records:
            logging.getLogger(record.name).handle(record)
        results.append(result)
    return results
