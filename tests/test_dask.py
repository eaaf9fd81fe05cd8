"""Grid searches and large fits on a Dask cluster through joblib's backend.

``distributed`` is in the ``test`` extra. These tests are skipped where it is
absent, except in CI (``CI`` set), where a missing install is an error: they
must run there.
"""

# SPDX-License-Identifier: BSD-3-Clause

import os

import joblib
import numpy as np
import pytest
from sklearn.model_selection import GridSearchCV, KFold
from sklearn.pipeline import make_pipeline

from sklearn_gpca import GPCAClustering, PowerFactorization
from sklearn_gpca.datasets import make_motions
from sklearn_gpca.metrics import misclassification_scorer

try:
    import distributed
except ImportError:
    if os.environ.get("CI"):
        raise
    pytest.skip("distributed is not installed", allow_module_level=True)


@pytest.fixture(scope="module")
def client():
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as dask_client,
    ):
        yield dask_client


def grid_search():
    return GridSearchCV(
        make_pipeline(
            PowerFactorization(random_state=0), GPCAClustering(2, random_state=0)
        ),
        {"gpcaclustering__n_clusters": [2, 3]},
        scoring=misclassification_scorer,
        cv=KFold(3, shuffle=True, random_state=0),
        n_jobs=-1,
    )


def test_grid_search_dask_backend(client):
    X, y = make_motions(2, n_points=[60, 60], n_frames=8, noise=0.5, random_state=0)
    with joblib.parallel_config(backend="dask"):
        search = grid_search().fit(X, y)
    reference = grid_search().fit(X, y)  # default (loky) backend

    assert search.best_params_["gpcaclustering__n_clusters"] == 2
    assert search.best_params_ == reference.best_params_
    for key in ("split0_test_score", "split1_test_score", "split2_test_score"):
        np.testing.assert_allclose(search.cv_results_[key], reference.cv_results_[key])
    np.testing.assert_array_equal(
        search.best_estimator_[-1].labels_, reference.best_estimator_[-1].labels_
    )


def test_large_fit_dask_backend(client):
    X, _ = make_motions(2, n_points=[3000, 3000], n_frames=8, noise=0.5, random_state=0)
    points = PowerFactorization(random_state=0).fit_transform(X)
    expected = GPCAClustering(2, random_state=0).fit(points).labels_
    with joblib.parallel_config(backend="dask"):
        labels = GPCAClustering(2, n_jobs=-1, random_state=0).fit(points).labels_
    np.testing.assert_array_equal(labels, expected)
