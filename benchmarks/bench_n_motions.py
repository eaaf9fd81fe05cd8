"""How well ``GPCAClustering(n_clusters="auto")`` finds the number of motions.

For every sequence: ``PowerFactorization(random_state=0)`` projects the
trajectories to R^5, :func:`sklearn_gpca.gpca` segments the projection into
``n = 1 .. 5`` subspaces (``random_state=0``, as ``n_clusters="auto"`` does),
and each criterion keeps one of the five segmentations
(:func:`sklearn_gpca.select_n_clusters`). Reported per data set and criterion:
the confusion of true and found n, the share found right, the mean
misclassification with the found n (best label matching; extra clusters count
as errors, as :func:`~sklearn_gpca.metrics.misclassification_rate` does) and
with the true n, and the median time of the five fits and the criterion (what
``GPCAClustering("auto").fit`` costs on the projection).

Data: Hopkins155 (complete trajectories, 120 two-motion and 35 three-motion
sequences) and synthetic draws with 1 to 5 motions, so that the rule is not
fitted to one benchmark: ``make_motions`` (100 points per motion, 10 frames,
1 pixel noise, 20 % of the entries missing on odd seeds) and ``make_tracks``
(the ``"lab"`` scene: complete tracks, weak perspective, unequal motions).

Usage::

    python benchmarks/bench_n_motions.py --data ../shared/data/hopkins155 --jobs 2
    python benchmarks/bench_n_motions.py --step 5 --seeds 4   # a quick subset
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import time
import warnings
from functools import partial
from pathlib import Path

import numpy as np
from _tables import write_markdown
from joblib import Parallel, delayed
from threadpoolctl import threadpool_limits

from sklearn_gpca import PowerFactorization, gpca
from sklearn_gpca._model_selection import (
    MIN_MERGE_RATIO,
    coding_length_cost,
    merge_ratio,
)
from sklearn_gpca.datasets import load_hopkins155, make_motions, make_tracks
from sklearn_gpca.metrics import misclassification_rate

MAX_N = 5

NOTE = (
    "Read against the issue's target (>= 90 % on Hopkins155): the "
    "merge-ratio gate stops most of the over-counting of two-motion "
    "sequences and cuts the error with the found n, but finds few "
    "three-motion sequences: in R^5 two of their three motions often lie "
    "near one hyperplane (merge ratio under 5 with the right labels), and "
    "then no hyperplane criterion tells them apart. For the same reason the "
    "gate loses three- to five-motion draws of `make_motions` and "
    "`make_tracks`, where the plain coding length was better: a trade-off, "
    "not a free win. The hyperplane energy `E` is trimmed to the 90 % "
    "best-fitted points (robust to a few misassigned held-out points, which "
    "`GridSearchCV` scores)."
)


def distinct_at(threshold, points, labels):
    """:func:`distinct_coding_length_cost` with another merge-ratio threshold."""
    if merge_ratio(points, labels) < threshold:
        return np.inf
    return coding_length_cost(points, labels)


#: name -> criterion(points, labels); the first is the former default.
CRITERIA = {
    "coding length (former default)": coding_length_cost,
    f"distinct coding length, merge ratio >= {MIN_MERGE_RATIO:g} (default)": (
        partial(distinct_at, MIN_MERGE_RATIO)
    ),
    "distinct coding length, merge ratio >= 3": partial(distinct_at, 3.0),
    "distinct coding length, merge ratio >= 8": partial(distinct_at, 8.0),
}


def run_one(X, y, n_true):
    """Found n, error with it, error with the true n and seconds, per criterion."""
    threadpool_limits(1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        Z = PowerFactorization(random_state=0).fit_transform(X)
        start = time.perf_counter()
        segmentations = {}
        for n in range(1, MAX_N + 1):
            try:
                segmentations[n] = gpca(Z, n, random_state=0).labels
            except ValueError:  # too few points for the Veronese embedding
                break
        fits = time.perf_counter() - start
    true_error = misclassification_rate(y, segmentations[n_true])
    rows = {}
    for name, criterion in CRITERIA.items():
        start = time.perf_counter()
        costs = [criterion(Z, labels) for labels in segmentations.values()]
        found = int(np.argmin(costs)) + 1
        seconds = fits + time.perf_counter() - start
        error = misclassification_rate(y, segmentations[found])
        rows[name] = (n_true, found, error, true_error, seconds)
    return rows


def hopkins_items(folder, step):
    sequences = load_hopkins155(folder)[::step]
    return [(b.X, b.y, b.n_motions) for b in sequences]


def motions_items(seeds):
    items = []
    for n in range(1, MAX_N + 1):
        for seed in range(seeds):
            X, y = make_motions(
                n, n_points=100 * n, missing=0.2 * (seed % 2), random_state=seed
            )
            items.append((X, y, n))
    return items


def tracks_items(seeds):
    items = []
    for n in range(1, MAX_N + 1):
        for seed in range(seeds):
            X, y = make_tracks(n, scene="lab", random_state=seed)
            items.append((X, y, n))
    return items


def confusion_table(results):
    """Markdown rows: true n, counts of found n, right, mean errors."""
    n_true, found, error, true_error, _ = (
        np.array(c) for c in zip(*results, strict=True)
    )
    lines = [
        "| true n | found 1 | 2 | 3 | 4 | 5 | right | error, found n | error, true n |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for n in np.unique(n_true):
        mask = n_true == n
        counts = np.bincount(found[mask], minlength=MAX_N + 1)[1:]
        cells = " | ".join(str(c) for c in counts)
        lines.append(
            f"| {n} | {cells} | {counts[n - 1]} / {mask.sum()} | "
            f"{100 * error[mask].mean():.2f} % | "
            f"{100 * true_error[mask].mean():.2f} % |"
        )
    return lines


def summary_row(dataset, name, results):
    n_true, found, error, _, seconds = (np.array(c) for c in zip(*results, strict=True))
    right = np.mean(found == n_true)
    return (
        f"| {dataset} | {name} | {100 * right:.1f} % ({np.sum(found == n_true)} / "
        f"{len(found)}) | {100 * error.mean():.2f} % | {np.median(seconds):.2f} |"
    )


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", default="../shared/data/hopkins155")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--step", type=int, default=1, help="every step-th sequence")
    parser.add_argument("--seeds", type=int, default=10, help="draws per n")
    parser.add_argument(
        "--output", default=str(Path(__file__).parent / "results" / "n_motions.md")
    )
    args = parser.parse_args()
    datasets = {
        "Hopkins155": hopkins_items(args.data, args.step),
        "make_motions": motions_items(args.seeds),
        "make_tracks (lab)": tracks_items(args.seeds),
    }
    summary, details = [], []
    for dataset, items in datasets.items():
        start = time.perf_counter()
        runs = Parallel(n_jobs=args.jobs)(delayed(run_one)(*item) for item in items)
        print(f"{dataset}: {len(items)} draws, {time.perf_counter() - start:.0f} s")
        for name in CRITERIA:
            results = [run[name] for run in runs]
            summary.append(summary_row(dataset, name, results))
            print(summary[-1], flush=True)
            details += ["", f"### {dataset}: {name}", "", *confusion_table(results)]
    subset = "" if args.step == 1 else f" (every {args.step}th sequence)"
    lines = [
        "# The number of motions: `GPCAClustering(n_clusters='auto')`",
        "",
        "Regenerate with `python benchmarks/bench_n_motions.py --data "
        f"../shared/data/hopkins155 --jobs {args.jobs} --step {args.step} "
        f"--seeds {args.seeds}`{subset}.",
        "",
        "`PowerFactorization(random_state=0)` projects each sequence to R^5; "
        "`gpca(Z, n, random_state=0)` segments it into n = 1 .. 5 subspaces "
        "(what `GPCAClustering('auto')` fits); each criterion keeps one. "
        "Errors are mean misclassification over the sequences with the found n "
        "(extra clusters count as errors) and, for reference, with the true n. "
        "Time: median wall seconds of the five fits and the criterion per "
        "sequence (one thread per job, 2 jobs on a shared 2-core machine).",
        "",
        f"Synthetic draws, {args.seeds} per n: `make_motions(n, n_points=100 * n, "
        "missing=0.2 on odd seeds)` and `make_tracks(n, scene='lab')`.",
        "",
        "| data | criterion | right n | error, found n | median s |",
        "|---|---|---|---|---|",
        *summary,
        "",
        "The merge ratio of two groups is `E(a | b) / (E(a) + E(b))`, `E` the "
        "squared sines of a set's unit points to its best hyperplane "
        "(`sklearn_gpca.merge_ratio`). The default threshold, 5, was chosen "
        "on Hopkins155 and on synthetic draws like these (tuned, no held-out "
        "part); the rows at 3 and 8 show how much it matters.",
        "",
        NOTE,
        "",
        "## Confusion of true and found n",
        *details,
    ]
    write_markdown(args.output, "\n".join(lines))
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
