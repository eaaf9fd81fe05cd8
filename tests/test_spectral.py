"""Tests for low-rank spectral clustering."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.linalg import eigh
from sklearn.cluster import KMeans, SpectralClustering
from sklearn.metrics import adjusted_rand_score
from threadpoolctl import threadpool_info, threadpool_limits

from sklearn_gpca import _spectral
from sklearn_gpca._spectral import (
    embedding_kmeans,
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
