"""segment_motions with and without the re-segmented candidates.

With 3 motions or more, ``segment_motions`` keeps the largest motion of the
candidate its rule keeps, segments the other tracks again on their own motion
graph (:mod:`sklearn_gpca._resegment`), refines and judges those starts, and
lets one replace the kept candidate only when Vuong's test finds its score
lower by more than one standard error (``RESEGMENT_LEVEL``). This script
measures what that adds, in one process: per ``make_tracks`` setting of
``bench_segment.py --setting tracks`` (outlier tracks removed), the mean
misclassification of the default and of the same call without the re-segmented
starts (``resegmented_starts`` patched to find none: the code before they were
added), the oracle (the nearest true 4-D subspace on each track's observed
entries, fitted to convergence), and the median wall time per sequence of both
calls and their ratio; with ``--hopkins PATH``, the same on Hopkins155's
three-motion sequences (with two motions nothing is re-segmented).

Usage::

    python benchmarks/check_resegment.py --seeds 0 1 2 3
    python benchmarks/check_resegment.py --seeds 40 41 42 43 \\
        --out benchmarks/results/resegment_seeds40.md
    python benchmarks/check_resegment.py --seeds --hopkins \\
        ../shared/data/hopkins155 --out benchmarks/results/resegment_hopkins.md
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import os
import time
import warnings
from unittest import mock

from _tables import markdown_table, write_markdown
from check_perspective_background import draws as track_draws
from check_perspective_background import setting_table
from joblib import Parallel, delayed
from threadpoolctl import threadpool_limits

from sklearn_gpca import segment_motions
from sklearn_gpca.datasets import load_hopkins155
from sklearn_gpca.metrics import misclassification_rate, oracle_labels


def run_one(setting, name, X, y, n):
    with threadpool_limits(1), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        row = {"setting": setting, "name": name}
        start = time.perf_counter()
        labels, info = segment_motions(X, n, random_state=0, return_info=True)
        row["default_s"] = time.perf_counter() - start
        row["kept"] = info.candidates[info.chosen]
        with mock.patch("sklearn_gpca._segment.resegmented_starts", return_value=[]):
            start = time.perf_counter()
            without = segment_motions(X, n, random_state=0)
            row["without_s"] = time.perf_counter() - start
        row["default"] = misclassification_rate(y, labels)
        row["without"] = misclassification_rate(y, without)
        row["oracle"] = misclassification_rate(y, oracle_labels(X, y))
    return row


def draws(seeds, hopkins):
    # the make_tracks draws of check_perspective_background.py, outliers removed
    yield from track_draws(seeds, None, 1)
    if hopkins:
        for bunch in load_hopkins155(hopkins, n_motions=3):
            yield "Hopkins155, 3 motions", bunch.name, bunch.X, bunch.y, 3


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="*", default=[0, 1, 2, 3])
    parser.add_argument("--hopkins", default=None, help="Hopkins155 folder")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--out", default="benchmarks/results/resegment.md")
    args = parser.parse_args(argv)
    begin = time.perf_counter()
    rows = Parallel(n_jobs=args.jobs)(
        delayed(run_one)(*draw) for draw in draws(args.seeds, args.hopkins)
    )
    wall = time.perf_counter() - begin
    for row in rows:
        row["ratio"] = row["default_s"] / row["without_s"]
    methods = ["default", "without", "oracle"]
    table = setting_table(rows, methods, ["default_s", "without_s", "ratio"])
    command = "python benchmarks/check_resegment.py " + " ".join(
        (f"--seeds {' '.join(map(str, args.seeds))}",)
        + ((f"--hopkins {args.hopkins}",) if args.hopkins else ())
        + (f"--jobs {args.jobs} --out {args.out}",)
    )
    changed = [r for r in rows if r["default"] != r["without"]]
    text = "\n".join(
        [
            "# segment_motions: the re-segmented candidates",
            "",
            f"`{command}` ({wall:.0f} s wall time, one BLAS thread per job, "
            f"{args.jobs} jobs; OMP_NUM_THREADS: "
            f"{os.environ.get('OMP_NUM_THREADS', 'unset')}). Misclassification "
            "(%), mean over the sequences (outlier tracks removed); median wall "
            "seconds per sequence and median ratio of the two times. *default*: "
            "`segment_motions(X, n)`: with 3 motions or more, the kept "
            "candidate's largest motion kept and the other tracks segmented "
            "on their own motion graph (`sklearn_gpca._resegment`), refined, "
            "judged, and kept only when Vuong's test finds one's score lower "
            "by more than one standard error (`RESEGMENT_LEVEL`, z < -1); "
            "*without*: the same call with "
            "`sklearn_gpca._segment.resegmented_starts` patched to return no "
            "start (the code before); *oracle*: the nearest true 4-D subspace "
            "on each track's observed entries (`oracle_labels`, fitted to "
            "convergence). Seeds of `make_tracks`: "
            f"{', '.join(map(str, args.seeds)) or 'none'}.",
            "",
            *markdown_table(
                ["setting", "sequences", *methods, "default s", "without s", "ratio"],
                table,
            ),
            "",
            f"Sequences whose labels changed ({len(changed)} of {len(rows)}; "
            "% without -> default, the candidate kept): "
            + (
                "; ".join(
                    f"{r['name']}: {100 * r['without']:.1f} -> "
                    f"{100 * r['default']:.1f} ({r['kept']})"
                    for r in changed
                )
                or "none"
            )
            + ".",
            "",
        ]
    )
    write_markdown(args.out, text)
    print(text)


if __name__ == "__main__":
    main()
