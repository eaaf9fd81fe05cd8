"""How well ``GPCAClustering(n_clusters="auto")`` finds the number of motions.

For every sequence: ``PowerFactorization(20, whiten=False,
random_state=0)`` projects the trajectories to rank 20 (the largest even rank
<= 20 that the observed entries determine), the whitened leading 5
directions of that projection are segmented by :func:`sklearn_gpca.gpca` into
``n = 1 .. 5`` subspaces (``random_state=0``): what
``make_pipeline(PowerFactorization(20, whiten=False),
GPCAClustering("auto", segmentation_dim=5))`` fits. Each criterion keeps one of
the five segmentations (:func:`sklearn_gpca.select_n_clusters`): the
trajectory coding length on the rank-20 projection after each segmentation
is refined by coordinate descent on it, groups of fewer than 16 trajectories
rejected (the default with ``segmentation_dim``), the same without the
refinement (the former default), and the coding lengths of the 5-D points segmented (the
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

Besides the criteria, rules tried to fix the misses of the default (issue 16):
the Gaussian (probabilistic PCA) description length with a dimension per
motion and the noise estimated from the data (BIC, no fitted constant); the
default stopped at its first local minimum; the default plus the BIC
parameter cost of each extra 4-D motion; the default among the
segmentations whose groups are distinct subspaces of their own dimension in
the rank-20 projection; and, with ``--stability``, the default among the
numbers whose segmentation is stable when refitted on 80 % of the
trajectories (one more fit per n). With ``--step 1`` the page lists every
Hopkins155 sequence the default gets wrong, with its criterion at each n.

Usage::

    python benchmarks/bench_n_motions.py --data ../shared/data/hopkins155 \
        --jobs 2 --stability
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
from sklearn_gpca._coding_descent import coding_length_descent
from sklearn_gpca._coding_length import coding_length
from sklearn_gpca._model_selection import (
    MIN_MERGE_RATIO,
    MIN_MOTION_POINTS,
    POINTS_PER_DIMENSION,
    TRAJECTORY_DISTORTION,
    coded_trajectories,
    coding_length_cost,
    merge_ratio,
    refined_trajectory_coding_length_cost,
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
    "The default refines each of the five segmentations before comparing "
    "them: trajectories move one group at a time while the trajectory coding "
    "length falls (coordinate descent on the criterion itself, to a local "
    "minimum; `sklearn_gpca.refined_trajectory_coding_length_cost`), and a "
    "refined segmentation with a group of fewer than 16 trajectories (or an "
    "emptied one) is rejected. The descent has no constant; the floor 16 is "
    "the width cap's 4 points per dimension times a rigid motion's 4 "
    "dimensions, not tuned (floor 9, row above, counts the same on "
    "Hopkins155, even and odd halves alike). The refinement counts right on "
    "6 Hopkins155 sequences more than the former default, but on 4 "
    "`make_motions` draws fewer (3 of them with missing entries, where the "
    "rank-20 completion of 10 frames is arbitrary beyond rank 4 and the "
    "descent splits a motion) and on 2 `make_tracks` draws fewer: the "
    "descent lowers the code of a segmentation with one motion more as well "
    "as the one with the true n. One round of the descent (row above) trades "
    "2 Hopkins155 sequences for 2 and 1 of the synthetic draws. "
    "What was tuned on what: the distortion 0.007 and the width cap (at "
    "least 4 points per dimension) of the trajectory coding length were "
    "chosen on the even-indexed Hopkins155 sequences (distortions 0.005, "
    "0.007, 0.01, 0.015; 3, 4 or 6 points per dimension, or no cap); the "
    "odd-indexed ones are held out (line below the table). The synthetic "
    "draws were not used to choose them. The merge-ratio threshold 5 of the "
    "R^5 default was chosen on Hopkins155 and synthetic draws like these. "
    "The rules tried to fix the misses: the first local minimum, the BIC "
    "parameter cost of each extra motion and the PPCA BIC have no constant; "
    "the distinct-subspace gate (a dimension per motion of at most 3, a "
    "union energy at least 1.5 times the pieces') and the stability "
    "threshold (disagreement 0.1) were each the best of a small grid (gate: "
    "at most 3 or 4 dimensions, ratio 1.5, 2, 3, 5, 10; stability: 0.01, "
    "0.02, 0.05, 0.1, 0.2) on all 155 sequences, so their Hopkins155 rows "
    "flatter them; the gate's choice was also the best on the even half. "
    "None is adopted: the best two find one sequence more than the former "
    "default and lose on the synthetic draws (rows above). "
    "Why the wide projection counts better on real sequences than R^5: in "
    "the whitened R^5 every direction has unit variance, so perspective and "
    "tracking errors weigh as much as the motions (the coding length there "
    "splits motions) and two of three motions often lie near one hyperplane "
    "(the merge-ratio gate then merges them); in the unwhitened rank-20 "
    "projection these errors keep their small weight and distinct motions "
    "are distinct subspaces. Why a description length with the noise "
    "estimated from the data fails (PPCA BIC): the residual of a real motion "
    "off its subspace is perspective and tracking error, structured rather "
    "than white, and splitting a motion reduces it by more than the "
    "parameters cost; the fixed distortion of the coding length ignores "
    "residuals below it, which is what makes it count. Where it fails on "
    "synthetic draws: `make_motions` draws whose motions differ only in "
    "directions of little energy (slow rotations in pixel coordinates whose "
    "origin is the image corner: the rank-20 projection has about 4 "
    "significant directions for 2 to 5 motions) are under-counted, and so "
    "are `make_tracks` draws with 3 to 5 motions (on most of them the true "
    "labels themselves cost more bits than the segmentation chosen, and the "
    "segmentation with the true n misassigns 10 to 28 % of the tracks). "
    "Removing each trajectory's mean position (which makes the criterion "
    "independent of the image origin) does not help: measured once on the "
    "complete draws, 50 % of Hopkins155, 20 % of the complete `make_motions` "
    "draws, 48 % of `make_tracks`. The unit trajectories depend on the image "
    "origin: Hopkins155 uses calibrated coordinates centred on the principal "
    "point; in its pixel coordinates (origin at the corner) the trajectory "
    "coding length finds the right n on 74 % of the sequences (measured once "
    "on the same segmentations, not by this script). With missing entries "
    "the rank-20 completion of 10 frames (20 features, 20 % missing on odd "
    "`make_motions` seeds) segments worse than rank 5, so the R^5 rows of "
    "`make_motions` here are not the R^5 pipeline's: with "
    "`PowerFactorization(5)` an earlier run of this page found 58 % "
    "(distinct coding length) and 88 % (coding length) on `make_motions`; "
    "the `make_tracks` draws are complete and their rows are the same."
)


MISSES_NOTE = (
    "Bits above the cheapest of the five refined segmentations (inf: a "
    "refined group of fewer than 16 trajectories), the true n in bold; errors "
    "are the segmentation's with the true and with the found n. The "
    "refinement fixes 1R2RCR, 1R2RC_g13, 1RT2TC_g12, 1RT2TC_g13, 2RT3RC, "
    "2RT3RCR, 2RT3RCT_A, cars1 and three-cars, the former default's misses "
    "of category (1) and (3): the segmentation with the true n misassigned 1 "
    "to 13 trajectories (in 1RT2TC a single trajectory costs about 200 bits, "
    "a direction added to its group's code), or two motions near one "
    "low-dimensional subspace were merged; refined, the true labels are the "
    "cheapest. Without the group floor the descent gathers 4 to 9 outlying "
    "trajectories into a group of their own in cars1, cars8, cars10, head and "
    "1RT2TC_g13 (row 'no group floor'). Lost by the refinement: 2RT3RCR_g23, "
    "2T3RCRT_g13 and cars3_g13, where the descent lowers the segmentation "
    "with a motion split in two pieces (38 to 150 trajectories) more than "
    "the one with the true n; in 2RT3RCR_g23 the refined true labels cost "
    "208 bits less than every candidate: the fit with n = 2 is too far from "
    "them for the descent to reach them (measured with the same "
    "segmentations outside this script). "
    "Remaining as before: (2) one rigid motion made of planar parts: in "
    "2T3RCTP, its three pairs and 2T3RCRT_g23 one motion (e.g. 151 or 209 "
    "trajectories, singular values 1, 0.55, 0.05 and 1, 0.71, 0.11, 0.04) "
    "splits into two or three pieces of dimension about 2, and the refined "
    "true labels cost 57 to 138 bits more than the split: two planar parts "
    "of one body span two 3-D subspaces inside one 4-D subspace, exactly as "
    "two translating bodies do, and no criterion on subspaces alone can tell "
    "them apart. (4) two_cranes and its three pairs (articulated, with 39 to "
    "94 trajectories): all the trajectories lie near one 3-D subspace (1, "
    "0.42, 0.02) and the true labels cost more than one group; the ground "
    "truth (parts of articulated cranes) is debatable from the trajectories "
    "alone, but they count as misses."
)


def refined_with_floor(floor, points, labels, max_iter=100):
    """:func:`refined_trajectory_coding_length_cost` with another group floor
    or number of rounds of the descent."""
    groups = np.unique(labels, return_inverse=True)[1].reshape(-1)
    refined, bits = coding_length_descent(
        coded_trajectories(points), groups, TRAJECTORY_DISTORTION, max_iter=max_iter
    )
    n_groups = np.unique(labels).size
    if n_groups > 1 and np.bincount(refined, minlength=n_groups).min() < floor:
        return np.inf
    return bits


def wide_at(distortion, points, labels):
    """The trajectory coding length at another distortion, no width cap."""
    return coding_length(unit_rows(points), labels, distortion)


def distinct_at(threshold, points, labels):
    """:func:`distinct_coding_length_cost` with another merge-ratio threshold."""
    if merge_ratio(points, labels) < threshold:
        return np.inf
    return coding_length_cost(points, labels)


def _capped_unit(points):
    """The unit rows the trajectory coding length codes (width cap included)."""
    unit = unit_rows(points)
    n_samples, n_features = unit.shape
    width = min(n_features, max(n_samples // POINTS_PER_DIMENSION, 1))
    if width < n_features:
        unit = unit_rows(unit @ np.linalg.svd(unit, full_matrices=False)[2][:width].T)
    return unit


def _descending_eigenvalues(unit):
    return np.linalg.eigvalsh(unit.T @ unit)[::-1].clip(0)


def ppca_bic(points, labels):
    """BIC of a mixture of zero-mean probabilistic PCA models (Tipping & Bishop),
    one per group, each with the dimension d_k that minimises its own BIC and
    its noise variance estimated by maximum likelihood (the mean of its
    trailing eigenvalues): -2 log-likelihood + parameters * log(P), with
    D d - d (d - 1) / 2 + d + 1 parameters per group plus its weight. No
    constant is fitted."""
    unit = _capped_unit(points)
    n_samples, n_features = unit.shape
    log_n = np.log(n_samples)
    total = 0.0
    for group in np.unique(labels):
        members = unit[labels == group]
        size = members.shape[0]
        eig = _descending_eigenvalues(members) / size
        rank = int(np.sum(eig > 1e-12 * eig[0]))
        best = np.inf
        for dim in range(min(rank - 1, n_features - 1) + 1):
            noise = eig[dim:].mean()
            nll = size * (
                np.log(eig[:dim]).sum() + (n_features - dim) * (np.log(noise) + 1)
            )
            n_params = n_features * dim - dim * (dim - 1) / 2 + dim + 1
            best = min(best, nll + n_params * log_n)
        total += best - 2 * size * np.log(size / n_samples) + log_n
    return total


def parameter_margin(costs, points):
    """Bits an extra motion must save: the BIC cost of a 4-D subspace of the
    coded width, (4 D - 6) / 2 log2(P)."""
    unit = _capped_unit(points)
    n_samples, n_features = unit.shape
    return (4 * n_features - 6) / 2 * np.log2(n_samples)


def distinct_in_wide(points, labels, max_dim=3, min_ratio=1.5):
    """Whether every pair of groups is two subspaces of the rank-20 projection.

    Each group gets the dimension d_k (at most ``max_dim``) of the directions
    its coding length spends at least half a bit per point on; a pair is
    distinct when the energy of their union beyond max(d_a, d_b) is at least
    ``min_ratio`` times the sum of their own energies beyond d_a and d_b.
    """
    unit = _capped_unit(points)
    n_features = unit.shape[1]
    groups = np.unique(labels)
    eig, dims = {}, {}
    for group in groups:
        members = unit[labels == group]
        eig[group] = _descending_eigenvalues(members)
        scale = n_features / (TRAJECTORY_DISTORTION**2 * members.shape[0])
        dims[group] = int(min(max_dim, np.sum(scale * eig[group] >= 1)))
    for i, a in enumerate(groups):
        for b in groups[i + 1 :]:
            dim = max(dims[a], dims[b])
            union = _descending_eigenvalues(unit[(labels == a) | (labels == b)])
            separate = eig[a][dims[a] :].sum() + eig[b][dims[b] :].sum()
            if union[dim:].sum() < min_ratio * separate:
                return False
    return True


def by_min(costs, points, segmentations, extra):
    return int(np.argmin(costs)) + 1


def first_local_minimum(costs, points, segmentations, extra, margin=None):
    """The smallest n whose successor does not cost less (by ``margin`` bits)."""
    margin = 0.0 if margin is None else margin(costs, points)
    n = 1
    while n < len(costs) and costs[n] < costs[n - 1] - margin:
        n += 1
    return n


def among_distinct(costs, points, segmentations, extra):
    keep = [distinct_in_wide(points, labels) for labels in segmentations.values()]
    return int(np.argmin(np.where(keep, costs, np.inf))) + 1


#: Largest disagreement, with the refit on 80 % of the trajectories, of a
#: segmentation the stability rule keeps (0.01 .. 0.2 were tried).
MAX_DISAGREEMENT = 0.1


def among_stable(costs, points, segmentations, extra):
    disagreement = extra["disagreement"]
    keep = np.array([disagreement.get(n, 1.0) for n in segmentations]) <= (
        MAX_DISAGREEMENT
    )
    return int(np.argmin(np.where(keep, costs, np.inf))) + 1


DEFAULT = (
    "trajectory coding length, rank 20, refined by coordinate descent, groups "
    f">= {MIN_MOTION_POINTS} (default)"
)
UNREFINED = "trajectory coding length, rank 20, unrefined (former default)"
STABLE = (
    "trajectory coding length among the n stable on 80 % of the trajectories "
    f"(disagreement <= {MAX_DISAGREEMENT:g})"
)

#: name -> (space, criterion(points, labels), rule); space "wide" is the
#: rank-20 projection, "5" the whitened 5-D points segmented; the rule turns
#: the criterion of each n into the n found.
CRITERIA = {
    DEFAULT: ("wide", refined_trajectory_coding_length_cost, by_min),
    "trajectory coding length, refined, groups >= 9": (
        "wide",
        partial(refined_with_floor, 9),
        by_min,
    ),
    f"trajectory coding length, one round of the descent, groups >= "
    f"{MIN_MOTION_POINTS}": (
        "wide",
        partial(refined_with_floor, MIN_MOTION_POINTS, max_iter=1),
        by_min,
    ),
    "trajectory coding length, refined, no group floor": (
        "wide",
        partial(refined_with_floor, 0),
        by_min,
    ),
    UNREFINED: ("wide", trajectory_coding_length_cost, by_min),
    "trajectory coding length, no width cap": (
        "wide",
        partial(wide_at, TRAJECTORY_DISTORTION),
        by_min,
    ),
    "trajectory coding length, distortion 0.005, no width cap": (
        "wide",
        partial(wide_at, 0.005),
        by_min,
    ),
    "trajectory coding length, distortion 0.015, no width cap": (
        "wide",
        partial(wide_at, 0.015),
        by_min,
    ),
    "trajectory coding length, first local minimum": (
        "wide",
        trajectory_coding_length_cost,
        first_local_minimum,
    ),
    "trajectory coding length, each extra motion must save its BIC parameter cost": (
        "wide",
        trajectory_coding_length_cost,
        partial(first_local_minimum, margin=parameter_margin),
    ),
    "trajectory coding length among distinct subspaces of their own dimension": (
        "wide",
        trajectory_coding_length_cost,
        among_distinct,
    ),
    "PPCA BIC, a dimension per motion, noise estimated (no constant)": (
        "wide",
        ppca_bic,
        by_min,
    ),
    f"distinct coding length in R^5, merge ratio >= {MIN_MERGE_RATIO:g} "
    "(default without segmentation_dim)": (
        "5",
        partial(distinct_at, MIN_MERGE_RATIO),
        by_min,
    ),
    "coding length in R^5 (former default)": ("5", coding_length_cost, by_min),
}
STABLE_ENTRY = ("wide", trajectory_coding_length_cost, among_stable)


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


def disagreements(Z, segmentations, seed=0):
    """Misclassification, on the trajectories kept, between each segmentation
    and a refit of ``gpca`` on a random 80 % of them."""
    kept = np.sort(
        np.random.RandomState(seed).choice(
            Z.shape[0], int(0.8 * Z.shape[0]), replace=False
        )
    )
    out = {1: 0.0}
    for n, labels in segmentations.items():
        if n == 1:
            continue
        try:
            refit = gpca(Z[kept], n, random_state=2).labels
        except ValueError:
            continue
        out[n] = misclassification_rate(labels[kept], refit)
    return out


def run_one(X, y, n_true, stability=False):
    """Found n, error with it, error with the true n, seconds and the costs of
    the default, per criterion."""
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
        extra = {}
        if stability:
            extra["disagreement"] = disagreements(Z, segmentations)
            extra["seconds"] = time.perf_counter() - start - fits
    true_error = misclassification_rate(y, segmentations[n_true])
    criteria = dict(CRITERIA, **({STABLE: STABLE_ENTRY} if stability else {}))
    rows = {}
    for name, (space, criterion, rule) in criteria.items():
        start = time.perf_counter()
        points = wide if space == "wide" else Z
        costs = np.array([criterion(points, lab) for lab in segmentations.values()])
        found = rule(costs, points, segmentations, extra)
        seconds = fits + time.perf_counter() - start
        if rule is among_stable:  # the refits on 80 % of the trajectories
            seconds += extra["seconds"]
        error = misclassification_rate(y, segmentations[found])
        rows[name] = (n_true, found, error, true_error, seconds, costs)
    return rows


def miss_rows(names, runs):
    """Markdown rows: each sequence the default gets wrong, with its costs."""
    lines = [
        "| sequence | true n | found n | default's bits above its minimum, n = 1 .. 5 "
        "| error, true n | error, found n |",
        "|---|---|---|---|---|---|",
    ]
    for name, run in zip(names, runs, strict=True):
        n_true, found, error, true_error, _, costs = run[DEFAULT]
        if found == n_true:
            continue
        above = ", ".join(
            f"**{c:.0f}**" if n == n_true else f"{c:.0f}"
            for n, c in enumerate(costs - costs.min(), start=1)
        )
        lines.append(
            f"| {name} | {n_true} | {found} | {above} | {100 * true_error:.1f} % | "
            f"{100 * error:.1f} % |"
        )
    return lines


def halves(runs, name):
    """Right n on the even- and the odd-indexed sequences."""
    right = [run[name][0] == run[name][1] for run in runs]
    return (
        f"{sum(right[::2])} / {len(right[::2])} even-indexed sequences "
        f"and {sum(right[1::2])} / {len(right[1::2])} odd-indexed ones"
    )


def hopkins_items(folder, step):
    sequences = load_hopkins155(folder)[::step]
    return [(b.X, b.y, b.n_motions, b.name) for b in sequences]


def motions_items(seeds):
    items = []
    for n in range(1, MAX_N + 1):
        for seed in range(seeds):
            X, y = make_motions(
                n, n_points=100 * n, missing=0.2 * (seed % 2), random_state=seed
            )
            items.append((X, y, n, f"make_motions({n}, seed={seed})"))
    return items


def tracks_items(seeds):
    items = []
    for n in range(1, MAX_N + 1):
        for seed in range(seeds):
            X, y = make_tracks(n, scene="lab", random_state=seed)
            items.append((X, y, n, f"make_tracks({n}, seed={seed})"))
    return items


def confusion_table(results):
    """Markdown rows: true n, counts of found n, right, mean errors."""
    n_true, found, error, true_error = (
        np.array(c) for c in list(zip(*results, strict=True))[:4]
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
    n_true, found, error, _, seconds = (
        np.array(c) for c in list(zip(*results, strict=True))[:5]
    )
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
        "--stability",
        action="store_true",
        help="also refit every n on 80 %% of the trajectories (the stability rule)",
    )
    parser.add_argument(
        "--output", default=str(Path(__file__).parent / "results" / "n_motions.md")
    )
    args = parser.parse_args()
    datasets = {
        "Hopkins155": hopkins_items(args.data, args.step),
        "make_motions": motions_items(args.seeds),
        "make_tracks (lab)": tracks_items(args.seeds),
    }
    names = [*CRITERIA, *([STABLE] if args.stability else [])]
    summary, details, held_out, misses = [], [], "", []
    for dataset, items in datasets.items():
        start = time.perf_counter()
        runs = Parallel(n_jobs=args.jobs)(
            delayed(run_one)(*item[:3], stability=args.stability) for item in items
        )
        print(f"{dataset}: {len(items)} draws, {time.perf_counter() - start:.0f} s")
        if dataset == "Hopkins155":
            misses = miss_rows([item[3] for item in items], runs)
        for name in names:
            results = [run[name] for run in runs]
            summary.append(summary_row(dataset, name, results))
            print(summary[-1], flush=True)
            details += ["", f"### {dataset}: {name}", "", *confusion_table(results)]
        if dataset == "Hopkins155" and args.step == 1:
            held_out = (
                f"Default on Hopkins155: right n on {halves(runs, DEFAULT)} (the "
                "distortion and width cap of the code were chosen on the even "
                "half; the descent and the group floor have no tuned constant). "
                f"Former default: {halves(runs, UNREFINED)}."
            )
    subset = "" if args.step == 1 else f" (every {args.step}th sequence)"
    lines = [
        "# The number of motions: `GPCAClustering(n_clusters='auto')`",
        "",
        "Regenerate with `python benchmarks/bench_n_motions.py --data "
        f"../shared/data/hopkins155 --jobs {args.jobs} --step {args.step} "
        f"--seeds {args.seeds}{' --stability' if args.stability else ''}`{subset}.",
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
        "## The Hopkins155 sequences the default gets wrong",
        "",
        MISSES_NOTE,
        "",
        *misses,
        "",
        "## Confusion of true and found n",
        *details,
    ]
    write_markdown(args.output, "\n".join(lines))
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
