"""
=====================================================
Figure 1: trajectories coloured by their segmentation
=====================================================

The paper's Figure 1 shows a sequence with its tracked points coloured by
motion. Here a real Hopkins155 sequence (``1R2RCT_A``, three motions) is
segmented by the default pipeline and by the paper's algorithm
(:func:`sklearn_gpca.paper_pipeline`); crosses mark misclassified tracks. The
data are looked for in ``$SKLEARN_GPCA_DATA/hopkins155`` and in
``../shared/data/hopkins155`` beside the project; without them the example
falls back to synthetic motions.
"""

# SPDX-License-Identifier: BSD-3-Clause

import os
from pathlib import Path

import matplotlib.pyplot as plt
from sklearn.pipeline import make_pipeline

from sklearn_gpca import GPCAClustering, PowerFactorization, paper_pipeline
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
    sequence = load_hopkins155(folder, sequences="1R2RCT_A")[0]
    X, y, n, title = sequence.X_pixels, sequence.y, sequence.n_motions, sequence.name
else:
    X, y = make_motions(3, n_points=[120, 100, 80], n_frames=20, random_state=0)
    n, title = 3, "synthetic"
print(f"{title}: {X.shape[0]} tracks, {X.shape[1] // 2} frames, {n} motions")

# %%
# Pixel coordinates are used for the picture: the same affine map of every
# frame keeps each motion a linear subspace (its translation is part of M).
fig, axes = plt.subplots(
    1, 2, figsize=(11, 5.2), sharex=True, sharey=True, layout="constrained"
)
models = {
    "default pipeline": make_pipeline(
        PowerFactorization(random_state=0), GPCAClustering(n, random_state=0)
    ),
    "paper_pipeline (Algorithm 1)": paper_pipeline(n, random_state=0),
}
for ax, (name, model) in zip(axes, models.items(), strict=True):
    labels = model.fit_predict(X)
    error = misclassification_rate(y, labels)
    TrajectoryDisplay.from_predictions(
        X, labels, y_true=y, ax=ax, title=f"{name}: {100 * error:.1f} % wrong"
    )
    # below the tracks, not over them
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2, fontsize=9)
fig.suptitle(f"Hopkins155 sequence {title}" if folder else "Synthetic motions")
plt.show()
