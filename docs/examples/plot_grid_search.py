"""
=====================================================
Choosing the number of motions and the rank
=====================================================

:class:`~sklearn.model_selection.GridSearchCV` over ``gpcaclustering__n_clusters`` and
``powerfactorization__n_components``. Without ground truth the pipeline's own
``score`` (``GPCAClustering.score``: a penalised log-likelihood of the sine
distances of held-out trajectories to the fitted subspaces) selects the
model; with ground truth the
:data:`~sklearn_gpca.metrics.misclassification_scorer` can (it uses
``predict`` on the held-out folds). Both pick three motions here.
"""

# SPDX-License-Identifier: BSD-3-Clause

import warnings

import matplotlib.pyplot as plt
import numpy as np
from sklearn.model_selection import GridSearchCV, KFold
from sklearn.pipeline import make_pipeline

from sklearn_gpca import GPCAClustering, PowerFactorization
from sklearn_gpca.datasets import make_motions
from sklearn_gpca.metrics import misclassification_scorer

X, y = make_motions(3, n_points=[100, 100, 100], n_frames=8, random_state=0)
pipeline = make_pipeline(
    PowerFactorization(random_state=0), GPCAClustering(random_state=0)
)
grid = {
    "gpcaclustering__n_clusters": [2, 3, 4],
    "powerfactorization__n_components": [4, 5],
}
cv = KFold(3, shuffle=True, random_state=0)

with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    unsupervised = GridSearchCV(pipeline, grid, cv=cv).fit(X)
    supervised = GridSearchCV(pipeline, grid, cv=cv, scoring=misclassification_scorer)
    supervised.fit(X, y)
print("score (no labels):", unsupervised.best_params_)
print("misclassification_scorer:", supervised.best_params_)

# %%
# Mean cross-validated score of every cell of the grid.
fig, axes = plt.subplots(1, 2, figsize=(11, 4))
for ax, search, title in [
    (axes[0], unsupervised, "GPCAClustering.score"),
    (axes[1], supervised, "- misclassification rate"),
]:
    scores = search.cv_results_["mean_test_score"].reshape(
        len(grid["gpcaclustering__n_clusters"]),
        len(grid["powerfactorization__n_components"]),
    )
    image = ax.imshow(scores, cmap="viridis")
    ax.set_xticks(range(2), grid["powerfactorization__n_components"])
    ax.set_yticks(range(3), grid["gpcaclustering__n_clusters"])
    ax.set_xlabel("rank (n_components)")
    ax.set_ylabel("n_clusters")
    ax.set_title(title)
    best = np.unravel_index(np.argmax(scores), scores.shape)
    ax.scatter(best[1], best[0], marker="*", color="red", s=200)
    fig.colorbar(image, ax=ax)
fig.tight_layout()
plt.show()
