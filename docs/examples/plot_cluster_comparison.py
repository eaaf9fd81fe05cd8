"""
=====================================================
Comparing GPCA with scikit-learn's clusterers
=====================================================

In the style of scikit-learn's ``plot_cluster_comparison.py``: every estimator
is a drop-in clusterer fitted on the same trajectories, timed, and scored by
the misclassification rate (optimal label matching with
:func:`scipy.optimize.linear_sum_assignment`) and the adjusted Rand index
(ARI). The data are one Hopkins155 sequence of each category (checkerboard,
traffic, articulated) when the data are found (``$SKLEARN_GPCA_DATA`` or
``../shared/data``), else synthetic independent, partially dependent and
degenerate motions.

Generic clusterers look for blobs or density; motions are **linear
subspaces** through the origin, which a trajectory far from the camera centre
and one near it share. Centring the data or a
:class:`~sklearn.preprocessing.StandardScaler` would turn these linear
subspaces into *affine* ones, so no scaler is used in front of GPCA (the
others see the raw trajectories too). The generic clusterers need complete
data; the sequences here have none missing.
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

GPCA = "PowerFactorization + GPCA"


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
            GPCA,
            make_pipeline(
                PowerFactorization(random_state=0), GPCAClustering(n, random_state=0)
            ),
        ),
    ]


def fit_labels(estimator, X):
    """Fit, time and return the labels of any of the clusterers above."""
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
    return np.asarray(labels), seconds


scores = {}
labels_of = {}
for data_name, (X, y) in datasets.items():
    n = len(np.unique(y))
    for name, estimator in estimators(n):
        labels, seconds = fit_labels(estimator, X)
        labels_of[data_name, name] = labels
        scores[data_name, name] = (
            100 * misclassification_rate(y, labels),
            adjusted_rand_score(y, labels),
            seconds,
        )

# %%
# The segmentations
# -----------------
#
# One row per sequence: the ground truth, then two generic clusterers and the
# default pipeline. Colours are matched to the ground truth (optimal
# assignment), so a track whose colour differs from the truth column is
# misclassified; crosses mark those tracks.

SHOWN = ["KMeans", "SpectralClustering", GPCA]

for data_name, (X, y) in datasets.items():
    fig, axes = plt.subplots(1, 1 + len(SHOWN), figsize=(12, 3.6))
    TrajectoryDisplay.from_predictions(X, y, ax=axes[0], legend=False)
    axes[0].set_title(f"{data_name}\nground truth", fontsize=11)
    for ax, name in zip(axes[1:], SHOWN, strict=True):
        TrajectoryDisplay.from_predictions(
            X, labels_of[data_name, name], y_true=y, ax=ax, legend=False
        )
        error, ari, _ = scores[data_name, name]
        ax.set_title(f"{name}\nerror {error:.1f} %, ARI {ari:.2f}", fontsize=11)
    for ax in axes:
        ax.set(xticks=[], yticks=[], xlabel="", ylabel="")
    fig.tight_layout()
plt.show()

# %%
# All the scores
# --------------
#
# The misclassification rate (%), the ARI and the fit time of every clusterer
# on every sequence; the last line of each block says whether a generic
# clusterer beat the default pipeline.

for data_name in datasets:
    print(data_name)
    print(f"  {'method':<28}{'error %':>9}{'ARI':>7}{'time s':>8}")
    for name, _ in estimators(2):
        error, ari, seconds = scores[data_name, name]
        print(f"  {name:<28}{error:9.1f}{ari:7.2f}{seconds:8.3f}")
    best = min(
        (scores[data_name, name][0], name) for name, _ in estimators(2) if name != GPCA
    )
    ours = scores[data_name, GPCA][0]
    verdict = "beats" if best[0] < ours else "does not beat"
    print(f"  best generic clusterer ({best[1]}, {best[0]:.1f} %) {verdict} GPCA\n")

# %%
# Where the default pipeline loses, and why
# -----------------------------------------
#
# On the checkerboard and traffic sequences every motion spans its own
# subspace: the default pipeline misclassifies at most a few tracks, while
# the generic clusterers split the scene by position and cut through the
# motions. On the articulated sequence ``two_cranes`` it is the other way
# round: the generic clusterers do better than the default pipeline. Its
# three groups (55, 17 and 22 tracks over 30 frames) move together. The
# singular values below show it: for the whole trajectory matrix of
# ``two_cranes`` the fourth is a third of a per cent of the first, against a
# few per cent on the other two sequences, so its three motions together span
# about the dimensions of a single rigid motion. Their subspaces nearly
# coincide in :math:`\mathbb{R}^5`, so the normals that GPCA compares are
# alike for tracks of different motions. The groups are, however, far apart
# in the image, and position is all that KMeans or a nearest-neighbour graph
# need. Articulated sequences are the Hopkins155 category where the default
# pipeline's mean error is highest, though over the whole category the
# generic clusterers still do worse (see :ref:`benchmarks`).


def relative_singular_values(X, k=5):
    s = np.linalg.svd(X, compute_uv=False)
    return "  ".join(f"{v:.4f}" for v in s[:k] / s[0])


for data_name, (X, y) in datasets.items():
    print(data_name)
    print(f"  all tracks  {relative_singular_values(X)}")
    for k in np.unique(y):
        print(f"  motion {k}    {relative_singular_values(X[y == k])}")
