"""Tests for the sparse nearest-neighbour affinities and graph utilities."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
import scipy.sparse as sp
from numpy.testing import assert_allclose, assert_array_equal
from sklearn.neighbors import NearestNeighbors

from sklearn_gpca._affinity import (
    _between_cluster_weights,
    _kneighbors,
    merge_clusters,
    normal_affinity_graph,
    normalized_cut,
    sign_invariant_neighbors,
)
from sklearn_gpca._normals import local_normal_bases
from sklearn_gpca._spectral import leading_eigenvectors


def unit(X):
    return X / np.linalg.norm(X, axis=1, keepdims=True)


def spectral_embedding_sparse(affinity, n_components, random_state):
    """Ng-Jordan-Weiss embedding: leading eigenvectors with unit rows."""
    vectors = leading_eigenvectors(affinity, n_components, random_state)
    return vectors / np.linalg.norm(vectors, axis=1, keepdims=True)


def two_blocks(sizes, rng, cross=0.0):
    """Random symmetric affinity with dense blocks and weak cross edges."""
    n = sum(sizes)
    labels = np.repeat(np.arange(len(sizes)), sizes)
    A = rng.uniform(0.5, 1.0, (n, n)) * (labels[:, None] == labels[None, :])
    A += cross * rng.uniform(0, 1, (n, n)) * (labels[:, None] != labels[None, :])
    A = np.triu(A, 1)
    return sp.csr_matrix(A + A.T), labels


def test_sign_invariant_neighbors_ignores_sign():
    rng = np.random.RandomState(0)
    X = unit(rng.randn(50, 4))
    flipped = X * np.where(rng.rand(50) < 0.5, -1.0, 1.0)[:, None]
    assert_array_equal(
        sign_invariant_neighbors(X, 5), sign_invariant_neighbors(flipped, 5)
    )
    assert not np.any(sign_invariant_neighbors(X, 5) == np.arange(50)[:, None])


@pytest.mark.parametrize("dim", [2, 3, 4])
def test_local_normal_bases_span_complement(dim):
    rng = np.random.RandomState(dim)
    basis = np.linalg.qr(rng.randn(5, dim))[0]
    X = unit(rng.randn(80, dim) @ basis.T)
    neighbors = sign_invariant_neighbors(X, 10)
    bases, codims = local_normal_bases(X, neighbors, 0.05)
    assert_array_equal(codims, 5 - dim)
    # every normal direction is orthogonal to the subspace
    assert_allclose(np.einsum("kd,pkc->pdc", basis, bases), 0.0, atol=1e-8)


def test_normal_affinity_graph_weights_are_cos_power():
    rng = np.random.RandomState(1)
    normals = unit(rng.randn(20, 3))
    neighbors = (np.arange(20)[:, None] + np.arange(1, 4)) % 20
    graph = normal_affinity_graph(normals[:, :, None], np.ones(20), neighbors, 2)
    i, j = 0, 2
    assert_allclose(graph[i, j], (normals[i] @ normals[j]) ** 4, rtol=1e-12)
    assert_allclose((graph - graph.T).toarray(), 0.0)


def test_spectral_embedding_separates_blocks():
    rng = np.random.RandomState(2)
    graph, labels = two_blocks([30, 40, 20], rng, cross=0.01)
    embedding = spectral_embedding_sparse(graph, 3, rng)
    assert_allclose(np.linalg.norm(embedding, axis=1), 1.0)
    # rows of one block point the same way
    for k in range(3):
        rows = embedding[labels == k]
        assert np.min(np.abs(rows @ rows[0])) > 0.99


def test_leading_eigenvectors_nested():
    """The first m of m + 1 eigenvectors span the m-eigenvector space."""
    rng = np.random.RandomState(3)
    graph, _ = two_blocks([25, 25, 25], rng, cross=0.05)
    few = leading_eigenvectors(graph, 2, np.random.RandomState(0))
    more = leading_eigenvectors(graph, 3, np.random.RandomState(1))
    overlap = np.linalg.svd(few.T @ more[:, :2], compute_uv=False)
    assert_allclose(overlap, 1.0, atol=1e-6)


def test_normalized_cut_values():
    rng = np.random.RandomState(4)
    graph, labels = two_blocks([10, 15], rng)
    assert normalized_cut(graph, labels, 2) == pytest.approx(0.0)
    mixed = labels.copy()
    mixed[0] = 1
    assert normalized_cut(graph, mixed, 2) > 0.0
    assert normalized_cut(graph, np.zeros(25, np.intp), 2) == np.inf


def test_merge_clusters_joins_split_block():
    rng = np.random.RandomState(5)
    graph, labels = two_blocks([20, 30], rng, cross=0.01)
    over = labels.copy()
    over[:7] = 2  # split the first block in two
    merged = merge_clusters(graph, over, 2)
    assert set(merged) == {0, 1}
    assert_array_equal(merged[:20], merged[0])
    assert merged[0] != merged[-1]


@pytest.mark.parametrize("fmt", ["csr", "csc", "coo"])
def test_between_cluster_weights_sum_the_blocks(fmt):
    rng = np.random.RandomState(6)
    dense = rng.uniform(size=(30, 30)) * (rng.uniform(size=(30, 30)) < 0.2)
    labels = rng.randint(0, 4, 30)
    labels[:4] = np.arange(4)
    expected = np.array(
        [[dense[labels == a][:, labels == b].sum() for b in range(4)] for a in range(4)]
    )
    affinity = sp.csr_matrix(dense).asformat(fmt)
    assert_allclose(_between_cluster_weights(affinity, labels, 4), expected)
    # duplicate entries of a COO matrix add up, as in the matrix they stand for
    halves = sp.coo_matrix(dense / 2)
    doubled = sp.coo_matrix(
        (
            np.tile(halves.data, 2),
            (np.tile(halves.row, 2), np.tile(halves.col, 2)),
        ),
        shape=dense.shape,
    )
    assert_allclose(_between_cluster_weights(doubled, labels, 4), expected)


@pytest.mark.parametrize("n_neighbors", [5, 40, 70])
@pytest.mark.parametrize("n_jobs", [None, 2])
def test_kneighbors_is_nearest_neighbors_search(n_neighbors, n_jobs):
    # 5 and 40 neighbours of 100 points: a KD-tree; 70: brute force
    rng = np.random.RandomState(7)
    points = unit(rng.randn(100, 4))
    points[50:60] = points[:10]  # exact ties
    queries = np.vstack([points[:30], unit(rng.randn(20, 4))])
    search = NearestNeighbors(n_neighbors=n_neighbors).fit(points)
    expected = search.kneighbors(queries)
    found = _kneighbors(points, queries, n_neighbors, n_jobs)
    assert_array_equal(found[1], expected[1])
    assert_array_equal(found[0], expected[0])
