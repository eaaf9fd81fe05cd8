"""GPCAClustering's vote cut on tracker-like draws with missing entries.

Run from the project root (a few minutes)::

    python benchmarks/check_vote_cut_tracks.py --seeds 8

``make_tracks`` hand-held (3 motions, 40 frames, 50 % missing) and lab
(2 motions, 30 frames, 40 % missing) draws, outlier-free, the tracks seen in
at least 3 frames; ``PowerFactorization(random_state=0)`` then
``GPCAClustering(n, random_state=0)`` with the default vote cut
(``n_votes=100`` weighted by the vote graph's confidence), without it
(``n_votes=0``) and with ``vote_weighting="equal"``. Prints the
misclassification (%) per draw and the mean per scene.
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import warnings

import numpy as np

from sklearn_gpca import GPCAClustering, PowerFactorization
from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.metrics import misclassification_rate

SCENES = {
    "hand-held": {"scene": "handheld", "n_frames": 40, "missing": 0.5},
    "lab": {"scene": "lab", "n_motions": 2, "n_frames": 30, "missing": 0.4},
}
RULES = {
    "confidence-weighted vote cut (default)": {},
    "n_votes=0": {"n_votes": 0},
    "vote_weighting='equal'": {"vote_weighting": "equal"},
}


def errors(X, y):
    """Error (%) of each rule on one draw."""
    seen = (~np.isnan(X)).sum(axis=1) >= 6
    X, y = X[seen & (y >= 0)], y[seen & (y >= 0)]
    n = len(np.unique(y))
    Z = PowerFactorization(random_state=0).fit_transform(X)
    return [
        100
        * misclassification_rate(
            y, GPCAClustering(n, random_state=0, **rule).fit_predict(Z)
        )
        for rule in RULES.values()
    ]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=8)
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    print("| scene | seed | " + " | ".join(RULES) + " |")
    print("|---|---|" + "---|" * len(RULES))
    for scene, kwargs in SCENES.items():
        table = []
        for seed in range(args.seeds):
            X, y = make_tracks(random_state=seed, **kwargs)[:2]
            table.append(errors(X, y))
            cells = " | ".join(f"{e:.1f}" for e in table[-1])
            print(f"| {scene} | {seed} | {cells} |", flush=True)
        means = " | ".join(f"**{e:.1f}**" for e in np.mean(table, axis=0))
        print(f"| {scene} | mean | {means} |")


if __name__ == "__main__":
    main()
