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
the slowest sequence; then the same run in a child process with
``OMP_NUM_THREADS=1`` (``--no-one-thread`` skips it); then, on every
``--limit-every``-th sequence, the default pipeline with the k-means of the
spectral stage limited to one OpenMP thread and with the default pool,
alternately in this process; then the mean error of each solver over
``--mask-seeds`` occlusion draws (``random_state=0, 1, ...``): one draw's
mean moves by tenths of a point with the mask (one sequence can flip).
Writes ``benchmarks/results/occlusion.md`` and its CSV tables.
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import json
import os
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np
from _tables import markdown_table, write_markdown
from sklearn.pipeline import make_pipeline

from sklearn_gpca import GPCAClustering, PowerFactorization, _spectral
from sklearn_gpca.datasets import load_hopkins155, make_missing
from sklearn_gpca.metrics import misclassification_rate

RESULTS = Path(__file__).parent / "results" / "occlusion.md"
ONE_THREAD = {
    "OMP_NUM_THREADS": "1",
    "OPENBLAS_NUM_THREADS": "1",
    "MKL_NUM_THREADS": "1",
}


def pipeline_fit(sequence, X, solver):
    """Error (%), wall and CPU seconds of the pipeline's ``fit_predict``."""
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
    return 100 * misclassification_rate(sequence.y, labels), seconds, cpu


def run(sequence, X, solver):
    """Error (%), seconds and CPU seconds of the pipeline, seconds of the
    projection."""
    error, seconds, cpu = pipeline_fit(sequence, X, solver)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        start = time.perf_counter()
        PowerFactorization(solver=solver, random_state=0).fit_transform(X)
        projection = time.perf_counter() - start
    return error, seconds, cpu, projection


def solver_summary(sequences, masked, solver):
    """Mean and median error and median times over the sequences."""
    results = np.array(
        [run(s, X, solver) for s, X in zip(sequences, masked, strict=True)]
    )
    errors, seconds, cpu, projection = results.T
    slowest = int(np.argmax(seconds))
    return {
        "mean_error": errors.mean(),
        "median_error": np.median(errors),
        "seconds": np.median(seconds),
        "cpu": np.median(cpu),
        "projection": np.median(projection),
        "slowest": f"{seconds[slowest]:.2f} ({sequences[slowest].name})",
    }


def thread_limit_rows(sequences, masked, every):
    """The default pipeline with and without one OpenMP thread in k-means."""
    cpu = {True: [], False: []}
    errors = {True: [], False: []}
    for k in range(0, len(sequences), every):
        for on in (True, False):
            _spectral.LIMIT_KMEANS_THREADS = on
            error, _, seconds = pipeline_fit(sequences[k], masked[k], "varpro")
            cpu[on].append(seconds)
            errors[on].append(error)
    _spectral.LIMIT_KMEANS_THREADS = True
    ratios = np.array(cpu[False]) / np.array(cpu[True])
    return [
        [
            "one (default)" if on else "the machine's default pool",
            str(len(cpu[on])),
            f"{np.mean(errors[on]):.2f}",
            f"{np.median(cpu[on]):.3f}",
            f"{np.median(ratios):.1f}" if not on else "1",
        ]
        for on in (True, False)
    ]


def mask_seed_rows(sequences, summaries, fraction, n_seeds):
    """Mean error (%) of each solver on each occlusion draw, and overall; draw
    0 is the table's (``summaries``), the others are fitted here."""
    rows = []
    for solver, summary in summaries.items():
        means = [summary["mean_error"]]
        for seed in range(1, n_seeds):
            errors = [
                pipeline_fit(s, make_missing(s.X, fraction, random_state=seed), solver)
                for s in sequences
            ]
            means.append(np.mean([error for error, _, _ in errors]))
        name = "default (varpro)" if solver == "varpro" else solver
        rows.append([name, *(f"{m:.2f}" for m in means), f"{np.mean(means):.2f}"])
    return rows


def one_thread_child(args):
    """This benchmark's solver runs in a child process with one thread."""
    command = [sys.executable, __file__, "--child", "--missing", str(args.missing)]
    command += ["--solvers", *args.solvers]
    if args.data_home:
        command += ["--data-home", args.data_home]
    out = subprocess.run(
        command,
        env={**os.environ, **ONE_THREAD},
        capture_output=True,
        text=True,
        check=True,
    )
    return json.loads(out.stdout.splitlines()[-1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data-home", default=None, help="Hopkins155 folder")
    parser.add_argument("--missing", type=float, default=0.3)
    parser.add_argument("--solvers", nargs="+", default=["varpro", "als"])
    parser.add_argument("--limit-every", type=int, default=4)
    parser.add_argument("--no-one-thread", action="store_true")
    parser.add_argument("--mask-seeds", type=int, default=5)
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--output", type=Path, default=RESULTS)
    args = parser.parse_args()
    load = os.getloadavg()[0]
    sequences = load_hopkins155(args.data_home, n_motions=2)
    masked = [make_missing(s.X, args.missing, random_state=0) for s in sequences]
    summaries = {}
    for solver in args.solvers:
        summaries[solver] = solver_summary(sequences, masked, solver)
        print(solver, summaries[solver], file=sys.stderr, flush=True)
    if args.child:
        print(json.dumps(summaries))
        return
    single = {} if args.no_one_thread else one_thread_child(args)
    rows = []
    for solver, summary in summaries.items():
        one = single.get(solver)

        def both(key, digits=3, one=one, summary=summary):
            text = f"{summary[key]:.{digits}f}"
            return text if one is None else f"{text} ({one[key]:.{digits}f})"

        rows.append(
            [
                "default (varpro)" if solver == "varpro" else solver,
                str(len(sequences)),
                both("mean_error", 2),
                f"{summary['median_error']:.2f}",
                both("seconds"),
                both("cpu"),
                both("projection"),
                summary["slowest"],
            ]
        )
    limits = thread_limit_rows(sequences, masked, args.limit_every)
    seeds = mask_seed_rows(sequences, summaries, args.missing, args.mask_seeds)
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
        "the slowest pipeline; in brackets the same run in a child process "
        "with `OMP_NUM_THREADS=1`. Load average "
        f"(1 min) when the run started: {load:.1f} on {os.cpu_count()} cores.",
        "",
        *markdown_table(
            [
                "PowerFactorization solver",
                "sequences",
                "mean error (OMP=1)",
                "median error",
                "median pipeline s (OMP=1)",
                "median pipeline CPU s (OMP=1)",
                "median PowerFactorization s (OMP=1)",
                "slowest pipeline s",
            ],
            rows,
        ),
        "",
        "## One OpenMP thread in k-means, or the default pool",
        "",
        f"Every {args.limit_every}th sequence, the default pipeline with the "
        "spectral stage's k-means limited to one OpenMP thread "
        "(`sklearn_gpca._spectral.LIMIT_KMEANS_THREADS = True`, the default) "
        "and with the machine's default OpenMP pool, alternately in this "
        "process: mean error, median CPU seconds of the pipeline, and the "
        "median over the sequences of the ratio of CPU seconds without the "
        "limit to with it.",
        "",
        *markdown_table(
            [
                "OpenMP threads in k-means",
                "sequences",
                "mean error",
                "median pipeline CPU s",
                "CPU time / limited",
            ],
            limits,
        ),
        "",
        f"## Mean error over {args.mask_seeds} occlusion draws",
        "",
        "The same pipelines (default BLAS threads) on the masks "
        f'`make_missing(X, {args.missing}, pattern="occlusion", '
        "random_state=seed)`: mean misclassification (%) over the 120 "
        "sequences for each draw, and the mean of those means.",
        "",
        *markdown_table(
            [
                "PowerFactorization solver",
                *(f"draw {seed}" for seed in range(args.mask_seeds)),
                "mean",
            ],
            seeds,
        ),
        "",
    ]
    write_markdown(args.output, "\n".join(lines))
    print(f"written to {args.output}")


if __name__ == "__main__":
    main()
