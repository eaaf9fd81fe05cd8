"""Independent computations of one segmentation run in parallel processes."""

# SPDX-License-Identifier: BSD-3-Clause

from joblib import Parallel, delayed, effective_n_jobs


def map_jobs(function, items, n_jobs):
    """``[function(item) for item in items]``, in up to ``n_jobs`` processes.

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
        return [function(item) for item in items]
    return Parallel(n_jobs=n_jobs)(delayed(function)(item) for item in items)
