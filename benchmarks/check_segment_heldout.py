"""segment_motions on held-out make_tracks seeds: does the benchmark generalise?

``benchmarks/bench_segment.py --setting tracks`` draws seeds 0 .. 3 of each
realistic setting, the seeds on which the selection rule's settings were
chosen. This script draws other seeds of the same settings (default 20 .. 23,
never used to tune a setting; the ``"consistency"`` selection rule was checked
on them before it became the default) and reports, per setting, the mean
misclassification of the default ``segment_motions(X, n)`` (and, with
``--selection``, of other selection rules) and of the oracle (the nearest true 4-D
subspace on each track's observed entries), outlier tracks removed as in
``bench_segment.py``, and the median wall time per sequence. One process, the
machine's default BLAS threads unless ``OMP_NUM_THREADS`` is set.

Usage::

    python benchmarks/check_segment_heldout.py [--first-seed 20] [--draws 4]
        [--selection separability ...]
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import os
import time
import warnings

import numpy as np
from _tables import markdown_table, write_markdown
from bench_segment import TRACK_SETTINGS, track_draws

from sklearn_gpca import segment_motions
from sklearn_gpca.metrics import misclassification_rate, oracle_labels


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--first-seed", type=int, default=20)
    parser.add_argument("--draws", type=int, default=4)
    parser.add_argument("--out", default="benchmarks/results/segment_tracks_heldout.md")
    parser.add_argument(
        "--selection",
        nargs="*",
        default=[],
        choices=["separability", "fitted_separability", "coding_length"],
        help="other selection rules to report beside the default",
    )
    args = parser.parse_args(argv)
    errors = {
        s: {"default": [], "oracle": [], **{r: [] for r in args.selection}}
        for s in TRACK_SETTINGS
    }
    seconds = []
    for setting, name, X, y, n in track_draws(args.draws, first_seed=args.first_seed):
        inliers = y >= 0
        X, y = X[inliers], y[inliers]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            start = time.perf_counter()
            labels = segment_motions(X, n, random_state=0)
            seconds.append(time.perf_counter() - start)
        errors[setting]["default"].append(100 * misclassification_rate(y, labels))
        for rule in args.selection:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                other = segment_motions(X, n, selection=rule, random_state=0)
            errors[setting][rule].append(100 * misclassification_rate(y, other))
        oracle = oracle_labels(X, y)
        errors[setting]["oracle"].append(100 * misclassification_rate(y, oracle))
        print(name, round(errors[setting]["default"][-1], 2), flush=True)
    rows = []
    for setting, e in errors.items():
        per_seed = " / ".join(f"{v:.1f}" for v in e["default"])
        rows.append(
            [
                setting,
                f"{np.mean(e['default']):.2f}",
                per_seed,
                *(f"{np.mean(e[r]):.2f}" for r in args.selection),
                f"{np.mean(e['oracle']):.2f}",
            ]
        )

    def overall(key):
        return f"{np.mean([v for e in errors.values() for v in e[key]]):.2f}"

    rows.append(
        [
            "all",
            overall("default"),
            "",
            *(overall(r) for r in args.selection),
            overall("oracle"),
        ]
    )
    seeds = f"{args.first_seed} .. {args.first_seed + args.draws - 1}"
    threads = os.environ.get("OMP_NUM_THREADS", "the machine's default")
    text = "\n".join(
        [
            "# segment_motions on held-out make_tracks seeds",
            "",
            f"`python benchmarks/check_segment_heldout.py --first-seed "
            f"{args.first_seed} --draws {args.draws}"
            + "".join(f" --selection {r}" for r in args.selection)
            + "` (see its docstring): the "
            f"settings of `bench_segment.py --setting tracks`, seeds {seeds} "
            "(not used to tune any setting), outlier tracks removed; "
            "misclassification (%), mean over the seeds. "
            f"Median {np.median(seconds):.1f} s per sequence "
            f"(OMP_NUM_THREADS: {threads}).",
            "",
            *markdown_table(
                [
                    "setting",
                    "segment_motions (default)",
                    "per seed",
                    *(f"selection='{r}'" for r in args.selection),
                    "oracle",
                ],
                rows,
            ),
        ]
    )
    write_markdown(args.out, text + "\n")
    print(text)


if __name__ == "__main__":
    main()
