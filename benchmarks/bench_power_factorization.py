"""Time PowerFactorization.fit against numpy.linalg.svd on complete data.

Run from the project root::

    python benchmarks/bench_power_factorization.py

Writes ``benchmarks/results/power_factorization.md``. Timings are medians of
repeated runs; the ratio to the SVD, measured in the same process, is the
figure to read on a shared machine.
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import time
from pathlib import Path

import numpy as np
from _tables import write_markdown

from sklearn_gpca import PowerFactorization

RESULTS = Path(__file__).parent / "results" / "power_factorization.md"


def median_seconds(func, repeats):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        func()
        times.append(time.perf_counter() - start)
    return float(np.median(times))


def trajectories(n_samples, n_features, rank=5, noise=0.01, seed=0):
    rng = np.random.RandomState(seed)
    X = rng.standard_normal((n_samples, rank)) @ rng.standard_normal((rank, n_features))
    return X + noise * rng.standard_normal(X.shape)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 10000, 100000])
    parser.add_argument("--n-features", type=int, default=40)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--output", type=Path, default=RESULTS)
    args = parser.parse_args()

    rows = []
    for n_samples in args.sizes:
        X = trajectories(n_samples, args.n_features)
        pf = PowerFactorization(5, random_state=0)
        t_pf = median_seconds(lambda X=X, pf=pf: pf.fit(X), args.repeats)
        t_svd = median_seconds(
            lambda X=X: np.linalg.svd(X, full_matrices=False), args.repeats
        )
        rows.append(
            f"| {n_samples:,} | {args.n_features} | {pf.n_iter_} | {t_pf * 1e3:.2f} "
            f"| {t_svd * 1e3:.2f} | {t_pf / t_svd:.2f} |"
        )
        print(rows[-1], flush=True)

    table = "\n".join(
        [
            "# PowerFactorization.fit against numpy.linalg.svd (complete data)",
            "",
            f"Rank-5 data plus noise, n_features = {args.n_features}, median of "
            f"{args.repeats} runs. Regenerate with "
            "`python benchmarks/bench_power_factorization.py`.",
            "",
            "| n_samples | n_features | iterations | fit (ms) | svd (ms) | fit / svd |",
            "|---|---|---|---|---|---|",
            *rows,
            "",
        ]
    )
    write_markdown(args.output, table)
    print(f"written to {args.output}")


if __name__ == "__main__":
    main()
