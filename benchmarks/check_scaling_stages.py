"""Where the error of the default pipeline comes from on the scaling draws.

For ``make_motions(3, n_points=P, n_frames=10, noise=1.0, missing=0.1,
random_state=seed)`` (the draws of ``bench_scaling.py``), runs the default
``make_pipeline(PowerFactorization(), GPCAClustering(3))`` and measures the
labels after each of ``GPCAClustering``'s stages against the truth: the
graph route on its random subsample of ``max_spectral_samples`` points, the
extension of those labels to all points, and smoothed K-subspaces on all
points in ``R^5`` (the default's output); beside them the two references
(nearest true hyperplane in ``R^5``, nearest true subspace in ``R^{2F}``)
and the full-space steps after the default: :func:`refine_full_space`
(smoothed K-subspaces on 5,000 tracks, neighbours in ``R^5``, then one
smoothed assignment) and :func:`reassign_full_space` with and without its
anchor and refits. Writes ``benchmarks/results/scaling_stages.md``.

Usage::

    python benchmarks/check_scaling_stages.py --sizes 10000 100000 --seeds 0 1 2
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse

import numpy as np
from _tables import markdown_table, write_markdown
from sklearn.pipeline import make_pipeline

from sklearn_gpca import GPCAClustering, PowerFactorization
from sklearn_gpca import _gpca as gpca_module
from sklearn_gpca._subspaces import fit_subspace, sine_residuals
from sklearn_gpca.datasets import make_motions
from sklearn_gpca.metrics import misclassification_rate, oracle_labels
from sklearn_gpca.stages import (
    extend_labels,
    extension_neighbors,
    reassign_full_space,
    refine_full_space,
    unit_rows,
)

COLUMNS = [
    "P",
    "draw",
    "subsample segmentation",
    "extension to all",
    "+ K-subspaces R^5 (default)",
    "nearest true hyperplane R^5",
    "nearest true subspace R^{2F}",
    "+ refine_full_space",
    "+ reassign, no anchor, no refit",
    "+ reassign, anchor 1, no refit",
    "+ reassign, anchor 1, one refit (the earlier default)",
    "+ reassign (anchor 1, two refits without the worst 20 %: the default, "
    "as GPCAClustering(3, segmentation_dim=5, input_subspace_dim=4) on the "
    "raw tracks)",
]


def stage_errors(n, seed):
    sizes = [n - 2 * (n // 3), n // 3, n // 3]
    X, y = make_motions(
        3, n_points=sizes, n_frames=10, noise=1.0, missing=0.1, random_state=seed
    )
    stages = {}
    extend = gpca_module._extend

    def recording_extend(points, unit, polynomials, sample, segmented, bases, p):
        # the labels before and after the extension, then the default's stage 6
        neighbors = extension_neighbors(unit, sample, segmented.local_neighbors)
        stages["sample"] = sample
        stages["segmented"] = segmented.labels.copy()
        stages["extended"] = extend_labels(
            unit, sample, segmented.labels, neighbors, bases, smoothing=p["smoothing"]
        )
        return extend(points, unit, polynomials, sample, segmented, bases, p)

    gpca_module._extend = recording_extend
    try:
        pipe = make_pipeline(
            PowerFactorization(random_state=0), GPCAClustering(3, random_state=0)
        )
        labels = pipe.fit_predict(X)
    finally:
        gpca_module._extend = extend
    unit = unit_rows(pipe[0].transform(X))
    hyperplanes = [fit_subspace(unit[y == k], 4, 0.0) for k in range(3)]
    errors = [
        misclassification_rate(y[stages["sample"]], stages["segmented"])
        if stages
        else np.nan,
        misclassification_rate(y, stages["extended"]) if stages else np.nan,
        misclassification_rate(y, labels),
        misclassification_rate(y, np.argmin(sine_residuals(unit, hyperplanes), axis=1)),
        misclassification_rate(y, oracle_labels(X, y)),
        misclassification_rate(
            y, refine_full_space(X, labels, unit, random_state=0)[0]
        ),
    ]
    for anchor, n_trim, trim_fraction in [
        (0.0, 0, 0.0),
        (1.0, 0, 0.0),
        (1.0, 1, 0.0),
        (1.0, 2, 0.2),
    ]:
        reassigned = reassign_full_space(
            X,
            labels,
            anchor=anchor,
            n_trim=n_trim,
            trim_fraction=trim_fraction,
            random_state=0,
        )[0]
        errors.append(misclassification_rate(y, reassigned))
    return [f"{n:,}", str(seed)] + [f"{100 * e:.2f}" for e in errors]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[10_000, 100_000])
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    parser.add_argument("--out", default="benchmarks/results/scaling_stages.md")
    args = parser.parse_args()
    rows = []
    for n in args.sizes:
        for seed in args.seeds:
            rows.append(stage_errors(n, seed))
            print(" | ".join(rows[-1]), flush=True)
    text = "\n".join(
        [
            "# Where the scaling draws' error comes from",
            "",
            "`python benchmarks/check_scaling_stages.py --sizes "
            + " ".join(map(str, args.sizes))
            + " --seeds "
            + " ".join(map(str, args.seeds))
            + "` (see its docstring). Misclassification (%) of the labels after "
            "each stage of the default pipeline (the subsample's on the "
            "subsample), of the references and of the full-space steps after "
            "the default.",
            "",
            *markdown_table(COLUMNS, rows),
        ]
    )
    write_markdown(args.out, text + "\n")
    print(text)


if __name__ == "__main__":
    main()
