"""Memory is estimated before it is asked for (issue 13)."""

# SPDX-License-Identifier: BSD-3-Clause

import tracemalloc

import numpy as np
import pytest
from sklearn import config_context

from sklearn_gpca import GPCAClustering, gpca
from sklearn_gpca._affinity import normal_affinity_graph, sign_invariant_neighbors
from sklearn_gpca._memory import gpca_memory, physical_memory
from sklearn_gpca._normals import local_normal_bases


def _peak_bytes(function, *args, **kwargs):
    tracemalloc.start()
    try:
        function(*args, **kwargs)
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


@pytest.mark.skipif(physical_memory() is None, reason="memory size unknown")
def test_too_large_a_veronese_embedding_is_refused_before_allocation():
    """50 features, 4 clusters: C(53, 4) = 292,825 monomials, whose Gram matrix
    alone is 686 GB; the fit used to ask for 143 GiB at once."""
    X = np.random.RandomState(0).standard_normal((300_000, 50))
    tracemalloc.start()
    try:
        with pytest.raises(ValueError, match=r"292825 x 292825 Gram .*n_components=5"):
            GPCAClustering(4).fit(X)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 4 * X.nbytes  # the validated copy of X, nothing more


def test_graph_edges_are_weighted_within_working_memory():
    """5,100 points of R^100: the edge features once took 150,000 x 5,050
    floats (6 GB) twice; in chunks the temporaries follow working_memory."""
    rng = np.random.RandomState(0)
    unit = rng.standard_normal((1500, 40))
    unit /= np.linalg.norm(unit, axis=1, keepdims=True)
    neighbors = sign_invariant_neighbors(unit, 30)
    bases, codims = local_normal_bases(unit, neighbors[:, :10], 0.05)
    edge_features = 2 * 1500 * 30 * (40 * 41 // 2) * 8  # the unchunked temporaries
    with config_context(working_memory=8):
        small = normal_affinity_graph(bases, codims, neighbors, 4)
        peak = _peak_bytes(normal_affinity_graph, bases, codims, neighbors, 4)
    full = normal_affinity_graph(bases, codims, neighbors, 4)
    assert peak < edge_features / 4
    assert abs(small - full).max() == 0.0


def test_estimate_bounds_the_arrays_of_a_fit():
    rng = np.random.RandomState(0)
    bases = [np.linalg.qr(rng.standard_normal((12, 11)))[0] for _ in range(2)]
    X = np.vstack([rng.standard_normal((600, 11)) @ B.T for B in bases])
    params = dict(
        affinity="nearest_neighbors",
        max_spectral_samples=5000,
        point_normals="local",
        n_neighbors=30,
    )
    estimate = sum(gpca_memory(*X.shape, 2, params).values())
    assert _peak_bytes(gpca, X, 2, random_state=0) <= estimate
