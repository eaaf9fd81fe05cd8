"""segment_motions with and without the merge/split moves, in one process.

``segment_motions(merge_split=True)`` tries, after the selection, moves that
merge two motions and split another in two, each refined as the candidates
are and kept while the selection rule prefers it (with the default
``selection="consistency"``: the penalised fit of the segmentation's own
models). This script measures what the moves add: per ``make_tracks`` setting
of ``bench_segment.py --setting tracks`` (outlier tracks removed), and with
``--hopkins PATH`` on every ``--step``-th Hopkins155 sequence (complete and,
two motions, with 30 % occlusion), the mean misclassification of the default,
of ``merge_split=True`` and of the oracle, and the median wall time per
sequence of both calls.

Usage::

    python benchmarks/check_merge_split.py --seeds 0 1 2 3
    python benchmarks/check_merge_split.py --seeds 83 --jobs 1 \
        --out benchmarks/results/merge_split_threads.md

With ``--jobs 1`` the calls run with the machine's default BLAS threads,
otherwise with one BLAS thread per job.
    python benchmarks/check_merge_split.py --seeds 80 81 82 83 \\
        --out benchmarks/results/merge_split_seeds80.md
    python benchmarks/check_merge_split.py --seeds --hopkins \\
        ../shared/data/hopkins155 --step 1 \\
        --out benchmarks/results/merge_split_hopkins.md
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import os
import time
import warnings

from _tables import markdown_table, write_markdown
from check_perspective_background import draws, setting_table
from joblib import Parallel, delayed
from threadpoolctl import threadpool_limits

from sklearn_gpca import segment_motions
from sklearn_gpca.metrics import misclassification_rate, oracle_labels


def run_one(setting, name, X, y, n, threads):
    with threadpool_limits(threads), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        row = {"setting": setting, "name": name}
        for key, merge_split in (("default", False), ("merge_split", True)):
            start = time.perf_counter()
            labels = segment_motions(X, n, merge_split=merge_split, random_state=0)
            row[f"{key}_s"] = time.perf_counter() - start
            row[key] = misclassification_rate(y, labels)
        row["oracle"] = misclassification_rate(y, oracle_labels(X, y))
    return row


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="*", default=[0, 1, 2, 3])
    parser.add_argument("--hopkins", default=None, help="Hopkins155 folder")
    parser.add_argument("--step", type=int, default=1, help="every k-th sequence")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--out", default="benchmarks/results/merge_split.md")
    args = parser.parse_args(argv)
    # one BLAS thread per job when jobs share the cores; else the default
    threads = 1 if args.jobs > 1 else None
    begin = time.perf_counter()
    rows = Parallel(n_jobs=args.jobs)(
        delayed(run_one)(*draw, threads)
        for draw in draws(args.seeds, args.hopkins, args.step)
    )
    wall = time.perf_counter() - begin
    methods = ["default", "merge_split", "oracle"]
    table = setting_table(rows, methods, ["default_s", "merge_split_s"])
    command = "python benchmarks/check_merge_split.py " + " ".join(
        (f"--seeds {' '.join(map(str, args.seeds))}",)
        + ((f"--hopkins {args.hopkins} --step {args.step}",) if args.hopkins else ())
        + (f"--jobs {args.jobs} --out {args.out}",)
    )
    header = ["setting", "sequences", *methods, "default s", "merge_split s"]
    per_sequence = "; ".join(
        f"{r['name']}: {100 * r['default']:.1f} / {100 * r['merge_split']:.1f}"
        for r in rows
    )
    text = "\n".join(
        [
            "# segment_motions: the merge/split moves",
            "",
            f"`{command}` ({wall:.0f} s wall time, "
            + ("one BLAS thread per job" if threads else "the default BLAS threads")
            + f", {args.jobs} jobs; OMP_NUM_THREADS: "
            f"{os.environ.get('OMP_NUM_THREADS', 'unset')}). Misclassification "
            "(%), mean over the sequences (outlier tracks removed); median wall "
            "seconds per sequence. *default*: `segment_motions(X, n)`; "
            "*merge_split*: `segment_motions(X, n, merge_split=True)` (moves "
            'judged by the default `selection="consistency"`); *oracle*: the '
            "nearest true 4-D subspace on each track's observed entries. Seeds "
            f"of `make_tracks`: {', '.join(map(str, args.seeds)) or 'none'}.",
            "",
            *markdown_table(header, table),
            "",
            f"Per sequence (%, default / merge_split): {per_sequence}",
            "",
        ]
    )
    write_markdown(args.out, text)
    print(text)


if __name__ == "__main__":
    main()
