r"""
============================================
Segmenting synthetic motions with a pipeline
============================================

Three rigid bodies seen by an affine camera over 10 frames, a fifth of the
point-frames lost to occlusions. ``make_pipeline(PowerFactorization(),
GPCAClustering(3))`` projects the incomplete trajectories onto
:math:`\mathbb{R}^5` and segments them; the left panel shows the tracks
coloured by the segmentation (crosses mark the misclassified ones), the right
panel the same points in the first three projected coordinates, where every
motion is a linear subspace through the origin.
"""

# SPDX-License-Identifier: BSD-3-Clause

import matplotlib.pyplot as plt
import numpy as np
from sklearn.pipeline import make_pipeline

from sklearn_gpca import GPCAClustering, PowerFactorization
from sklearn_gpca.datasets import make_motions
from sklearn_gpca.metrics import misclassification_rate
from sklearn_gpca.plotting import TrajectoryDisplay

X, y = make_motions(
    3,
    n_points=[100, 100, 100],
    n_frames=10,
    noise=1.0,
    missing=0.2,
    missing_pattern="occlusion",
    random_state=0,
)
print(f"X: {X.shape}, {100 * np.isnan(X).mean():.0f} % missing")

pipeline = make_pipeline(
    PowerFactorization(random_state=0), GPCAClustering(3, random_state=0)
)
labels = pipeline.fit_predict(X)
print(f"misclassification rate: {misclassification_rate(y, labels):.3f}")

# %%
# The tracks, and the projected points on the unit sphere.
fig = plt.figure(figsize=(11, 4.5))
ax = fig.add_subplot(1, 2, 1)
TrajectoryDisplay.from_predictions(X, labels, y_true=y, ax=ax, title="Tracks")

Z = pipeline[0].transform(X)
Z = Z / np.linalg.norm(Z, axis=1, keepdims=True)
ax3d = fig.add_subplot(1, 2, 2, projection="3d")
# coloured by true motion: the colours of the tracks on the left
for k in range(3):
    ax3d.scatter(*Z[y == k, :3].T, s=6, label=f"motion {k}")
ax3d.set_title("Projected trajectories by true motion\n(first 3 of 5 coordinates)")
ax3d.legend(fontsize="small")
plt.show()
