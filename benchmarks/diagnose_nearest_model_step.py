"""Would one "nearest model" step help the consistency rule? A diagnosis.

On one ``make_tracks`` draw (outlier tracks removed), ``segment_motions(X,
n, random_state=0, return_info=True)``; for each of its refined candidates
(on the tracks the screening keeps), prints its error and its penalised fit
under ``selection="consistency"`` (the fit plus ``MISFIT_COST`` per track
nearer another group's model), then the same for the candidate moved one
step: every track to its nearest group model
(``oracle_labels(X, labels, perspective_background=True)``, the largest
group a perspective camera, the others 4-D subspaces). Also the truth's and
the perspective oracle's penalised fit, and which candidate the rule keeps
with and without the stepped ones. Exploratory (5 Dec 2026: the rule keeps
degenerate small groups after the step; see
``benchmarks/results/history_tracker_output.md``).

Usage::

    python benchmarks/diagnose_nearest_model_step.py --scene driving --seed 3 \
        --tracks 500
    python benchmarks/diagnose_nearest_model_step.py --scene handheld --seed 4 \
        --tracks 3200
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import warnings

import numpy as np

from sklearn_gpca import segment_motions
from sklearn_gpca._model_consistency import model_consistency
from sklearn_gpca._segment import MISFIT_COST, _scaled_tracks
from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.metrics import misclassification_rate, oracle_labels

#: Keywords of make_tracks per scene (those of check_track_count.py).
SCENES = {
    "driving": {"scene": "driving"},
    "handheld": {"scene": "handheld", "n_frames": 40, "missing": 0.5},
    "lab": {"scene": "lab"},
}


def penalised_fit(X0, mask, labels, noise):
    """The consistency rule's score of one segmentation (lower is kept)."""
    inconsistency, fit = model_consistency(X0, mask, labels, noise)[:2]
    return fit + MISFIT_COST * inconsistency * labels.size


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", choices=sorted(SCENES), default="driving")
    parser.add_argument("--seed", type=int, default=3)
    parser.add_argument("--tracks", type=int, default=500)
    args = parser.parse_args(argv)
    X, y = make_tracks(
        n_tracks=args.tracks, random_state=args.seed, **SCENES[args.scene]
    )[:2]
    X, y = X[y >= 0], y[y >= 0]
    n = np.unique(y).size
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        _, info = segment_motions(X, n, random_state=0, return_info=True)
        kept = ~info.outliers
        Xk, yk = X[kept], y[kept]
        X0, mask, _ = _scaled_tracks(Xk)
        scores = np.asarray(info.residuals) + MISFIT_COST * np.asarray(
            info.inconsistency
        ) * np.count_nonzero(kept)
        errors = [100 * misclassification_rate(yk, labels) for labels in info.refined]
        stepped_scores, stepped_errors = [], []
        print("candidate | error % | score | stepped error % | score | group sizes")
        for k, labels in enumerate(info.refined):
            stepped = oracle_labels(Xk, labels, perspective_background=True)
            sizes = np.bincount(stepped, minlength=n)
            score = np.inf  # a stepped candidate that lost a group is not judged
            if sizes.all():
                score = penalised_fit(X0, mask, stepped, info.noise)
            stepped_scores.append(score)
            stepped_errors.append(100 * misclassification_rate(yk, stepped))
            print(
                f"{info.candidates[k]} | {errors[k]:.1f} | {scores[k]:.0f} | "
                f"{stepped_errors[-1]:.1f} | {score:.0f} | {sizes}",
                flush=True,
            )
        for name, labels in (
            ("truth", yk),
            ("perspective oracle", oracle_labels(Xk, yk, perspective_background=True)),
        ):
            print(
                f"{name}: error {100 * misclassification_rate(yk, labels):.1f} %, "
                f"score {penalised_fit(X0, mask, labels, info.noise):.0f}"
            )
    kept_alone = int(np.argmin(scores))
    both = np.r_[scores, stepped_scores]
    with_steps = int(np.argmin(both))
    print(
        f"kept by the rule: {errors[kept_alone]:.1f} %; with the stepped "
        f"candidates: {np.r_[errors, stepped_errors][with_steps]:.1f} % "
        f"({'stepped' if with_steps >= len(errors) else 'unstepped'})"
    )


if __name__ == "__main__":
    main()
