"""Candidate segmentations: spectral clustering of affinity graphs.

A candidate is a labelling of the points into ``n_clusters`` groups. The
candidates of the library come from the graphs between the point normals
(:mod:`sklearn_gpca._affinity`); any other labelling of the same points (e.g.
from subspace hypotheses) can join the list before the refinement and the
selection (:mod:`sklearn_gpca._selection`).
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._affinity import merge_clusters, normal_affinity_graph
from sklearn_gpca._spectral import embedding_kmeans, leading_eigenvectors


def coarse_n_neighbors(n_neighbors):
    """Neighbourhood size of the coarse-scale graph of ``init="multi"``: 1.5 k."""
    return (3 * n_neighbors + 1) // 2


def candidate_graphs(
    normals, neighbors, power, *, coarse=None, gradients=None, multi=True
):
    """The affinity graphs to split, and the graph that selects among them.

    Parameters
    ----------
    normals : tuple of (bases, codims)
        Normal subspace at each point (:func:`~sklearn_gpca._normals.
        point_normal_bases`).
    neighbors : ndarray of shape (n_samples, n_neighbors)
        Nearest neighbours of each point: the edges of the graphs.
    power : int
        Exponent of the weights (:func:`~sklearn_gpca._affinity.
        normal_affinity_graph`).
    coarse : tuple of (bases, codims, neighbors) or None, default=None
        Normals and neighbours at a coarser scale; None skips the coarse graph.
    gradients : ndarray of shape (n_samples, n_features) or None, default=None
        Unit gradients of the fitted polynomial; None when ``normals`` are
        these gradients already.
    multi : bool, default=True
        False: the ``normals`` graph alone, and no selection graph.

    Returns
    -------
    graphs : list of scipy.sparse.csr_matrix
        ``[A]``, or ``[A, A_coarse, A * G]`` with ``A`` the graph of
        ``normals``, ``A_coarse`` the same at the coarse scale (when given)
        and ``G`` the graph of the polynomial's gradients (entrywise product).
    selection_graph : scipy.sparse.csr_matrix or None
        ``G``, on which :func:`~sklearn_gpca._selection.select_candidate`
        compares the candidates; None when ``multi`` is False.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca.stages import (
    ...     unit_rows, sign_invariant_neighbors, point_normal_bases, candidate_graphs)
    >>> rng = np.random.RandomState(0)
    >>> # two planes of R^3: z = 0 and x = 0
    >>> unit = unit_rows(np.vstack([rng.randn(20, 3) * [1, 1, 0],
    ...                             rng.randn(20, 3) * [0, 1, 1]]))
    >>> neighbors = sign_invariant_neighbors(unit, 9)
    >>> normals = point_normal_bases(
    ...     "local", unit, points=unit, polynomials=None, degree=2,
    ...     neighbors=neighbors[:, :3], tol=0.05)
    >>> graphs, selection_graph = candidate_graphs(normals, neighbors, 4, multi=False)
    >>> len(graphs), graphs[0].shape, selection_graph
    (1, (40, 40), None)
    """
    graph = normal_affinity_graph(*normals, neighbors, power)
    if not multi:
        return [graph], None
    if gradients is None:
        selection_graph = graph
    else:
        n_samples = gradients.shape[0]
        selection_graph = normal_affinity_graph(
            gradients[:, :, None], np.ones(n_samples), neighbors, power
        )
    graphs = [graph, graph.multiply(selection_graph).tocsr()]
    if coarse is not None:
        graphs.insert(1, normal_affinity_graph(*coarse, power))
    return graphs, selection_graph


def spectral_candidates(graphs, n_clusters, *, over_segment, n_init, random_state):
    """Spectral clustering of each graph into ``n_clusters`` groups.

    Parameters
    ----------
    graphs : list of scipy.sparse matrix of shape (n_samples, n_samples)
        Symmetric non-negative affinities.
    n_clusters : int
        Number of groups.
    over_segment : bool
        Also split each graph into ``n_clusters + 1`` groups and merge them
        back greedily (:func:`~sklearn_gpca._affinity.merge_clusters`): a
        small subspace that the plain split would share out survives. The
        ``n_clusters + 1`` leading eigenvectors are computed once; their first
        ``n_clusters`` give the plain split.
    n_init : int
        Number of k-means runs on each embedding.
    random_state : RandomState instance
        Lanczos start vectors and k-means seeds.

    Returns
    -------
    candidates : list of ndarray of shape (n_samples,), dtype=intp
        One labelling per graph, or two (plain, then over-segmented and
        merged) with ``over_segment``.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca.stages import (
    ...     unit_rows, sign_invariant_neighbors, point_normal_bases,
    ...     candidate_graphs, spectral_candidates)
    >>> rng = np.random.RandomState(0)
    >>> # two planes of R^3: z = 0 and x = 0
    >>> unit = unit_rows(np.vstack([rng.randn(20, 3) * [1, 1, 0],
    ...                             rng.randn(20, 3) * [0, 1, 1]]))
    >>> neighbors = sign_invariant_neighbors(unit, 9)
    >>> normals = point_normal_bases(
    ...     "local", unit, points=unit, polynomials=None, degree=2,
    ...     neighbors=neighbors[:, :3], tol=0.05)
    >>> graphs, _ = candidate_graphs(normals, neighbors, 4, multi=False)
    >>> candidates = spectral_candidates(
    ...     graphs, 2, over_segment=False, n_init=10,
    ...     random_state=np.random.RandomState(0))
    >>> len(candidates), candidates[0].shape
    (1, (40,))
    """
    kmeans = dict(n_init=n_init, random_state=random_state)
    candidates = []
    for graph in graphs:
        if not over_segment:
            vectors = leading_eigenvectors(graph, n_clusters, random_state)
            candidates.append(embedding_kmeans(vectors, n_clusters, **kmeans))
            continue
        vectors = leading_eigenvectors(graph, n_clusters + 1, random_state)
        split = embedding_kmeans(vectors, n_clusters + 1, **kmeans)
        plain = embedding_kmeans(vectors[:, :n_clusters], n_clusters, **kmeans)
        candidates.append(plain)
        candidates.append(merge_clusters(graph, split, n_clusters))
    return candidates
