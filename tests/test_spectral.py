"""Tests for low-rank spectral clustering."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
import scipy.sparse as sp
from numpy.testing import assert_allclose, assert_array_equal
from scipy.linalg import eigh
from sklearn.cluster import KMeans, SpectralClustering
from sklearn.metrics import adjusted_rand_score
from threadpoolctl import threadpool_info, threadpool_limits

from sklearn_gpca import _spectral
from sklearn_gpca._spectral import (
    _shift_invert_eigenpairs,
    embedding_kmeans,
    leading_eigenvectors,
    lowrank_eigenvectors,
    normal_subspace_features,
    spectral_clustering_lowrank,
)


def spectral_embedding_lowrank(features, n_components):
    """Ng-Jordan-Weiss embedding of ``features @ features.T``: unit rows."""
    vectors = lowrank_eigenvectors(features, n_components)
    norms = np.linalg.norm(vectors, axis=1, keepdims=True)
    return vectors / np.maximum(norms, np.finfo(float).tiny)


def spectral_embedding_dense(affinity, n_components):
    """Dense reference: leading eigenvectors of ``D^{-1/2} S D^{-1/2}``, unit rows."""
    inv_sqrt = 1.0 / np.sqrt(affinity.sum(axis=1))
    _, vectors = eigh(affinity * inv_sqrt[:, None] * inv_sqrt[None, :])
    vectors = vectors[:, ::-1][:, :n_components]
    return vectors / np.linalg.norm(vectors, axis=1, keepdims=True)


def spectral_clustering_dense(affinity, n_clusters, random_state):
    """Dense reference of spectral_clustering_lowrank (eigh, then k-means)."""
    embedding = spectral_embedding_dense(affinity, n_clusters)
    kmeans = KMeans(n_clusters=n_clusters, n_init=10, random_state=random_state)
    return kmeans.fit_predict(embedding)


def _noisy_normals(n_features, n_clusters, n_per_cluster, noise, seed):
    rng = np.random.RandomState(seed)
    centres = rng.randn(n_clusters, n_features)
    normals = np.repeat(centres, n_per_cluster, axis=0)
    normals += noise * rng.randn(*normals.shape)
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    return normals, np.repeat(np.arange(n_clusters), n_per_cluster)


@pytest.mark.parametrize("n_features", [2, 3, 5])
def test_features_give_squared_cosines(n_features):
    normals, _ = _noisy_normals(n_features, 3, 5, 0.3, seed=0)
    phi = normal_subspace_features(normals)
    assert phi.shape == (15, n_features * (n_features + 1) // 2)
    assert_allclose(phi @ phi.T, (normals @ normals.T) ** 2, atol=1e-12)


def test_features_of_bases_give_projector_traces():
    rng = np.random.RandomState(1)
    bases = np.stack([np.linalg.qr(rng.randn(5, 2))[0] for _ in range(6)])
    projectors = np.einsum("pij,pkj->pik", bases, bases)
    phi = normal_subspace_features(bases)
    expected = np.einsum("pij,qji->pq", projectors, projectors)
    assert_allclose(phi @ phi.T, expected, atol=1e-12)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_lowrank_matches_dense_route(seed):
    normals, _ = _noisy_normals(5, 3, 30, 0.4, seed=seed)
    phi = normal_subspace_features(normals)
    affinity = phi @ phi.T
    # the embeddings span the same space (up to a rotation of the columns)
    low = spectral_embedding_lowrank(phi, 3)
    dense = spectral_embedding_dense(affinity, 3)
    assert_allclose(low @ low.T, dense @ dense.T, atol=1e-8)
    labels_low = spectral_clustering_lowrank(phi, 3, random_state=0)
    labels_dense = spectral_clustering_dense(affinity, 3, random_state=0)
    assert adjusted_rand_score(labels_low, labels_dense) == 1.0


def test_agrees_with_sklearn_spectral_clustering():
    normals, truth = _noisy_normals(4, 3, 40, 0.05, seed=3)
    phi = normal_subspace_features(normals)
    labels = spectral_clustering_lowrank(phi, 3, random_state=0)
    reference = SpectralClustering(
        n_clusters=3, affinity="precomputed", random_state=0
    ).fit_predict(phi @ phi.T)
    assert adjusted_rand_score(labels, reference) == 1.0
    assert adjusted_rand_score(labels, truth) == 1.0


def test_single_cluster_and_isolated_points():
    normals, _ = _noisy_normals(3, 2, 5, 0.1, seed=4)
    phi = normal_subspace_features(normals)
    assert np.all(spectral_clustering_lowrank(phi, 1) == 0)
    phi[0] = 0.0  # zero degree: embedded at the origin, still labelled
    embedding = spectral_embedding_lowrank(phi, 2)
    assert np.all(np.isfinite(embedding))
    assert_allclose(embedding[0], 0.0)


def test_more_clusters_than_rank():
    # K=2 gives a rank-3 affinity; asking for 4 clusters keeps 3 eigenvectors
    angles = np.repeat(np.linspace(0, np.pi, 4, endpoint=False), 5)
    normals = np.column_stack([np.cos(angles), np.sin(angles)])
    phi = normal_subspace_features(normals)
    assert spectral_embedding_lowrank(phi, 4).shape == (20, 3)
    labels = spectral_clustering_lowrank(phi, 4, random_state=0)
    assert adjusted_rand_score(labels, np.repeat(np.arange(4), 5)) == 1.0


def _openmp_threads():
    return [i["num_threads"] for i in threadpool_info() if i["user_api"] == "openmp"]


def test_kmeans_runs_with_one_openmp_thread(monkeypatch):
    # k-means on a small embedding: one OpenMP thread, whatever the pool outside
    if not _openmp_threads():
        pytest.skip("no OpenMP runtime loaded")
    seen = []
    kmeans_labels = _spectral.kmeans_labels

    def recording_kmeans_labels(*args, **kwargs):
        seen.extend(_openmp_threads())
        return kmeans_labels(*args, **kwargs)

    monkeypatch.setattr(_spectral, "kmeans_labels", recording_kmeans_labels)
    vectors = np.repeat(np.eye(2), 5, axis=0)
    with threadpool_limits(2, user_api="openmp"):
        labels = embedding_kmeans(vectors, 2, n_init=2, random_state=0)
        assert set(_openmp_threads()) == {2}  # restored afterwards
    assert seen and set(seen) == {1}
    assert adjusted_rand_score(np.repeat([0, 1], 5), labels) == 1.0


def _block_graph(sizes, cross, seed, n_isolated=0):
    """Sparse symmetric affinity: random blocks, weak cross edges, isolated
    points at the end; and its normalised dense matrix D^{-1/2} A D^{-1/2}."""
    rng = np.random.RandomState(seed)
    labels = np.repeat(np.arange(len(sizes)), sizes)
    same = labels[:, None] == labels[None, :]
    A = rng.uniform(0.2, 1.0, same.shape) * (same + cross * ~same)
    A *= rng.uniform(size=A.shape) < 0.3  # sparse
    A = np.triu(A, 1)
    A = np.pad(A + A.T, (0, n_isolated))
    degrees = A.sum(axis=1)
    inv_sqrt = np.where(degrees > 0, 1 / np.sqrt(np.maximum(degrees, 1e-300)), 0.0)
    return sp.csr_matrix(A), A * inv_sqrt[:, None] * inv_sqrt


def _route(monkeypatch, route):
    """Force the dense shift-invert route (and check that it is the one
    taken) or the sparse Lanczos route."""
    limit = {"dense": 10**9, "sparse": 0}[route]
    monkeypatch.setattr(_spectral, "DENSE_EIGEN_SAMPLES", limit)
    if route == "dense":

        def no_lanczos(*args):
            raise AssertionError("the shift-invert route fell back to Lanczos")

        monkeypatch.setattr(_spectral, "_lanczos_eigenpairs", no_lanczos)


@pytest.mark.parametrize("route", ["dense", "sparse"])
@pytest.mark.parametrize("seed", [0, 1])
def test_leading_eigenvectors_match_dense_eigh(monkeypatch, route, seed):
    _route(monkeypatch, route)
    affinity, normalized = _block_graph([40, 30, 50, 20], 0.02, seed, n_isolated=2)
    vectors = leading_eigenvectors(affinity, 3, np.random.RandomState(seed))
    values, reference = np.linalg.eigh(normalized)
    reference = reference[:, ::-1][:, :3]
    reference[-2:] = 0.0  # isolated points: zero rows
    assert vectors.shape == (142, 3)
    # same leading m-spaces, m = 1, 2, 3 (eigenvalues distinct here)
    assert np.min(np.diff(values[::-1][:4]) ** 2) > 1e-6
    for m in (1, 2, 3):
        assert_allclose(
            vectors[:, :m] @ vectors[:, :m].T,
            reference[:, :m] @ reference[:, :m].T,
            atol=1e-8,
        )


@pytest.mark.parametrize("route", ["dense", "sparse"])
def test_leading_eigenvectors_of_disconnected_graph(monkeypatch, route):
    # five components: eigenvalue 1 five times, any 3 of its vectors will do
    _route(monkeypatch, route)
    affinity, normalized = _block_graph([20, 25, 30, 15, 20], 0.0, seed=2)
    vectors = leading_eigenvectors(affinity, 3, np.random.RandomState(0))
    assert_allclose(normalized @ vectors, vectors, atol=1e-8)
    assert_allclose(vectors.T @ vectors, np.eye(3), atol=1e-8)


def test_leading_eigenvectors_routes_draw_the_same_numbers(monkeypatch):
    # later draws of the caller's generator (k-means seeds) do not depend on
    # the route: both draw exactly the Lanczos start vector
    affinity, _ = _block_graph([30, 30], 0.05, seed=3)
    states = []
    for route in ("dense", "sparse"):
        with monkeypatch.context() as patch:
            _route(patch, route)
            random_state = np.random.RandomState(0)
            leading_eigenvectors(affinity, 2, random_state)
            states.append(random_state.uniform(size=3))
    expected = np.random.RandomState(0)
    expected.uniform(-1, 1, 60)
    assert_array_equal(states[0], states[1])
    assert_array_equal(states[0], expected.uniform(size=3))


def test_shift_invert_falls_back_to_lanczos(monkeypatch):
    affinity, normalized = _block_graph([40, 30, 50], 0.02, seed=4)
    start = np.random.RandomState(0).uniform(-1, 1, 120)
    # a shift inside the spectrum: sigma I - M is indefinite, no Cholesky factor
    monkeypatch.setattr(_spectral, "_SHIFT", -0.5)
    assert _shift_invert_eigenpairs(normalized.copy(), 3, start) is None
    monkeypatch.setattr(_spectral, "DENSE_EIGEN_SAMPLES", 10**9)
    vectors = leading_eigenvectors(affinity, 3, np.random.RandomState(0))
    reference = np.linalg.eigh(normalized)[1][:, ::-1][:, :3]
    assert_allclose(vectors @ vectors.T, reference @ reference.T, atol=1e-8)


def test_shift_invert_runs_with_one_blas_thread(monkeypatch):
    if not [i for i in threadpool_info() if i["user_api"] == "blas"]:
        pytest.skip("no BLAS found by threadpoolctl")
    seen = []
    shift_invert = _spectral._shift_invert_eigenpairs

    def recording(*args):
        seen.extend(
            i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"
        )
        return shift_invert(*args)

    monkeypatch.setattr(_spectral, "_shift_invert_eigenpairs", recording)
    affinity, _ = _block_graph([30, 30], 0.05, seed=5)
    with threadpool_limits(2, user_api="blas"):
        leading_eigenvectors(affinity, 2, np.random.RandomState(0))
        assert {
            i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"
        } == {2}
    assert seen and set(seen) == {1}
