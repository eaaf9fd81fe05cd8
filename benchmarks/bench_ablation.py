"""Ablation of GPCAClustering's components on Hopkins155.

Runs ``make_pipeline(PowerFactorization(), GPCAClustering(n, **config))`` on the
155 sequences for each configuration: the paper's Algorithm 1, the library
default, and the default with one component switched off or changed. Reports
mean and median misclassification (%) for two-motion, three-motion and all
sequences and the median wall time per sequence, and writes
``benchmarks/results/ablation.md``.

Usage::

    python benchmarks/bench_ablation.py --data ../shared/data/hopkins155 --jobs 2
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import time
import warnings
from pathlib import Path

import numpy as np
from _tables import write_markdown
from joblib import Parallel, delayed
from sklearn.pipeline import make_pipeline
from threadpoolctl import threadpool_limits

from sklearn_gpca import GPCAClustering, PowerFactorization
from sklearn_gpca.datasets import load_hopkins155
from sklearn_gpca.metrics import misclassification_rate

PAPER = dict(
    normalize=False,
    point_normals="one_polynomial",
    affinity="all_pairs",
    affinity_power=1,
    refine=False,
)

CONFIGS = [
    ("paper (Algorithm 1)", PAPER),
    ("paper + unit sphere", {**PAPER, "normalize": True}),
    (
        "paper + unit sphere + several polynomials (section 2.2.4)",
        {**PAPER, "normalize": True, "point_normals": "all_polynomials"},
    ),
    (
        "paper + unit sphere + K-subspaces",
        {**PAPER, "normalize": True, "refine": True, "smoothing": 0.0},
    ),
    (
        "paper + unit sphere + smoothed K-subspaces",
        {**PAPER, "normalize": True, "refine": True},
    ),
    (
        "polynomial normals, kNN graph, power 4",
        {"point_normals": "one_polynomial", "refine": False, "init": "spectral"},
    ),
    (
        "several polynomials' normals, kNN graph, power 4",
        {"point_normals": "all_polynomials", "refine": False, "init": "spectral"},
    ),
    (
        "local normals, kNN graph, power 1",
        {"affinity_power": 1, "refine": False, "init": "spectral"},
    ),
    ("local normals, kNN graph, power 4", {"refine": False, "init": "spectral"}),
    ("6 spectral inits, ncut selection, no refinement", {"refine": False}),
    ("single spectral init, smoothed K-subspaces", {"init": "spectral"}),
    ("default without smoothing (plain K-subspaces)", {"smoothing": 0.0}),
    ("default with smoothing=10", {"smoothing": 10.0}),
    ("default with n_neighbors=20", {"n_neighbors": 20}),
    ("default with n_neighbors=40", {"n_neighbors": 40}),
    (
        "default with point_normals='all_polynomials'",
        {"point_normals": "all_polynomials"},
    ),
    ("default with n_init=3", {"n_init": 3}),
    ("default with random_state=1", {"random_state": 1}),
    (
        "default with subspace_dim='auto', subspace_dim_tol=0.1",
        {"subspace_dim": "auto", "subspace_dim_tol": 0.1},
    ),
    (
        "default (local normals, kNN power 4, 6 spectral inits on 3 graphs, "
        "smoothed K-subspaces, ncut selection)",
        {},
    ),
]

NOTES = """\
Rows other than the paper's inherit the remaining defaults (`normalize=True,
point_normals="local", affinity="nearest_neighbors", n_neighbors=30,
affinity_power=4, refine=True, smoothing=5.0, subspace_dim=None,
normal_tol=0.05, subspace_dim_tol=0.05, init="multi", n_init=10,
random_state=0`).
Rows 6-9 isolate the graph (one spectral initialisation, no refinement); row 10
is the six-candidate initialisation (the `affinity` graph at 30 and 45
neighbours and its product with the polynomial-normal graph, each split into
n and into n + 1 clusters merged back) with normalised-cut selection but no
refinement; row 11 is one spectral initialisation followed by the smoothed
K-subspaces refinement. The previous default kept three of the six candidates
(no coarse graph) and measured 1.55 / 4.01 / 2.11. `n_neighbors=30` and the
candidate set were chosen on this benchmark, which has no held-out part: with
20 or 40 neighbours the mean is about 2.8 %, so read the default's figure as
tuned, within about a point of what an untuned choice gives. Times were
measured on a shared machine and vary by about +-30 % between runs.

How the normalised cut compares with the best candidate in hindsight, with a
coding-length criterion and with a refinement started from the ground truth:
`benchmarks/results/selection.md` (`python benchmarks/bench_selection.py`).
"""


def run_auto(bunch):
    """Number of motions chosen by ``n_clusters="auto"`` (1 .. 5)."""
    threadpool_limits(1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        wide = PowerFactorization(20, whiten=False, random_state=0)
        model = GPCAClustering("auto", segmentation_dim=5, random_state=0)
        model.fit(wide.fit_transform(bunch.X))
    return bunch.n_motions, model.n_clusters_


def run_one(bunch, config):
    # one BLAS/OpenMP thread per job: the jobs already fill the cores
    threadpool_limits(1)
    pipeline = make_pipeline(
        PowerFactorization(random_state=0),
        GPCAClustering(bunch.n_motions, **{"random_state": 0, **config}),
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        start = time.perf_counter()
        labels = pipeline.fit_predict(bunch.X)
        elapsed = time.perf_counter() - start
    return bunch.n_motions, misclassification_rate(bunch.y, labels), elapsed


def summarise(results):
    motions, errors, seconds = (np.array(c) for c in zip(*results, strict=True))
    errors = 100 * errors
    cells = []
    for mask in (motions == 2, motions == 3, np.ones_like(motions, bool)):
        cells.append(f"{errors[mask].mean():.2f} / {np.median(errors[mask]):.2f}")
    cells.append(f"{np.median(seconds):.3f}")
    return cells


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", default="../shared/data/hopkins155")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--only", type=int, nargs="*", help="config indices")
    parser.add_argument(
        "--output", default=str(Path(__file__).parent / "results" / "ablation.md")
    )
    args = parser.parse_args()
    sequences = load_hopkins155(args.data)
    configs = CONFIGS if args.only is None else [CONFIGS[i] for i in args.only]
    rows = []
    for name, config in configs:
        start = time.perf_counter()
        results = Parallel(n_jobs=args.jobs)(
            delayed(run_one)(b, config) for b in sequences
        )
        cells = summarise(results)
        rows.append((name, config, cells))
        print(
            f"[{len(rows)}/{len(configs)}] {name}: {' | '.join(cells)} "
            f"({time.perf_counter() - start:.0f} s)",
            flush=True,
        )
    lines = [
        "# GPCAClustering ablation on Hopkins155",
        "",
        "`make_pipeline(PowerFactorization(random_state=0), "
        "GPCAClustering(n_motions, random_state=0, **config))` on the 155 "
        "sequences (120 with two motions, 35 with three), complete data, points "
        "projected to R^5. Misclassification in %, mean / median; time is the "
        "median wall time per sequence of the whole pipeline (2 jobs with one "
        "thread each on a shared 2-core machine).",
        "",
        "| configuration | arguments | 2 motions | 3 motions | all | median s |",
        "|---|---|---|---|---|---|",
    ]
    for name, config, cells in rows:
        arguments = ", ".join(f"{k}={v!r}" for k, v in config.items()) or "defaults"
        lines.append(f"| {name} | `{arguments}` | " + " | ".join(cells) + " |")
    auto = np.array(Parallel(n_jobs=args.jobs)(delayed(run_auto)(b) for b in sequences))
    counts = {m: np.bincount(auto[auto[:, 0] == m, 1], minlength=6)[1:] for m in (2, 3)}
    print(f"n_clusters='auto' picks: {counts}", flush=True)
    lines += [
        "",
        "Number of motions: `make_pipeline(PowerFactorization(20, "
        "whiten=False), GPCAClustering('auto', segmentation_dim=5))` (1 to 5 "
        "subspaces, shortest trajectory coding length; `n_motions.md`) picks",
        "",
        "| true number | 1 | 2 | 3 | 4 | 5 | correct |",
        "|---|---|---|---|---|---|---|",
    ]
    for m, row in counts.items():
        cells = " | ".join(str(c) for c in row)
        lines.append(f"| {m} | {cells} | {row[m - 1]} / {row.sum()} |")
    lines += [
        "",
        "Published means (2 / 3 / all): GPCA 4.59 / 28.67 / 10.34, SSC 1.53 / 4.40 "
        "/ 2.18, LRR 2.13 / 4.03 / 2.56, SMR 0.88 / 1.92 / 1.12, FSASC 0.80 / "
        "2.48 / 1.18.",
        "",
        "Regenerate with `python benchmarks/bench_ablation.py --data "
        "../shared/data/hopkins155 --jobs 2`.",
        "",
        NOTES,
    ]
    if args.only is None:
        write_markdown(args.output, "\n".join(lines))
        print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
