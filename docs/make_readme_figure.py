"""Draw the README's picture: ``docs/_static/segmentation.png``.

Run from anywhere (needs matplotlib)::

    python docs/make_readme_figure.py

Segments the Hopkins155 sequence ``1R2RCT_A`` (three motions; looked for in
``$SKLEARN_GPCA_DATA/hopkins155`` or ``../shared/data/hopkins155`` beside the
project) with ``make_pipeline(PowerFactorization(), GPCAClustering(3))`` and
draws its tracks coloured by the segmentation (colours matched to the true
motions), beside the GPCA similarity with rows and columns ordered by true
motion, in the legend's order. Without the data it uses synthetic motions.
"""

# SPDX-License-Identifier: BSD-3-Clause

import os
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from sklearn.pipeline import make_pipeline

from sklearn_gpca import GPCAClustering, PowerFactorization
from sklearn_gpca.datasets import load_hopkins155, make_motions
from sklearn_gpca.metrics import misclassification_rate
from sklearn_gpca.plotting import SimilarityMatrixDisplay, TrajectoryDisplay

ROOT = Path(__file__).resolve().parents[1]
OUTPUT = ROOT / "docs" / "_static" / "segmentation.png"
SEQUENCE = "1R2RCT_A"


def load():
    env = os.environ.get("SKLEARN_GPCA_DATA")
    base = Path(env) if env else ROOT.parent / "shared" / "data"
    folder = base / "hopkins155"
    if folder.is_dir():
        seq = load_hopkins155(folder, sequences=SEQUENCE)[0]
        return seq.X_pixels, seq.y, seq.n_motions, f"Hopkins155 {seq.name}"
    X, y = make_motions(3, n_points=[120, 100, 80], n_frames=20, random_state=0)
    return X, y, 3, "synthetic motions"


def main():
    X, y, n, title = load()
    pipeline = make_pipeline(
        PowerFactorization(random_state=0), GPCAClustering(n, random_state=0)
    )
    labels = pipeline.fit_predict(X)
    error = misclassification_rate(y, labels)
    fig, (left, right) = plt.subplots(
        1, 2, figsize=(10, 4.2), gridspec_kw={"width_ratios": [1.4, 1]}
    )
    TrajectoryDisplay.from_predictions(
        X,
        labels,
        y_true=y,
        ax=left,
        title=f"{title}: {X.shape[0]} tracks, {X.shape[1] // 2} frames,\n"
        f"{100 * error:.1f} % misclassified",
    )
    # ordered by the true motion, as the legend on the left
    SimilarityMatrixDisplay.from_estimator(
        pipeline,
        y=y,
        ax=right,
        title="GPCA similarity cos²,\nrows and columns by true motion",
    )
    fig.tight_layout()
    OUTPUT.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(OUTPUT, dpi=80)
    print(f"wrote {OUTPUT.relative_to(ROOT)} ({title}, error {100 * error:.2f} %)")


if __name__ == "__main__":
    main()
