"""Hopkins155 two-motion sequences under occlusion: error and time per fit.

Run from the project root (a few minutes)::

    python benchmarks/bench_occlusion.py --data-home ../shared/data/hopkins155

The 120 two-motion sequences with the occlusion masks of
``bench_hopkins155.py`` (``make_missing(X, fraction, pattern="occlusion",
random_state=0)``), one fraction (default 30 %), fitted one after the other
in this process with the machine's default BLAS threads:
``make_pipeline(PowerFactorization(random_state=0), GPCAClustering(2,
random_state=0))`` with the default solver and with ``solver="als"``.
Reported: mean and median misclassification, the median wall seconds of the
whole pipeline's ``fit_predict`` and of ``PowerFactorization`` alone, and
the slowest sequence. Writes ``benchmarks/results/occlusion.md`` and its CSV
table.
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import os
import sys
import time
import warnings
from pathlib import Path

import numpy as np
from _tables import markdown_table, write_markdown
from sklearn.pipeline import make_pipeline

from sklearn_gpca import GPCAClustering, PowerFactorization
from sklearn_gpca.datasets import load_hopkins155, make_missing
from sklearn_gpca.metrics import misclassification_rate

RESULTS = Path(__file__).parent / "results" / "occlusion.md"


def run(sequence, X, solver):
    """Error (%) and seconds of the pipeline, and seconds of the projection."""
    pipeline = make_pipeline(
        PowerFactorization(solver=solver, random_state=0),
        GPCAClustering(sequence.n_motions, random_state=0),
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        start, cpu = time.perf_counter(), time.process_time()
        labels = pipeline.fit_predict(X)
        seconds = time.perf_counter() - start
        cpu = time.process_time() - cpu
        start = time.perf_counter()
        PowerFactorization(solver=solver, random_state=0).fit_transform(X)
        projection = time.perf_counter() - start
    error = 100 * misclassification_rate(sequence.y, labels)
    return error, seconds, cpu, projection


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data-home", default=None, help="Hopkins155 folder")
    parser.add_argument("--missing", type=float, default=0.3)
    parser.add_argument("--solvers", nargs="+", default=["varpro", "als"])
    parser.add_argument("--output", type=Path, default=RESULTS)
    args = parser.parse_args()
    load = os.getloadavg()[0]
    sequences = load_hopkins155(args.data_home, n_motions=2)
    rows = []
    for solver in args.solvers:
        results = []
        for sequence in sequences:
            X = make_missing(sequence.X, args.missing, random_state=0)
            results.append(run(sequence, X, solver))
        errors, seconds, cpu, projection = np.array(results).T
        slowest = int(np.argmax(seconds))
        rows.append(
            [
                "default (varpro)" if solver == "varpro" else solver,
                str(len(sequences)),
                f"{errors.mean():.2f}",
                f"{np.median(errors):.2f}",
                f"{np.median(seconds):.3f}",
                f"{np.median(cpu):.3f}",
                f"{np.median(projection):.3f}",
                f"{seconds[slowest]:.2f} ({sequences[slowest].name})",
            ]
        )
        print(rows[-1], flush=True)
    command = "python benchmarks/bench_occlusion.py " + " ".join(sys.argv[1:])
    lines = [
        "# Hopkins155 two-motion sequences under occlusion",
        "",
        f"Regenerate with `{command.strip()}`. The 120 two-motion sequences, "
        f"{args.missing:.0%} of the point-frames removed by "
        '`make_missing(X, fraction, pattern="occlusion", random_state=0)`, '
        "fitted one after the other with the machine's default BLAS threads "
        "by `make_pipeline(PowerFactorization(solver=..., random_state=0), "
        "GPCAClustering(2, random_state=0))`. Misclassification in %; wall "
        "seconds of the pipeline's `fit_predict` and of `PowerFactorization` "
        "alone (median over the sequences), CPU seconds of the pipeline, and "
        "the slowest pipeline. Load average (1 min) when the run started: "
        f"{load:.1f} on {os.cpu_count()} cores.",
        "",
        *markdown_table(
            [
                "PowerFactorization solver",
                "sequences",
                "mean error",
                "median error",
                "median pipeline s",
                "median pipeline CPU s",
                "median PowerFactorization s",
                "slowest pipeline s",
            ],
            rows,
        ),
        "",
    ]
    write_markdown(args.output, "\n".join(lines))
    print(f"written to {args.output}")


if __name__ == "__main__":
    main()
