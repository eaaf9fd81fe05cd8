"""map_jobs: results in order, each call with one BLAS and OpenMP thread."""

# SPDX-License-Identifier: BSD-3-Clause

import pytest
from joblib import parallel_config
from threadpoolctl import threadpool_info, threadpool_limits

from sklearn_gpca._jobs import map_jobs


def _threads(_):
    """The most threads any loaded BLAS or OpenMP library may use."""
    return max((pool["num_threads"] for pool in threadpool_info()), default=1)


def _square(x):
    return x * x


@pytest.mark.parametrize("n_jobs", [None, 1, 2])
def test_results_come_in_the_order_of_the_items(n_jobs):
    assert map_jobs(_square, range(5), n_jobs) == [0, 1, 4, 9, 16]


@pytest.mark.parametrize("n_jobs", [None, 2])
def test_every_call_runs_with_one_thread(n_jobs):
    # as if the machine gave this process, and each worker, two threads: the
    # calls must not see them (another number of threads sums in another
    # order, and a close choice downstream moves tracks between n_jobs=1 and
    # 2); without inner_max_num_threads a 2-core machine's workers would get
    # one thread whatever map_jobs does
    with threadpool_limits(limits=2), parallel_config("loky", inner_max_num_threads=2):
        assert map_jobs(_threads, range(3), n_jobs) == [1, 1, 1]
