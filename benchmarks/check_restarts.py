"""segment_motions with several random states: each run, the kept one, the oracle.

For each scene, number of motions ``n`` of ``--motions`` and seed,
``make_tracks(scene=..., n_motions=n, random_state=seed)``, outlier tracks
removed: ``segment_motions(X, n, random_state=0, n_init=K)`` (``K`` of
``--n-init``) runs the segmentation with ``K`` random states, the first 0 (the
plain call, ``n_init=1``), and keeps the run the consistency rule judges best
(:mod:`sklearn_gpca._restarts`). Reported: the error of the first run (what
``random_state=0`` gives), the mean over the ``K`` runs (what a call with an
arbitrary random state gives on average), their spread (largest minus
smallest), the kept run's error, the best run's in hindsight (what a perfect
judge would keep), the oracle (:func:`sklearn_gpca.metrics.oracle_labels`,
each track to the nearest of the true motions' 4-D subspaces on its observed
entries) and the wall seconds of the ``n_init=K`` call (one BLAS thread per
job with ``--jobs`` above 1; the machine's default threads with one job), of
each of its runs and of the judgement that keeps one (``info.run_seconds``,
``info.judge_seconds``). With
``--plain-time`` the plain call (``n_init=1``) is timed too, just before, in
the same process, and the ratio of the two times is given.

Usage::

    python benchmarks/check_restarts.py --seeds 700 701 702 703 704 705 706 707 \
        --motions 3 --n-init 4 --jobs 2 --out benchmarks/results/restarts.md
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import contextlib
import time
import warnings

import numpy as np
from _tables import command_line, write_check_page
from check_motion_count import SCENES as MOTION_COUNT_SCENES
from joblib import Parallel, delayed
from threadpoolctl import threadpool_limits

from sklearn_gpca import segment_motions
from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.metrics import misclassification_rate, oracle_labels

#: The scenes of ``check_motion_count.py`` and the lab scene of
#: ``bench_outliers.py`` (two rigid objects on a table, a static camera).
SCENES = MOTION_COUNT_SCENES | {
    "lab, 30 frames": {"scene": "lab", "n_frames": 30, "missing": 0.4},
}


def _row(scene, n_motions, seed, n_init, plain_time, parallel):
    X, y = make_tracks(n_motions=n_motions, random_state=seed, **SCENES[scene])[:2]
    X, y = X[y >= 0], y[y >= 0]
    threads = threadpool_limits(1) if parallel else contextlib.nullcontext()
    with threads, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        plain = None
        if plain_time:
            clock = time.perf_counter()
            segment_motions(X, n_motions, random_state=0)
            plain = time.perf_counter() - clock
        clock = time.perf_counter()
        labels, info = segment_motions(
            X, n_motions, random_state=0, n_init=n_init, return_info=True
        )
        seconds = time.perf_counter() - clock
        oracle = misclassification_rate(y, oracle_labels(X, y))
    runs = [misclassification_rate(y, found) for found in info.run_labels]
    kept = misclassification_rate(y, labels)
    times = (plain, seconds, info.run_seconds, info.judge_seconds)
    return scene, n_motions, seed, runs, kept, oracle, times


def _cells(runs, kept, oracle):
    """First run, mean and spread of the runs, kept, best run, oracle (%)."""
    runs = np.asarray(runs)
    values = [runs[0], runs.mean(), runs.max() - runs.min(), kept, runs.min(), oracle]
    return [f"{100 * v:.2f}" for v in values]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=list(range(700, 708)))
    parser.add_argument("--motions", type=int, nargs="+", default=[3])
    parser.add_argument(
        "--scenes", nargs="+", default=list(MOTION_COUNT_SCENES), choices=SCENES
    )
    parser.add_argument("--n-init", type=int, default=4)
    parser.add_argument("--plain-time", action="store_true")
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--out", default=None, help="also write the page here")
    args = parser.parse_args(argv)
    jobs = [
        (scene, n, seed, args.n_init, args.plain_time, args.jobs > 1)
        for scene in args.scenes
        for n in args.motions
        for seed in args.seeds
    ]
    results = Parallel(n_jobs=args.jobs)(delayed(_row)(*job) for job in jobs)
    errors = ["first run (random_state=0) %", "mean of the runs %", "spread %"]
    errors += [f"kept (n_init={args.n_init}) %", "best run %", "oracle %"]
    header = ["scene", "motions", "seed", *errors, f"s (n_init={args.n_init})"]
    header += ["s of each run", "s judging"]
    if args.plain_time:
        header += ["s (n_init=1)", "time ratio"]
    rows, by_setting, times = [], {}, []
    for scene, n, seed, runs, kept, oracle, timing in results:
        plain, seconds, run_seconds, judge_seconds = timing
        by_setting.setdefault((scene, n), []).append((runs, kept, oracle))
        rows.append([scene, str(n), str(seed), *_cells(runs, kept, oracle)])
        rows[-1].append(f"{seconds:.1f}")
        each = " / ".join(f"{t:.1f}" for t in run_seconds)
        rows[-1] += [each, f"{judge_seconds:.1f}"]
        if args.plain_time:
            rows[-1] += [f"{plain:.1f}", f"{seconds / plain:.2f}"]
        times.append((plain or np.nan, seconds, np.sum(run_seconds), judge_seconds))
        print(" | ".join(rows[-1]), flush=True)
    sections = []
    plain, seconds, run_seconds, judge_seconds = np.sum(times, axis=0)
    total = [f"{seconds:.1f}", f"{run_seconds:.1f}", f"{judge_seconds:.1f}"]
    columns = [f"s (n_init={args.n_init})", "s of the runs", "s judging"]
    if args.plain_time:
        total += [f"{plain:.1f}", f"{seconds / plain:.2f}"]
        columns += ["s (n_init=1)", "ratio"]
    print(", ".join(columns) + ":", " | ".join(total))
    sections.append(("Time, all draws", columns, [total]))
    means = ["scene", "motions", "draws", *errors, "draws kept better / worse"]
    summary = []
    groups = [((scene, str(n)), draws) for (scene, n), draws in by_setting.items()]
    groups.append((("all", ""), [d for draws in by_setting.values() for d in draws]))
    for names, draws in groups:
        cells = np.array([[float(c) for c in _cells(*draw)] for draw in draws])
        better = int(np.sum(cells[:, 3] < cells[:, 0]))
        worse = int(np.sum(cells[:, 3] > cells[:, 0]))
        means_of_draws = [f"{v:.2f}" for v in cells.mean(axis=0)]
        summary.append(
            [*names, str(len(draws)), *means_of_draws, f"{better} / {worse}"]
        )
        print(" | ".join(summary[-1]))
    if args.out:
        write_check_page(
            args.out,
            command_line(
                "check_restarts.py",
                args,
                ["seeds", "motions", "scenes", "n_init", "jobs"],
            )
            + (" --plain-time" if args.plain_time else ""),
            __doc__,
            "segment_motions: several random states",
            [
                ("Mean over the seeds", means, summary),
                *sections,
                ("Per draw", header, rows),
            ],
        )


if __name__ == "__main__":
    main()
