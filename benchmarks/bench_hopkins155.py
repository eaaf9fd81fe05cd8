"""Misclassification on Hopkins155, beside the published methods.

Run from the project root (about 5 minutes with two jobs)::

    python benchmarks/bench_hopkins155.py --data-home ../shared/data/hopkins155 --jobs 2

Writes ``benchmarks/results/hopkins155.md`` (complete data, all 155 sequences
with two or three motions, per method), ``benchmarks/results/
hopkins155_missing.md`` (the 120 two-motion sequences with occlusion masks
removing 0 to 50 % of the point-frames, fixed seed), their tables as CSV in
``benchmarks/results/tables/`` and the raw per-sequence figures as CSV beside
them. The methods, the published figures and the writers are in
``benchmarks/_hopkins155_harness.py``.
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import sys
from pathlib import Path

from _hopkins155_harness import MISSING_FRACTIONS, run_hopkins155

RESULTS = Path(__file__).parent / "results"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data-home", default=None, help="Hopkins155 folder")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument(
        "--missing",
        type=float,
        nargs="*",
        default=list(MISSING_FRACTIONS),
        help="occlusion fractions for the two-motion sequences "
        "(the flag alone, with no fraction, skips them)",
    )
    parser.add_argument(
        "--no-imputers",
        action="store_true",
        help="skip the imputer baselines on the occluded sequences",
    )
    parser.add_argument("--output-dir", type=Path, default=RESULTS)
    args = parser.parse_args()
    command = " ".join(["python", "benchmarks/bench_hopkins155.py", *sys.argv[1:]])
    run_hopkins155(
        args.data_home,
        args.output_dir,
        command=command,
        jobs=args.jobs,
        seed=args.seed,
        missing=args.missing,
        imputers=not args.no_imputers,
    )


if __name__ == "__main__":
    main()
