"""PowerFactorization and GPCAClustering composed the scikit-learn way."""

import pickle

import numpy as np
import pytest
from sklearn.base import clone
from sklearn.model_selection import GridSearchCV, KFold
from sklearn.pipeline import make_pipeline

from sklearn_gpca import GPCAClustering, PowerFactorization, paper_pipeline
from sklearn_gpca.datasets import make_motions
from sklearn_gpca.metrics import misclassification_rate, misclassification_scorer


def motions(n_motions, missing=0.2, seed=0, **kwargs):
    params = dict(n_frames=10, noise=0.5, missing_pattern="random", random_state=seed)
    params.update(kwargs)
    return make_motions(n_motions, n_points=[80] * n_motions, missing=missing, **params)


def default_pipeline(n_clusters, seed=0):
    return make_pipeline(
        PowerFactorization(random_state=seed),
        GPCAClustering(n_clusters, random_state=seed),
    )


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("n_motions", [2, 3])
def test_pipeline_segments_motions_with_missing_entries(n_motions, seed):
    X, y = motions(n_motions, seed=seed)
    assert np.isnan(X).mean() == pytest.approx(0.2, abs=0.01)
    labels = default_pipeline(n_motions).fit_predict(X)
    assert misclassification_rate(y, labels) <= 0.05


def test_predict_new_incomplete_trajectories():
    X, y = motions(2, seed=3)
    train, test = np.arange(0, 160, 2), np.arange(1, 160, 2)
    pipeline = default_pipeline(2).fit(X[train])
    assert misclassification_rate(y[test], pipeline.predict(X[test])) <= 0.05


def test_score_set_params_clone_and_pickle():
    X, _ = motions(2)
    pipeline = default_pipeline(2).fit(X)
    assert np.isfinite(pipeline.score(X))
    restored = pickle.loads(pickle.dumps(pipeline))
    np.testing.assert_array_equal(restored.predict(X), pipeline.predict(X))
    changed = clone(pipeline).set_params(
        powerfactorization__n_components=4, gpcaclustering__n_clusters=3
    )
    assert changed.fit(X).named_steps["powerfactorization"].components_.shape[0] == 4
    assert set(changed.named_steps["gpcaclustering"].labels_) == {0, 1, 2}
    assert not hasattr(clone(pipeline).named_steps["gpcaclustering"], "labels_")


@pytest.mark.parametrize(
    "scoring", ["adjusted_rand_score", misclassification_scorer], ids=["ari", "mis"]
)
def test_grid_search_with_labels_finds_the_number_of_motions(scoring):
    X, y = motions(3, missing=0.1, seed=4)
    search = GridSearchCV(
        default_pipeline(2),
        {
            "powerfactorization__n_components": [4, 5],
            "gpcaclustering__n_clusters": [2, 3, 4],
        },
        scoring=scoring,
        cv=KFold(3, shuffle=True, random_state=0),
        n_jobs=2,
    ).fit(X, y)
    assert search.best_params_["gpcaclustering__n_clusters"] == 3


def unsupervised_search(grid, X, **pipeline_params):
    """GridSearchCV without labels: pipelines compared by GPCAClustering.score."""
    return GridSearchCV(
        default_pipeline(2).set_params(**pipeline_params),
        grid,
        cv=KFold(3, shuffle=True, random_state=0),
        error_score="raise",
    ).fit(X)


@pytest.mark.parametrize("seed", [0, 1])
@pytest.mark.parametrize("n_motions", [2, 3])
def test_unsupervised_grid_search_finds_the_number_of_motions(n_motions, seed):
    X, _ = make_motions(
        n_motions, n_points=[60] * n_motions, n_frames=8, noise=0.1, random_state=seed
    )
    search = unsupervised_search({"gpcaclustering__n_clusters": [1, 2, 3, 4]}, X)
    assert search.best_params_["gpcaclustering__n_clusters"] == n_motions


def test_unsupervised_grid_search_finds_the_number_of_motions_with_gaps():
    X, _ = make_motions(
        3,
        n_points=[60] * 3,
        n_frames=8,
        noise=0.1,
        missing=0.1,
        missing_pattern="random",
        random_state=0,
    )
    search = unsupervised_search(
        {"gpcaclustering__n_clusters": [1, 2, 3, 4]},
        X,
        powerfactorization__completion_rank="auto",
    )
    assert search.best_params_["gpcaclustering__n_clusters"] == 3


@pytest.mark.parametrize(
    ("motion_type", "rank"),
    # Each motion spans 4 (full) or 3 (planar) dimensions: projected to one
    # more, the motions are hyperplanes, which GPCAClustering fits exactly.
    [("full", 5), ("planar", 4)],
)
@pytest.mark.parametrize("seed", [0, 1])
def test_unsupervised_grid_search_finds_the_rank(motion_type, rank, seed):
    # Noise-free draws: with noise the penalised score keeps rising with the
    # rank (measured: 0.01 px already picks rank 6 for full motions), so the
    # rank is found by this score only on exact unions of subspaces.
    X, _ = make_motions(
        2,
        n_points=[60, 60],
        n_frames=8,
        noise=0.0,
        motion_types=motion_type,
        random_state=seed,
    )
    search = unsupervised_search(
        {"powerfactorization__n_components": [3, 4, 5, 6]},
        X,
        gpcaclustering__criterion="sine_likelihood",  # comparable across ranks
    )
    assert search.best_params_["powerfactorization__n_components"] == rank


def test_paper_pipeline_is_algorithm_1():
    pipeline = paper_pipeline(3, random_state=0)
    pf, gpca = (step for _, step in pipeline.steps)
    assert isinstance(pf, PowerFactorization) and pf.n_components == 5
    assert isinstance(gpca, GPCAClustering) and gpca.n_clusters == 3
    errors = [
        misclassification_rate(y, paper_pipeline(2, random_state=0).fit_predict(X))
        for X, y in (motions(2, missing=0.0, seed=seed) for seed in range(4))
    ]
    assert np.mean(errors) <= 0.05
