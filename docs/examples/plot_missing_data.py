"""
=============================================
Segmentation error against missing data
=============================================

Occlusions remove contiguous runs of frames from each track
(:func:`sklearn_gpca.datasets.make_missing` with ``pattern="occlusion"``).
:class:`~sklearn_gpca.plotting.ErrorCurveDisplay` refits the pipeline on
masks removing a growing fraction of the point-frames (two masks per
fraction) and draws the mean misclassification rate with its range; the
default pipeline is compared with the paper's algorithm and with mean
imputation in front of the default GPCA.
"""

# SPDX-License-Identifier: BSD-3-Clause

import warnings

import matplotlib.pyplot as plt
from sklearn.impute import SimpleImputer
from sklearn.pipeline import make_pipeline

from sklearn_gpca import GPCAClustering, PowerFactorization, paper_pipeline
from sklearn_gpca.datasets import make_motions
from sklearn_gpca.plotting import ErrorCurveDisplay

X, y = make_motions(2, n_points=[60, 60], n_frames=8, noise=1.0, random_state=0)
fractions = [0.0, 0.1, 0.2, 0.3, 0.4]

models = {
    "PowerFactorization + GPCA (default)": make_pipeline(
        PowerFactorization(random_state=0), GPCAClustering(2, random_state=0)
    ),
    "paper_pipeline": paper_pipeline(2, random_state=0),
    "mean imputation + SVD + GPCA": make_pipeline(
        SimpleImputer(), PowerFactorization(random_state=0), GPCAClustering(2)
    ),
}

fig, ax = plt.subplots(figsize=(10, 4.5), layout="constrained")
with warnings.catch_warnings():
    warnings.simplefilter("ignore")  # ConvergenceWarning on heavy occlusion
    for name, model in models.items():
        display = ErrorCurveDisplay.from_estimator(
            model,
            X,
            y,
            param_name="missing_fraction",
            param_values=fractions,
            n_repeats=2,
            random_state=0,
            name=name,
            ax=ax,
        )
        print(f"{name}: {display.errors.mean(axis=1).round(3)}")
ax.set_title("Two motions, 120 tracks, 8 frames, occlusions")
# beside the curves, not over them
ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1), fontsize=9)
plt.show()
