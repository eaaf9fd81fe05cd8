"""paper_pipeline is Algorithm 1 of Vidal & Hartley (CVPR 2004), and only that."""

# SPDX-License-Identifier: BSD-3-Clause

from itertools import combinations_with_replacement

import numpy as np
import pytest
from numpy.testing import assert_allclose
from sklearn.base import clone
from sklearn.cluster import KMeans
from sklearn.metrics import adjusted_rand_score

from sklearn_gpca import GPCAClustering, PowerFactorization, paper_pipeline
from sklearn_gpca.datasets import make_motions

# The paper's settings, with where Algorithm 1 says so.
PAPER_POWER_FACTORIZATION = dict(
    n_components=5,  # step 1: "project the data onto a five-dimensional space"
    whiten=True,  # step 1: the points are the columns of W^ (rows of V)
    solver="als",  # section 2.1: PowerFactorization, alternating least squares
    completion_rank=None,  # the rank-5 fit itself, no separate completion
    n_init=1,  # one random start
    max_init_samples=None,  # on all the trajectories
)
PAPER_GPCA = dict(
    normalize=False,  # the points w_i as projected, not scaled
    point_normals="one_polynomial",  # step 3: Dp(w_i) of the one polynomial
    affinity="all_pairs",  # step 3: S_ij for all i, j = 1 .. P
    affinity_power=1,  # S_ij = cos^2(theta_ij)
    refine=False,  # nothing after the spectral clustering
)


def test_paper_pipeline_has_exactly_the_paper_settings():
    pipeline = paper_pipeline(3, random_state=7)
    (_, pf), (_, gpca) = pipeline.steps
    assert type(pf) is PowerFactorization and type(gpca) is GPCAClustering
    pf_params, gpca_params = pf.get_params(), gpca.get_params()
    for name, value in PAPER_POWER_FACTORIZATION.items():
        assert pf_params[name] == value, name
    for name, value in PAPER_GPCA.items():
        assert gpca_params[name] == value, name
    assert gpca_params["n_clusters"] == 3
    assert pf_params["random_state"] == gpca_params["random_state"] == 7
    # every other parameter keeps its default; none of them acts on this route
    defaults = GPCAClustering().get_params()
    others = set(defaults) - set(PAPER_GPCA) - {"n_clusters", "random_state"}
    assert {name: gpca_params[name] for name in others} == {
        name: defaults[name] for name in others
    }


def _monomials(points, degree):
    """Columns of W~ (section 2.2.2), by brute force."""
    exponents = np.array(
        [
            np.bincount(combo, minlength=points.shape[1])
            for combo in combinations_with_replacement(range(points.shape[1]), degree)
        ]
    )
    return np.prod(points[:, None, :] ** exponents, axis=2), exponents


def _algorithm_1_steps_2_3(points, n_clusters):
    """Steps 2 and 3 written from the paper: the null vector c of W~, the unit
    gradients Dp(w_i), S = cos^2 of their angles, spectral clustering."""
    embedded, exponents = _monomials(points, n_clusters)
    c = np.linalg.svd(embedded, full_matrices=False)[2][-1]
    gradients = np.zeros_like(points)
    for k in range(points.shape[1]):
        lowered = exponents.copy()
        lowered[:, k] -= 1
        terms = np.prod(points[:, None, :] ** np.maximum(lowered, 0), axis=2)
        gradients[:, k] = terms @ (c * exponents[:, k])
    normals = gradients / np.linalg.norm(gradients, axis=1, keepdims=True)
    similarity = (normals @ normals.T) ** 2
    # Ng, Jordan & Weiss [21]: leading eigenvectors of D^-1/2 S D^-1/2, unit
    # rows, k-means (rotation invariant, so any eigenbasis gives the same)
    scale = 1 / np.sqrt(similarity.sum(axis=1))
    vectors = np.linalg.eigh(similarity * scale[:, None] * scale)[1][:, -n_clusters:]
    vectors /= np.linalg.norm(vectors, axis=1, keepdims=True)
    labels = KMeans(n_clusters, n_init=10, random_state=0).fit_predict(vectors)
    return normals, labels


@pytest.mark.parametrize("n_motions", [2, 3])
def test_paper_pipeline_computes_algorithm_1(n_motions):
    X, _ = make_motions(n_motions, n_points=60, n_frames=8, random_state=n_motions)
    pipeline = paper_pipeline(n_motions, random_state=0).fit(X)
    points = clone(pipeline[0]).fit_transform(X)
    normals, labels = _algorithm_1_steps_2_3(points, n_motions)
    gpca = pipeline[-1]
    # the same normals (up to sign) and the same segmentation
    assert_allclose(
        np.abs(np.sum(gpca.point_normals_ * normals, axis=1)), 1.0, atol=1e-6
    )
    assert adjusted_rand_score(labels, gpca.labels_) == 1.0
    assert gpca.n_iter_ == 0


@pytest.mark.parametrize(
    "name, value",
    [
        ("normalize", True),
        ("point_normals", "local"),
        ("affinity", "nearest_neighbors"),
        ("refine", True),
    ],
)
def test_leaving_a_paper_setting_is_seen(name, value):
    """Each of the paper's GPCA settings changes what the fit computes."""
    X, _ = make_motions(3, n_points=60, n_frames=8, random_state=3)
    paper = paper_pipeline(3, random_state=0).fit(X)
    changed = clone(paper).set_params(**{f"gpcaclustering__{name}": value})
    if name == "affinity":
        changed.set_params(gpcaclustering__affinity_power=4)
    changed.fit(X)
    same_normals = np.allclose(
        np.abs(np.sum(paper[-1].point_normals_ * changed[-1].point_normals_, axis=1)),
        1.0,
        atol=1e-6,
    )
    same_labels = adjusted_rand_score(paper[-1].labels_, changed[-1].labels_) == 1.0
    assert not (same_normals and same_labels and changed[-1].n_iter_ == 0)
