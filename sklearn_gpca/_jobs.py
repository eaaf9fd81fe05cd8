"""Independent computations of one segmentation run in parallel processes."""

# SPDX-License-Identifier: BSD-3-Clause

from functools import partial

from joblib import Parallel, delayed, effective_n_jobs

from sklearn_gpca._threads import one_thread


def _with_one_thread(function, item):
    with one_thread("blas"), one_thread("openmp"):
        return function(item)


def map_jobs(function, items, n_jobs):
    """``[function(item) for item in items]``, in up to ``n_jobs`` processes.

    Every call runs with one BLAS and one OpenMP thread, in this process as
    in a worker (whose threads joblib limits to the cores per job): sums
    taken by another number of threads differ in their last bits, and a
    close choice downstream (a refinement, a spectral clustering) then moves
    a few tracks. With one thread everywhere the results do not depend on
    ``n_jobs`` nor on the machine's core count; the calls are many small
    computations that gain nothing from a second thread
    (``benchmarks/results/segment_speed.md``).

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
    call = partial(_with_one_thread, function)
    n_jobs = min(effective_n_jobs(n_jobs), len(items))
    if n_jobs <= 1:
        return [call(item) for item in items]
    return Parallel(n_jobs=n_jobs)(delayed(call)(item) for item in items)
