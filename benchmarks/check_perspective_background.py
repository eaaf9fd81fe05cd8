"""segment_motions with and without the perspective background candidates.

``segment_motions(perspective_background=True)`` (the default) refines every
candidate a second time with its largest motion -- the background of a
tracker's output -- modelled by a perspective camera
(:mod:`sklearn_gpca._projective_motion`) and chooses among both sets. This
script measures what that adds, in one process: per ``make_tracks`` setting of
``bench_segment.py --setting tracks`` (outlier tracks removed), the mean
misclassification of the default, of ``perspective_background=False``, of the
oracle (the nearest true 4-D subspace on each track's observed entries) and of
the *perspective oracle* (the same with the background modelled by a
perspective camera), and the median wall time per sequence of both calls; with
``--hopkins PATH``, the same on every ``--step``-th Hopkins155 sequence,
complete and (two motions) with 30 % occlusion.

Usage::

    python benchmarks/check_perspective_background.py --seeds 0 1 2 3
    python benchmarks/check_perspective_background.py --seeds 20 21 22 23 \\
        --out benchmarks/results/perspective_background_heldout.md
    python benchmarks/check_perspective_background.py --seeds 40 41 42 43 \\
        --out benchmarks/results/perspective_background_fresh.md
    python benchmarks/check_perspective_background.py --seeds --hopkins \\
        ../shared/data/hopkins155 --step 1 \\
        --out benchmarks/results/perspective_background_hopkins.md
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import os
import time
import warnings

import numpy as np
from _tables import markdown_table, write_markdown
from bench_segment import TRACK_SETTINGS
from joblib import Parallel, delayed
from threadpoolctl import threadpool_limits

from sklearn_gpca import segment_motions
from sklearn_gpca.datasets import load_hopkins155, make_missing, make_tracks
from sklearn_gpca.metrics import misclassification_rate, oracle_labels


def run_one(setting, name, X, y, n):
    with threadpool_limits(1), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        row = {"setting": setting, "name": name}
        start = time.perf_counter()
        labels = segment_motions(X, n, random_state=0)
        row["default_s"] = time.perf_counter() - start
        start = time.perf_counter()
        affine = segment_motions(X, n, perspective_background=False, random_state=0)
        row["affine_s"] = time.perf_counter() - start
        row["default"] = misclassification_rate(y, labels)
        row["affine"] = misclassification_rate(y, affine)
        row["oracle"] = misclassification_rate(y, oracle_labels(X, y))
        row["perspective oracle"] = misclassification_rate(
            y, oracle_labels(X, y, perspective_background=True)
        )
    return row


def draws(seeds, hopkins, step):
    for setting, params in TRACK_SETTINGS.items():
        for seed in seeds:
            X, y = make_tracks(**params, random_state=seed)
            inliers = y >= 0
            X, y = X[inliers], y[inliers]
            yield setting, f"{setting} #{seed}", X, y, int(np.unique(y).size)
    if hopkins:
        for index, bunch in enumerate(load_hopkins155(hopkins)):
            if index % step:
                continue
            setting = f"Hopkins155, {bunch.n_motions} motions"
            yield setting, bunch.name, bunch.X, bunch.y, bunch.n_motions
            if bunch.n_motions == 2:
                X = make_missing(bunch.X, 0.3, random_state=0)
                setting = "Hopkins155, 2 motions, 30 % occlusion"
                yield setting, f"{bunch.name} (occluded)", X, bunch.y, 2


def setting_table(rows, methods, seconds):
    """Rows of the summary: per setting, then over all ``make_tracks`` settings.

    Each holds the setting, its number of sequences, the mean error (%) of
    every key of ``methods`` and the median of every key of ``seconds``.
    """
    settings = list(dict.fromkeys(r["setting"] for r in rows))
    table = []
    for setting in [*settings, "all make_tracks settings"]:
        mine = [
            r
            for r in rows
            if r["setting"] == setting
            or (setting.startswith("all") and r["setting"] in TRACK_SETTINGS)
        ]
        if not mine:
            continue
        table.append(
            [setting, str(len(mine))]
            + [f"{100 * np.mean([r[m] for r in mine]):.2f}" for m in methods]
            + [f"{np.median([r[key] for r in mine]):.2f}" for key in seconds]
        )
    return table


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="*", default=[0, 1, 2, 3])
    parser.add_argument("--hopkins", default=None, help="Hopkins155 folder")
    parser.add_argument("--step", type=int, default=1, help="every k-th sequence")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--out", default="benchmarks/results/perspective_background.md")
    args = parser.parse_args(argv)
    begin = time.perf_counter()
    rows = Parallel(n_jobs=args.jobs)(
        delayed(run_one)(*draw) for draw in draws(args.seeds, args.hopkins, args.step)
    )
    wall = time.perf_counter() - begin
    methods = ["default", "affine", "oracle", "perspective oracle"]
    table = setting_table(rows, methods, ["default_s", "affine_s"])
    command = "python benchmarks/check_perspective_background.py " + " ".join(
        (f"--seeds {' '.join(map(str, args.seeds))}",)
        + ((f"--hopkins {args.hopkins} --step {args.step}",) if args.hopkins else ())
        + (f"--jobs {args.jobs} --out {args.out}",)
    )
    text = "\n".join(
        [
            "# segment_motions: the perspective background candidates",
            "",
            f"`{command}` ({wall:.0f} s wall time, one BLAS thread per job, "
            f"{args.jobs} jobs; OMP_NUM_THREADS: "
            f"{os.environ.get('OMP_NUM_THREADS', 'unset')}). Misclassification "
            "(%), mean over the sequences (outlier tracks removed); median wall "
            "seconds per sequence. *default*: `segment_motions(X, n)`, which "
            "also refines every candidate with its largest motion seen by a "
            "perspective camera and chooses among both sets; *affine*: "
            "`perspective_background=False`; *oracle*: the nearest true 4-D "
            "subspace on each track's observed entries "
            "(`sklearn_gpca.metrics.oracle_labels`); *perspective oracle*: the "
            "same with the largest true group modelled by a perspective camera "
            "(`oracle_labels(X, y, perspective_background=True)`). Seeds of "
            "`make_tracks`: "
            f"{', '.join(map(str, args.seeds)) or 'none'}.",
            "",
            *markdown_table(
                ["setting", "sequences", *methods, "default s", "affine s"],
                table,
            ),
            "",
            "Per sequence (%): "
            + "; ".join(
                f"{r['name']}: {100 * r['default']:.1f} / {100 * r['affine']:.1f}"
                for r in rows
            ),
            "",
        ]
    )
    write_markdown(args.out, text)
    print(text)


if __name__ == "__main__":
    main()
