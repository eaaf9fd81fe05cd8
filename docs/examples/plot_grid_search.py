"""
=====================================================
Choosing the number of motions and the rank
=====================================================

Without ground truth, :class:`~sklearn.model_selection.GridSearchCV` over
``gpcaclustering__n_clusters`` selects by the pipeline's own ``score``:
``GPCAClustering.score`` is minus the lossy coding length per trajectory of
the held-out trajectories segmented by ``predict``
(:func:`~sklearn_gpca.coding_length_cost`), the criterion of
``n_clusters="auto"`` and :class:`~sklearn_gpca.NClustersSearch`. It is
measured on the projected points, so it compares numbers of motions at one
rank. On this draw of three motions the held-out folds prefer two and the
training data (``NClustersSearch``) three: segmenting held-out points by the
nearest fitted subspace is a weaker test than the fit itself. With ground
truth the :data:`~sklearn_gpca.metrics.misclassification_scorer` (it uses
``predict`` on the held-out folds) can also choose the rank.
"""

# SPDX-License-Identifier: BSD-3-Clause

import warnings

import matplotlib.pyplot as plt
import numpy as np
from sklearn.model_selection import GridSearchCV, KFold
from sklearn.pipeline import make_pipeline

from sklearn_gpca import GPCAClustering, NClustersSearch, PowerFactorization
from sklearn_gpca.datasets import make_motions
from sklearn_gpca.metrics import misclassification_scorer

X, y = make_motions(3, n_points=[100, 100, 100], n_frames=8, random_state=0)
pipeline = make_pipeline(
    PowerFactorization(random_state=0), GPCAClustering(random_state=0)
)
n_clusters = [2, 3, 4]
grid = {
    "gpcaclustering__n_clusters": n_clusters,
    "powerfactorization__n_components": [4, 5],
}
cv = KFold(3, shuffle=True, random_state=0)

with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    unsupervised = GridSearchCV(
        pipeline, {"gpcaclustering__n_clusters": n_clusters}, cv=cv
    ).fit(X)
    search = NClustersSearch(pipeline, n_clusters_grid=n_clusters).fit(X)
    supervised = GridSearchCV(pipeline, grid, cv=cv, scoring=misclassification_scorer)
    supervised.fit(X, y)
print("score (no labels), held out:", unsupervised.best_params_)
print("NClustersSearch (no labels):", search.best_n_clusters_)
print("misclassification_scorer:", supervised.best_params_)

# %%
# The criterion against the number of motions, and the supervised grid.
fig, axes = plt.subplots(1, 2, figsize=(11, 4))
axes[0].plot(
    n_clusters, -unsupervised.cv_results_["mean_test_score"], "o-", label="held out"
)
axes[0].plot(n_clusters, search.costs_ / X.shape[0], "s--", label="training")
axes[0].set_xticks(n_clusters)
axes[0].set_xlabel("n_clusters")
axes[0].set_ylabel("coding length (bits per trajectory)")
axes[0].legend()
scores = supervised.cv_results_["mean_test_score"].reshape(len(n_clusters), 2)
image = axes[1].imshow(scores, cmap="viridis")
axes[1].set_xticks(range(2), grid["powerfactorization__n_components"])
axes[1].set_yticks(range(3), n_clusters)
axes[1].set_xlabel("rank (n_components)")
axes[1].set_ylabel("n_clusters")
axes[1].set_title("- misclassification rate")
best = np.unravel_index(np.argmax(scores), scores.shape)
axes[1].scatter(best[1], best[0], marker="*", color="red", s=200)
fig.colorbar(image, ax=axes[1])
fig.tight_layout()
plt.show()
