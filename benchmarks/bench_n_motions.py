"""How well ``GPCAClustering(n_clusters="auto")`` finds the number of motions.

For every sequence: ``PowerFactorization(20, whiten=False,
random_state=0)`` projects the trajectories to rank 20 (the largest even rank
<= 20 that the observed entries determine), the whitened leading 5
directions of that projection are segmented by :func:`sklearn_gpca.gpca` into
``n = 1 .. 5`` subspaces (``random_state=0``): what
``make_pipeline(PowerFactorization(20, whiten=False),
GPCAClustering("auto", segmentation_dim=5))`` fits. Each criterion keeps one of
the five segmentations (:func:`sklearn_gpca.select_n_clusters`): the
trajectory coding length on the rank-20 projection (the default with
``segmentation_dim``), and the coding lengths of the 5-D points segmented (the
default without it, and the former default). Reported per data set and criterion:
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
from sklearn_gpca._coding_length import coding_length
from sklearn_gpca._model_selection import (
    MIN_MERGE_RATIO,
    TRAJECTORY_DISTORTION,
    coding_length_cost,
    merge_ratio,
    trajectory_coding_length_cost,
)
from sklearn_gpca._rows import unit_rows
from sklearn_gpca._segmentation_space import (
    fit_segmentation_space,
    to_segmentation_space,
)
from sklearn_gpca.datasets import load_hopkins155, make_motions, make_tracks
from sklearn_gpca.metrics import misclassification_rate

MAX_N = 5
WIDE_RANK = 4 * MAX_N

NOTE = (
    "What was tuned on what: the distortion 0.007 and the width cap (at "
    "least 4 points per dimension) of the trajectory coding length were "
    "chosen on the even-indexed Hopkins155 sequences (distortions 0.005, "
    "0.007, 0.01, 0.015; 3, 4 or 6 points per dimension, or no cap); the "
    "odd-indexed ones are held out (line below the table). The synthetic "
    "draws were not used to choose them. The merge-ratio threshold 5 of the "
    "R^5 default was chosen on Hopkins155 and synthetic draws like these. "
    "Why the wide projection counts better on real sequences: in the "
    "whitened R^5 every direction has unit variance, so perspective and "
    "tracking errors weigh as much as the motions (the coding length there "
    "splits motions) and two of three motions often lie near one hyperplane "
    "(the merge-ratio gate then merges them); in the unwhitened rank-20 "
    "projection these errors keep their small weight and distinct motions "
    "are distinct subspaces. Where it fails: `make_motions` draws whose "
    "motions differ only in directions of little energy (slow rotations in "
    "pixel coordinates whose origin is the image corner: the rank-20 "
    "projection has about 4 significant directions for 2 to 5 motions) are "
    "under-counted; only the whitened coding length finds them, and it "
    "over-counts most real sequences. The unit trajectories depend on the "
    "image origin: Hopkins155 uses calibrated coordinates centred on the "
    "principal point; in its pixel coordinates (origin at the corner) the "
    "trajectory coding length finds the right n on 74 % of the sequences "
    "(measured once on the same segmentations, not by this script). With "
    "missing entries the rank-20 completion of 10 frames (20 features, 20 % "
    "missing on odd `make_motions` seeds) segments worse than rank 5 (error "
    "with the true n 7.5 % for two motions, 0.15 % with "
    "`PowerFactorization(5)`), so the R^5 rows of `make_motions` here are "
    "not the R^5 pipeline's: with `PowerFactorization(5)` the previous run "
    "of this page found 58 % (distinct coding length) and 88 % (coding "
    "length) on `make_motions`; the `make_tracks` draws are complete and "
    "their rows are the same."
)


def wide_at(distortion, points, labels):
    """The trajectory coding length at another distortion, no width cap."""
    return coding_length(unit_rows(points), labels, distortion)


def distinct_at(threshold, points, labels):
    """:func:`distinct_coding_length_cost` with another merge-ratio threshold."""
    if merge_ratio(points, labels) < threshold:
        return np.inf
    return coding_length_cost(points, labels)


DEFAULT = "trajectory coding length, rank 20 (default)"

#: name -> (space, criterion(points, labels)); space "wide" is the rank-20
#: projection, "5" the whitened 5-D points segmented.
CRITERIA = {
    DEFAULT: ("wide", trajectory_coding_length_cost),
    "trajectory coding length, no width cap": (
        "wide",
        partial(wide_at, TRAJECTORY_DISTORTION),
    ),
    "trajectory coding length, distortion 0.005, no width cap": (
        "wide",
        partial(wide_at, 0.005),
    ),
    "trajectory coding length, distortion 0.015, no width cap": (
        "wide",
        partial(wide_at, 0.015),
    ),
    f"distinct coding length in R^5, merge ratio >= {MIN_MERGE_RATIO:g} "
    "(default without segmentation_dim)": ("5", partial(distinct_at, MIN_MERGE_RATIO)),
    "coding length in R^5 (former default)": ("5", coding_length_cost),
}


def wide_projection(X):
    """Unwhitened PowerFactorization at rank 20, or the largest even rank the
    observed entries determine."""
    rank = min(WIDE_RANK, *X.shape)
    while True:
        try:
            pf = PowerFactorization(rank, whiten=False, random_state=0)
            return pf.fit_transform(X)
        except ValueError:
            if rank <= 6:
                raise
            rank -= 2


def run_one(X, y, n_true):
    """Found n, error with it, error with the true n and seconds, per criterion."""
    threadpool_limits(1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        start = time.perf_counter()
        wide = wide_projection(X)
        Z = to_segmentation_space(wide, *fit_segmentation_space(wide, 5))
        segmentations = {}
        for n in range(1, MAX_N + 1):
            try:
                segmentations[n] = gpca(Z, n, random_state=0).labels
            except ValueError:  # too few points for the Veronese embedding
                break
        fits = time.perf_counter() - start
    true_error = misclassification_rate(y, segmentations[n_true])
    rows = {}
    for name, (space, criterion) in CRITERIA.items():
        start = time.perf_counter()
        points = wide if space == "wide" else Z
        costs = [criterion(points, labels) for labels in segmentations.values()]
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
    summary, details, held_out = [], [], ""
    for dataset, items in datasets.items():
        start = time.perf_counter()
        runs = Parallel(n_jobs=args.jobs)(delayed(run_one)(*item) for item in items)
        print(f"{dataset}: {len(items)} draws, {time.perf_counter() - start:.0f} s")
        for name in CRITERIA:
            results = [run[name] for run in runs]
            summary.append(summary_row(dataset, name, results))
            print(summary[-1], flush=True)
            details += ["", f"### {dataset}: {name}", "", *confusion_table(results)]
        if dataset == "Hopkins155" and args.step == 1:
            right = [run[DEFAULT][0] == run[DEFAULT][1] for run in runs]
            held_out = (
                "Default on Hopkins155: right n on "
                f"{sum(right[::2])} / {len(right[::2])} even-indexed sequences "
                f"(where its two constants were chosen) and {sum(right[1::2])} / "
                f"{len(right[1::2])} odd-indexed ones (held out)."
            )
    subset = "" if args.step == 1 else f" (every {args.step}th sequence)"
    lines = [
        "# The number of motions: `GPCAClustering(n_clusters='auto')`",
        "",
        "Regenerate with `python benchmarks/bench_n_motions.py --data "
        f"../shared/data/hopkins155 --jobs {args.jobs} --step {args.step} "
        f"--seeds {args.seeds}`{subset}.",
        "",
        "`PowerFactorization(20, whiten=False, random_state=0)` projects each "
        "sequence to rank 20 (on a few `make_motions` draws with missing "
        "entries, 18 or less: the largest even rank the observed entries "
        "determine); `gpca(Z, n, random_state=0)` segments the whitened leading "
        "5 directions Z of that projection into n = 1 .. 5 subspaces (what "
        "`make_pipeline(PowerFactorization(20, whiten=False), "
        "GPCAClustering('auto', segmentation_dim=5))` fits; with complete data Z "
        "is `PowerFactorization(5)`'s projection); each criterion keeps one. "
        "The trajectory coding length (`sklearn_gpca."
        "trajectory_coding_length_cost`) is measured on the rank-20 "
        "projection, the others on Z. "
        "Errors are mean misclassification over the sequences with the found n "
        "(extra clusters count as errors) and, for reference, with the true n. "
        "Time: median wall seconds of the rank-20 projection, the five fits "
        "and the criterion per "
        "sequence (one thread per job, 2 jobs on a shared 2-core machine).",
        "",
        f"Synthetic draws, {args.seeds} per n: `make_motions(n, n_points=100 * n, "
        "missing=0.2 on odd seeds)` and `make_tracks(n, scene='lab')`.",
        "",
        "| data | criterion | right n | error, found n | median s |",
        "|---|---|---|---|---|",
        *summary,
        "",
        held_out,
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
