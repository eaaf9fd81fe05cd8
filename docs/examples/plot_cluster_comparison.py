"""
=====================================================
Comparing GPCA with scikit-learn's clusterers
=====================================================

In the style of scikit-learn's ``plot_cluster_comparison.py``: every estimator
is a drop-in clusterer fitted on the same trajectories, timed, and scored by
the adjusted Rand index (ARI) and the misclassification rate (optimal label
matching with :func:`scipy.optimize.linear_sum_assignment`). The data are one
Hopkins155 sequence of each category (checkerboard, traffic, articulated)
when the data are found (``$SKLEARN_GPCA_DATA`` or ``../shared/data``), else
synthetic independent, partially dependent and degenerate motions. (The
synthetic bodies sit apart in the image, which already lets the generic
clusterers separate them by position; on real sequences the motions overlap.)

Generic clusterers look for blobs or density; motions are **linear
subspaces** through the origin, which a trajectory far from the camera centre
and one near it share. Note that centring the data or a ``StandardScaler``
would turn these linear subspaces into *affine* ones, so no scaler is used in
front of GPCA (the others see the raw trajectories too). The generic
clusterers need complete data; the datasets here have none missing.
"""

# SPDX-License-Identifier: BSD-3-Clause

import os
import time
import warnings
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from sklearn.cluster import HDBSCAN, AgglomerativeClustering, KMeans, SpectralClustering
from sklearn.metrics import adjusted_rand_score
from sklearn.mixture import GaussianMixture
from sklearn.pipeline import make_pipeline

from sklearn_gpca import GPCAClustering, PowerFactorization
from sklearn_gpca.datasets import load_hopkins155, make_motions
from sklearn_gpca.metrics import misclassification_rate
from sklearn_gpca.plotting import TrajectoryDisplay


def find_hopkins155():
    """``$SKLEARN_GPCA_DATA/hopkins155``, else ``../shared/data/hopkins155``."""
    candidates = []
    if os.environ.get("SKLEARN_GPCA_DATA"):
        candidates.append(Path(os.environ["SKLEARN_GPCA_DATA"]) / "hopkins155")
    here = Path.cwd().resolve()
    for folder in (here, *here.parents):
        if (folder / "pyproject.toml").is_file():
            candidates.append(folder.parent / "shared" / "data" / "hopkins155")
            break
    return next((c for c in candidates if c.is_dir()), None)


folder = find_hopkins155()
if folder is not None:
    # One sequence of each Hopkins155 category.
    datasets = {
        f"{seq.name} ({seq.category})": (seq.X, seq.y)
        for seq in load_hopkins155(
            folder, sequences=["1R2RCT_A", "cars3", "two_cranes"]
        )
    }
else:
    datasets = {
        "independent": make_motions(
            3, n_points=[100, 100, 100], n_frames=8, random_state=0
        ),
        "dependent (rotation)": make_motions(
            3,
            n_points=[100, 100, 100],
            n_frames=8,
            dependent="rotation",
            random_state=1,
        ),
        "degenerate": make_motions(
            3,
            n_points=[100, 100, 100],
            n_frames=8,
            motion_types=["full", "planar", "linear"],
            random_state=2,
        ),
    }


def estimators(n):
    return [
        ("KMeans", KMeans(n, n_init=10, random_state=0)),
        (
            "SpectralClustering",
            SpectralClustering(n, affinity="nearest_neighbors", random_state=0),
        ),
        ("Agglomerative (ward)", AgglomerativeClustering(n)),
        ("GaussianMixture", GaussianMixture(n, random_state=0)),
        ("HDBSCAN", HDBSCAN(min_cluster_size=15)),
        (
            "PowerFactorization + GPCA",
            make_pipeline(
                PowerFactorization(random_state=0), GPCAClustering(n, random_state=0)
            ),
        ),
    ]


fig, axes = plt.subplots(
    len(datasets), 6, figsize=(18, 3 * len(datasets)), squeeze=False
)
rows = []
for i, (data_name, (X, y)) in enumerate(datasets.items()):
    n = len(np.unique(y))
    for j, (name, estimator) in enumerate(estimators(n)):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            start = time.perf_counter()
            estimator.fit(X)
            seconds = time.perf_counter() - start
        if hasattr(estimator, "labels_"):
            labels = estimator.labels_
        elif hasattr(estimator, "steps"):
            labels = estimator[-1].labels_
        else:
            labels = estimator.predict(X)
        labels = np.asarray(labels)
        ari = adjusted_rand_score(y, labels)
        error = misclassification_rate(y, labels)
        rows.append((data_name, name, ari, error, seconds))
        ax = axes[i, j]
        TrajectoryDisplay.from_predictions(X, labels, ax=ax, legend=False)
        ax.set(xticks=[], yticks=[], xlabel="", ylabel="")
        ax.set_aspect("auto")
        ax.text(
            0.99,
            0.01,
            f"ARI {ari:.2f}  err {100 * error:.0f}%  {seconds:.2f}s",
            transform=ax.transAxes,
            ha="right",
            fontsize=8,
        )
        if i == 0:
            ax.set_title(name, fontsize=10)
        if j == 0:
            ax.set_ylabel(data_name)
fig.tight_layout()
plt.show()

# %%
# The scores as a table.
print(f"{'data':<28}{'method':<28}{'ARI':>6}{'error %':>9}{'time s':>8}")
for data_name, name, ari, error, seconds in rows:
    print(f"{data_name:<28}{name:<28}{ari:6.2f}{100 * error:9.1f}{seconds:8.3f}")
