"""One thread for the hot loops that run many small computations.

Thread pools pay off on large BLAS calls and large k-means problems. The
library's hot loops run thousands of small ones (the solvers' factorisations,
k-means on a few thousand rows of two or three eigenvectors), where a second
thread only adds synchronisation, and, on a machine whose cores are busy,
waits at every barrier for a thread the system has not scheduled: several
times to a hundred times slower (``benchmarks/results/frames.md`` and
``benchmarks/results/occlusion.md`` measure both ways). Limited as
scikit-learn limits the BLAS threads inside ``KMeans``, with ``threadpoolctl``.
"""

# SPDX-License-Identifier: BSD-3-Clause

import functools

from threadpoolctl import ThreadpoolController


@functools.cache
def threadpool_controller():
    """The process's ``ThreadpoolController``, built once (it scans the
    loaded libraries)."""
    return ThreadpoolController()


def one_thread(user_api):
    """Context manager running its block with one thread of ``user_api``
    (``"blas"`` or ``"openmp"``)."""
    return threadpool_controller().limit(limits=1, user_api=user_api)
