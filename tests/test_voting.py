"""Tests for the randomized-voting runs and the vote-graph selection."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose, assert_array_equal
from sklearn.pipeline import make_pipeline

from sklearn_gpca import GPCAClustering, PowerFactorization
from sklearn_gpca._affinity import normalized_cut, sign_invariant_neighbors
from sklearn_gpca._selection import select_candidate
from sklearn_gpca._spectral import spectral_clustering_lowrank
from sklearn_gpca._voting import (
    _nearest,
    _scatters,
    vote_confidence,
    vote_cut,
    vote_features,
    voting_runs,
)
from sklearn_gpca.datasets import load_hopkins155, make_missing, make_motions
from sklearn_gpca.metrics import misclassification_rate


def three_hyperplanes(n_per=80, noise=1e-3, seed=0):
    """Unit points on three random hyperplanes of R^5 and their labels.

    Points within a sine of 0.1 of another hyperplane (near an intersection,
    where the label is a guess) are left out.
    """
    rng = np.random.RandomState(seed)
    bases = [np.linalg.qr(rng.randn(5, 4))[0] for _ in range(3)]
    X = np.vstack([rng.randn(n_per, 4) @ B.T for B in bases])
    X += noise * rng.randn(*X.shape)
    X /= np.linalg.norm(X, axis=1, keepdims=True)
    y = np.repeat([0, 1, 2], n_per)
    sines = np.stack([np.linalg.norm(X - X @ B @ B.T, axis=1) for B in bases], 1)
    sines[np.arange(y.size), y] = np.inf
    keep = sines.min(axis=1) >= 0.1
    return X[keep], y[keep]


def merged_labels(y):
    """Motions 0 and 1 in one group, motion 2 cut in two halves."""
    half = np.arange(y.size) % 2
    return np.where(y < 2, 0, 1 + half)


def test_nearest_matches_loop_over_runs():
    rng = np.random.RandomState(0)
    unit = rng.randn(50, 5)
    unit /= np.linalg.norm(unit, axis=1, keepdims=True)
    # 7 runs, 3 subspaces of codimension 2 each
    normals = np.linalg.qr(rng.randn(7, 3, 5, 2))[0]
    expected = np.stack(
        [
            np.argmin(
                [np.sum((unit @ normals[r, k]) ** 2, axis=1) for k in range(3)],
                axis=0,
            )
            for r in range(7)
        ],
        axis=1,
    )
    assert_array_equal(_nearest(unit, normals), expected)


def test_scatters_sum_each_runs_clusters():
    rng = np.random.RandomState(1)
    unit = rng.randn(30, 4)
    labels = rng.randint(3, size=(30, 5))
    outer = (unit[:, :, None] * unit[:, None, :]).reshape(30, -1)
    scatter, counts = _scatters(outer, labels, 3)
    for r in range(5):
        for k in range(3):
            members = unit[labels[:, r] == k]
            assert_allclose(scatter[r, k], members.T @ members, atol=1e-12)
            assert counts[r, k] == members.shape[0]


def test_vote_cut_equals_cut_of_dense_vote_matrix():
    """The low-rank formula gives the normalised cut of ``V = B B^T``."""
    rng = np.random.RandomState(2)
    runs = rng.randint(3, size=(40, 6))
    features = vote_features(runs, 3)
    dense = features @ features.T
    # V_ij counts the runs that put i and j together
    assert_array_equal(dense, (runs[:, None, :] == runs[None, :, :]).sum(axis=2))
    labels = rng.randint(3, size=40)
    assert_allclose(
        vote_cut(features, labels, 3),
        normalized_cut(sp.csr_matrix(dense), labels, 3),
        rtol=1e-12,
    )


def test_vote_cut_empty_cluster_is_inf():
    features = vote_features(np.zeros((5, 2), dtype=int), 2)
    assert vote_cut(features, np.zeros(5, dtype=int), 2) == np.inf


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**16), permutation=st.permutations([0, 1, 2]))
def test_vote_cut_ignores_label_names(seed, permutation):
    rng = np.random.RandomState(seed)
    runs = rng.randint(3, size=(30, 4))
    labels = np.r_[0, 1, 2, rng.randint(3, size=27)]
    features = vote_features(runs, 3)
    renamed = np.asarray(permutation)[labels]
    assert_allclose(
        vote_cut(features, renamed, 3), vote_cut(features, labels, 3), rtol=1e-12
    )
    # so do the runs' own label names
    shuffled = vote_features(np.asarray(permutation)[runs], 3)
    assert_allclose(
        vote_cut(shuffled, labels, 3), vote_cut(features, labels, 3), rtol=1e-12
    )


def test_vote_graph_recovers_hyperplanes():
    """Spectral clustering of the vote matrix finds the three hyperplanes."""
    unit, y = three_hyperplanes()
    neighbors = sign_invariant_neighbors(unit, 10)
    runs = voting_runs(
        unit,
        3,
        neighbors,
        n_runs=50,
        dim=4,
        n_iter=5,
        random_state=np.random.RandomState(0),
    )
    assert runs.shape == (y.size, 50)
    assert runs.min() >= 0 and runs.max() <= 2
    labels = spectral_clustering_lowrank(vote_features(runs, 3), 3, random_state=0)
    assert misclassification_rate(y, labels) == 0.0


def test_voting_runs_with_fewer_neighbours_than_dim():
    """Samples are clipped to the neighbours there are; runs still label all."""
    unit, y = three_hyperplanes(n_per=20)
    neighbors = sign_invariant_neighbors(unit, 1)
    runs = voting_runs(
        unit,
        3,
        neighbors,
        n_runs=4,
        dim=4,
        n_iter=2,
        random_state=np.random.RandomState(0),
    )
    assert runs.shape == (y.size, 4)
    assert set(np.unique(runs)) <= {0, 1, 2}


def test_vote_cut_prefers_truth_over_merged_candidate():
    """On the vote graph the truth cuts less than merging two hyperplanes and
    splitting the third; with the vote cut the selection keeps the truth where
    a kNN graph built to favour the merged candidate would not."""
    unit, y = three_hyperplanes()
    merged = merged_labels(y)
    runs = voting_runs(
        unit,
        3,
        sign_invariant_neighbors(unit, 10),
        n_runs=50,
        dim=4,
        n_iter=5,
        random_state=np.random.RandomState(0),
    )
    features = vote_features(runs, 3)
    vote_cuts = [vote_cut(features, c, 3) for c in (merged, y)]
    assert vote_cuts[1] < vote_cuts[0]
    # a local graph that joins the points of the true groups and, a little
    # more, those of the merged labelling: it prefers the merged candidate
    same = [(c[:, None] == c[None, :]).astype(float) for c in (y, merged)]
    graph = sp.csr_matrix(same[0] + 1.2 * same[1])
    common = dict(graph=graph, subspace_dim=4, subspace_dim_tol=0.05, fit_gate=np.inf)
    chosen, cuts, _ = select_candidate(unit, [merged, y], 3, **common)
    assert chosen == 0 and cuts[0] < cuts[1] < cuts[0] + vote_cuts[0] - vote_cuts[1]
    chosen = select_candidate(unit, [merged, y], 3, vote_cuts=vote_cuts, **common)
    assert chosen[0] == 1


def test_default_pipeline_vote_cut_prefers_truth_on_motions():
    """A derived draw: three synthetic motions through PowerFactorization; the
    fitted model's votes cut the true motions less than a merged labelling."""
    X, y = make_motions(3, n_points=60, n_frames=8, noise=0.5, random_state=0)
    model = make_pipeline(
        PowerFactorization(random_state=0), GPCAClustering(3, random_state=0)
    ).fit(X)
    Z = model[0].transform(X)
    unit = Z / np.linalg.norm(Z, axis=1, keepdims=True)
    runs = voting_runs(
        unit,
        3,
        sign_invariant_neighbors(unit, 10),
        n_runs=100,
        dim=4,
        n_iter=5,
        random_state=np.random.RandomState(0),
    )
    features = vote_features(runs, 3)
    assert vote_cut(features, y, 3) < vote_cut(features, merged_labels(y), 3)
    assert misclassification_rate(y, model[-1].labels_) < 0.05


def test_selection_uses_both_cuts():
    """``n_votes > 0``: the kept candidate minimises cut + vote cut (times the
    vote graph's confidence with ``vote_weighting="confidence"``) among those
    that fit; ``n_votes=0``: the cut alone, and no vote cuts."""
    unit, _ = three_hyperplanes(n_per=60, noise=1e-2, seed=3)
    voted = GPCAClustering(3, vote_weighting="equal", random_state=0).fit(unit)
    plain = GPCAClustering(3, n_votes=0, random_state=0).fit(unit)
    weighted = GPCAClustering(3, random_state=0).fit(unit)
    weight = weighted.vote_confidence_
    assert 0 < weight <= 1
    assert np.isnan(plain.vote_confidence_) and np.isnan(voted.vote_confidence_)
    for model, score in [
        (voted, voted.candidate_ncuts_ + voted.candidate_vote_cuts_),
        (weighted, weighted.candidate_ncuts_ + weight * weighted.candidate_vote_cuts_),
        (plain, plain.candidate_ncuts_),
    ]:
        residuals = model.candidate_residuals_
        admissible = residuals <= 3 * residuals.min()
        assert admissible[model.chosen_candidate_]
        assert score[model.chosen_candidate_] == score[admissible].min()
    assert np.all((voted.candidate_vote_cuts_ >= 0) & (voted.candidate_vote_cuts_ <= 3))
    assert np.all(np.isnan(plain.candidate_vote_cuts_))
    # the votes are drawn after the candidates: the same refined candidates
    assert_allclose(voted.candidate_ncuts_, plain.candidate_ncuts_)


@pytest.mark.parametrize("n_votes", [-1, 1.5, True, "100"])
def test_n_votes_validated(n_votes):
    X = np.random.RandomState(0).randn(40, 3)
    with pytest.raises(ValueError, match="n_votes"):
        GPCAClustering(2, n_votes=n_votes).fit(X)


def test_vote_cuts_shape_checked():
    unit, y = three_hyperplanes(n_per=10)
    graph = sp.csr_matrix((y[:, None] == y[None, :]).astype(float))
    with pytest.raises(ValueError, match="vote_cuts has shape"):
        select_candidate(
            unit,
            [y, y],
            3,
            graph=graph,
            subspace_dim=4,
            subspace_dim_tol=0.05,
            vote_cuts=[0.1],
        )


def normalized_vote_eigenvalues(runs, n_clusters):
    """Eigenvalues of ``D^{-1/2} V D^{-1/2}`` from the dense vote matrix."""
    same = (runs[:, None, :] == runs[None, :, :]).sum(axis=2).astype(float)
    scale = 1 / np.sqrt(same.sum(axis=1))
    return np.sort(np.linalg.eigvalsh(same * scale[:, None] * scale[None, :]))[::-1]


@pytest.mark.parametrize("n_clusters", [2, 3])
def test_vote_confidence_is_mean_of_normalized_eigenvalues(n_clusters):
    rng = np.random.RandomState(n_clusters)
    truth = rng.randint(n_clusters, size=50)
    runs = np.where(
        rng.rand(50, 12) < 0.3, rng.randint(n_clusters, size=(50, 12)), truth[:, None]
    )
    values = normalized_vote_eigenvalues(runs, n_clusters)
    assert_allclose(values[0], 1.0)
    assert_allclose(
        vote_confidence(vote_features(runs, n_clusters), n_clusters),
        values[1:n_clusters].mean(),
    )


def svd_vote_confidence(features, n_clusters):
    """The definition: mean of the squared singular values 2 .. n of
    ``D^{-1/2} B`` (eigenvalues of the normalised vote matrix)."""
    degrees = features @ features.sum(axis=0)
    scaled = features / np.sqrt(degrees)[:, None]
    values = np.linalg.svd(scaled, compute_uv=False)[:n_clusters] ** 2
    return float(np.clip(values[1:].mean(), 0.0, 1.0))


@settings(max_examples=40, deadline=None)
@given(
    n_points=st.integers(4, 60),
    n_runs=st.integers(2, 30),
    n_clusters=st.integers(2, 5),
    agreement=st.floats(0.0, 1.0),
    seed=st.integers(0, 2**16),
)
def test_vote_confidence_equals_svd_definition(
    n_points, n_runs, n_clusters, agreement, seed
):
    """The top eigenvalues of the smaller Gram matrix (either side of
    ``D^{-1/2} B``: more points than run clusters or fewer) equal the squared
    singular values of the definition."""
    rng = np.random.RandomState(seed)
    truth = rng.randint(n_clusters, size=n_points)
    runs = np.where(
        rng.rand(n_points, n_runs) < agreement,
        truth[:, None],
        rng.randint(n_clusters, size=(n_points, n_runs)),
    )
    features = vote_features(runs, n_clusters)
    if n_clusters > min(features.shape):
        return
    assert_allclose(
        vote_confidence(features, n_clusters),
        svd_vote_confidence(features, n_clusters),
        rtol=0,
        atol=1e-10,
    )


def test_vote_confidence_bounds_every_vote_cut():
    """No labelling cuts the vote graph below ``(n - 1)(1 - confidence)``
    (spectral relaxation); the runs' consensus cuts it at zero."""
    rng = np.random.RandomState(0)
    consensus = np.repeat([0, 1, 2], 20)
    runs = np.where(
        rng.rand(60, 30) < 0.4, rng.randint(3, size=(60, 30)), consensus[:, None]
    )
    features = vote_features(runs, 3)
    bound = 2 * (1 - vote_confidence(features, 3))
    for labels in [consensus, rng.randint(3, size=60), merged_labels(consensus)]:
        assert vote_cut(features, labels, 3) >= bound - 1e-12
    agreeing = vote_features(np.repeat(consensus[:, None], 30, axis=1), 3)
    assert_allclose(vote_confidence(agreeing, 3), 1.0)
    assert_allclose(vote_cut(agreeing, consensus, 3), 0.0, atol=1e-12)


def test_vote_confidence_low_when_runs_disagree():
    """Runs that split the points independently of each other: the normalised
    vote matrix is 1/R times a sum of R independent rank-one centred parts,
    its second eigenvalue about (1 + sqrt(R / P))^2 / R = 0.075 here."""
    runs = np.random.RandomState(0).randint(2, size=(400, 20))
    assert vote_confidence(vote_features(runs, 2), 2) < 0.2


def test_vote_confidence_validated():
    features = vote_features(np.array([[0, 1], [1, 0], [0, 0]]), 2)
    with pytest.raises(ValueError, match="n_clusters=1 must be at least 2"):
        vote_confidence(features, 1)
    features[2] = 0
    with pytest.raises(ValueError, match="all-zero rows"):
        vote_confidence(features, 2)


def test_confidence_keeps_clean_knn_cut_over_uncertain_votes():
    """Runs that each cut the points their own way, leaning to a merged
    labelling: its vote cut is a little lower than the truth's. Added as is,
    this outweighs the kNN graph's clean separation of the truth; weighted by
    the vote graph's (low) confidence it does not."""
    unit, y = three_hyperplanes()
    merged = merged_labels(y)
    rng = np.random.RandomState(0)
    # each run keeps the merged label of half the points, the rest at random
    runs = np.where(
        rng.rand(y.size, 100) < 0.5, rng.randint(3, size=(y.size, 100)), merged[:, None]
    )
    features = vote_features(runs, 3)
    vote_cuts = np.array([vote_cut(features, c, 3) for c in (merged, y)])
    confidence = vote_confidence(features, 3)
    assert confidence < 0.3
    # a graph joining the points of the true groups and, less, those of the
    # merged labelling: it prefers the truth
    same = [(c[:, None] == c[None, :]).astype(float) for c in (y, merged)]
    graph = sp.csr_matrix(same[0] + 0.8 * same[1])
    common = dict(
        graph=graph,
        subspace_dim=4,
        subspace_dim_tol=0.05,
        fit_gate=np.inf,
        vote_cuts=vote_cuts,
    )
    _, cuts, _ = select_candidate(unit, [merged, y], 3, **common)
    # the merged labelling wins on the votes by more than it loses on the graph
    assert (
        vote_cuts[1] - vote_cuts[0]
        > cuts[0] - cuts[1]
        > confidence * (vote_cuts[1] - vote_cuts[0])
    )
    assert select_candidate(unit, [merged, y], 3, vote_weight=1.0, **common)[0] == 0
    assert (
        select_candidate(unit, [merged, y], 3, vote_weight=confidence, **common)[0] == 1
    )


@pytest.mark.parametrize("weight", [-0.1, 1.5, np.nan, np.inf])
def test_vote_weight_validated(weight):
    unit, y = three_hyperplanes(n_per=10)
    graph = sp.csr_matrix((y[:, None] == y[None, :]).astype(float))
    with pytest.raises(ValueError, match=r"vote_weight=.* must be a number in"):
        select_candidate(
            unit,
            [y, y],
            3,
            graph=graph,
            subspace_dim=4,
            subspace_dim_tol=0.05,
            vote_cuts=[0.1, 0.2],
            vote_weight=weight,
        )


def test_occluded_sequence_kept_by_the_knn_cut(hopkins155_dir):
    """Hopkins155 2T3RCRTP_g13 with 30 % occlusion (bench_occlusion.py's
    mask): no voting run finds the small motion, and the runs split the large
    one each their own way (confidence ~0.39). The equal-weight vote cut keeps
    a candidate with 27 % error; weighted by the confidence (the default), the
    kNN cut's clean separation of the truth wins."""
    sequence = load_hopkins155(hopkins155_dir, sequences="2T3RCRTP_g13")[0]
    X = make_missing(sequence.X, 0.3, random_state=0)
    Z = PowerFactorization(random_state=0).fit_transform(X)
    default = GPCAClustering(2, random_state=0).fit(Z)
    equal = GPCAClustering(2, vote_weighting="equal", random_state=0).fit(Z)
    errors = [misclassification_rate(sequence.y, m.labels_) for m in (default, equal)]
    assert default.vote_confidence_ < 0.5
    assert errors[0] < 0.01 < 0.2 < errors[1]


@pytest.mark.parametrize("weighting", ["votes", 1.0, None])
def test_vote_weighting_validated(weighting):
    X = np.random.RandomState(0).randn(40, 3)
    with pytest.raises(ValueError, match="vote_weighting"):
        GPCAClustering(2, vote_weighting=weighting).fit(X)
