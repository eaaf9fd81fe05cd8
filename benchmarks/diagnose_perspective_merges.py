"""Where the perspective route loses 5 motions: each stage against the truth.

Run from the project root::

    python benchmarks/diagnose_perspective_merges.py [--seeds 5]
        [--first-seed 100] [--jobs 2]
        [--output benchmarks/results/perspective_merges.md]

Draws the settings of ``bench_perspective.py`` (``make_tracks(scene=
"driving")``, 3 and 5 motions, and the wide-angle 3 motions; tracks seen in 5
frames or more), computes ``PerspectiveClustering``'s fused votes once per
draw (its defaults, ``random_state=0``) and clusters the same kernel
``K = votes @ votes.T`` with several rules, all reaching ``n`` clusters:

- ``n`` segments: the default (spectral embedding, k-means, kernel k-means
  refinement of the normalised cut);
- ``m n`` segments (``m`` = 2, 3), then merged to ``n``: greedily by
  normalised association ``W_AB / sqrt(vol_A vol_B)`` recomputed after every
  merge (``n_segments = m n``, the option of the library); by average
  (``merge="average"``) or complete linkage of the segments' pairwise
  normalised association (scipy);
  greedily by modularity gain ``W_AB - vol_A vol_B / vol``; for ``m = 2``,
  the merge with the lowest normalised cut among all partitions of the
  segments into ``n`` groups (enumerated: 42,525 for 10 segments into 5);
  each merged labelling is refined by kernel k-means as in the library;
- the purity of the ``m n`` segments: the error if every segment took its
  majority true motion, the lowest error any merge of them can reach;
- selection among the default, association and average-linkage merges by
  self-consistency: the candidate whose labels the nearest rank-4 subspace
  on observed entries (``metrics.oracle_labels`` fed the candidate's labels)
  changes least;
- selection among the default and the 2 n and 3 n segments merged by
  association and by average linkage by the model: the candidate whose
  clusters fit rank-4 subspaces on windows of 4 frames best (the smallest
  residual, ``PerspectiveClustering(partition="best_fit")``; the library
  draws its candidates with one random state in turn, so its labels may
  differ slightly);
- started from the truth: the kernel k-means refinement (does the normalised
  cut keep the true motions?).

Errors are misclassification rates in percent, mean over seeds, with the
per-seed values. Nothing is tuned here: it measures the rules. Writes
``benchmarks/results/perspective_merges.md``.
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
from pathlib import Path

import numpy as np
from _tables import write_markdown
from joblib import Parallel, delayed

SETTINGS = [
    ("driving, 3 motions", {"n_motions": 3}),
    ("driving, 5 motions", {"n_motions": 5}),
    (
        "wide angle, 3 motions",
        {"n_motions": 3, "focal_length": 360, "depth_range": (4, 40), "n_tracks": 800},
    ),
]
MIN_FRAMES = 5
MULTIPLES = (2, 3)


def _draw(params, seed):
    from sklearn_gpca.datasets import make_tracks

    params = dict(params)
    n = params.pop("n_motions")
    X, y = make_tracks(
        n, scene="driving", outlier_fraction=0, random_state=seed, **params
    )
    keep = np.isfinite(X[:, 0::2]).sum(axis=1) >= MIN_FRAMES
    return X[keep], y[keep], n


def _segments(votes, k):
    from sklearn.utils import check_random_state

    from sklearn_gpca._perspective import (
        refine_normalized_cut,
        spectral_embedding_votes,
    )
    from sklearn_gpca._spectral import embedding_kmeans

    embedding = spectral_embedding_votes(votes, k, check_random_state(0))
    labels = embedding_kmeans(
        embedding, k, n_init=10, random_state=check_random_state(0)
    )
    return refine_normalized_cut(votes, labels, k, 30)[0]


def _segment_weights(votes, labels, k):
    from sklearn_gpca._perspective import _indicator

    Z = votes.T @ _indicator(labels, k)
    return np.asarray(Z.T @ Z)


def _linkage_merge(weights, n, method):
    from scipy.cluster.hierarchy import cut_tree, linkage
    from scipy.spatial.distance import squareform

    volumes = weights.sum(axis=1)
    association = weights / np.sqrt(np.outer(volumes, volumes))
    distance = association.max() - association
    np.fill_diagonal(distance, 0.0)
    tree = linkage(squareform(distance, checks=False), method=method)
    return cut_tree(tree, n_clusters=n).ravel()


def _modularity_merge(weights, n):
    weights = weights.astype(float)
    volumes = weights.sum(axis=1)
    total = volumes.sum()
    alive = np.ones(weights.shape[0], dtype=bool)
    merged_into = np.arange(weights.shape[0])
    for _ in range(weights.shape[0] - n):
        gain = weights - np.outer(volumes, volumes) / total
        np.fill_diagonal(gain, -np.inf)
        gain[~alive] = gain[:, ~alive] = -np.inf
        i, j = np.unravel_index(np.argmax(gain), gain.shape)
        weights[i] += weights[j]
        weights[:, i] += weights[:, j]
        volumes[i] += volumes[j]
        alive[j] = False
        merged_into[merged_into == j] = i
    return np.unique(merged_into, return_inverse=True)[1]


def _set_partitions(k, n):
    """All partitions of ``k`` items into ``n`` non-empty blocks, as rows of
    block labels (restricted growth strings)."""
    found = []

    def grow(prefix, n_blocks):
        if len(prefix) == k:
            if n_blocks == n:
                found.append(prefix)
            return
        if n - n_blocks > k - len(prefix):
            return
        for block in range(min(n_blocks + 1, n)):
            grow([*prefix, block], max(n_blocks, block + 1))

    grow([0], 1)
    return np.array(found)


def _lowest_ncut_merge(weights, n):
    partitions = _set_partitions(weights.shape[0], n)
    members = np.zeros((*partitions.shape, n))
    np.put_along_axis(members, partitions[..., None], 1.0, axis=2)
    within = np.einsum("pkc,kl,plc->pc", members, weights, members)
    volumes = np.einsum("pkc,k->pc", members, weights.sum(axis=1))
    ncut = np.sum(1.0 - within / volumes, axis=1)
    return partitions[np.argmin(ncut)]


def _purity_error(y, labels):
    wrong = sum(
        np.sum(labels == s) - np.bincount(y[labels == s]).max()
        for s in np.unique(labels)
    )
    return 100 * wrong / y.size


def one(setting, params, seed):
    from sklearn.utils import check_random_state

    from sklearn_gpca._perspective import (
        MODELS,
        fused_votes,
        merge_segments,
        refine_normalized_cut,
        window_moments,
        windowed_fit_residual,
    )
    from sklearn_gpca.metrics import misclassification_rate, oracle_labels

    X, y, n = _draw(params, seed)
    votes = fused_votes(
        X,
        MODELS,
        n_hypotheses=100,
        top=0.05,
        gaps=(1, 2, 4, 8),
        window=4,
        n_neighbors=10,
        rng=check_random_state(0),
    )

    def error(labels):
        return 100 * misclassification_rate(y, labels)

    def refined(labels):
        return refine_normalized_cut(votes, labels, n, 30)[0]

    row, candidates = {}, {}
    candidates["n"] = _segments(votes, n)
    fitted = {"n": candidates["n"]}
    row["n segments (default)"] = error(candidates["n"])
    for m in MULTIPLES:
        segments = _segments(votes, m * n)
        weights = _segment_weights(votes, segments, m * n)
        row[f"{m}n segments: purity (best any merge reaches)"] = _purity_error(
            y, segments
        )
        association = refined(merge_segments(votes, segments, n))
        row[f"{m}n segments, greedy association (n_segments={m}n)"] = error(association)
        average = refined(merge_segments(votes, segments, n, rule="average"))
        row[f"{m}n segments, average linkage (merge='average')"] = error(average)
        complete = refined(_linkage_merge(weights, n, "complete")[segments])
        row[f"{m}n segments, complete linkage"] = error(complete)
        if m == 2:
            candidates["average"] = average
        fitted[f"{m}n association"] = association
        fitted[f"{m}n average"] = average
        row[f"{m}n segments, greedy modularity"] = error(
            refined(_modularity_merge(weights, n)[segments])
        )
        if m == 2:
            candidates["association"] = association
            row["2n segments, lowest normalised cut of all merges"] = error(
                refined(_lowest_ncut_merge(weights, n)[segments])
            )
    changed = {
        name: np.mean(oracle_labels(X, labels) != labels)
        for name, labels in candidates.items()
    }
    chosen = min(changed, key=changed.get)
    row["most self-consistent of n, 2n association, 2n average"] = error(
        candidates[chosen]
    )
    coords = window_moments(X, 4)
    residuals = {
        name: windowed_fit_residual(coords, labels, n)
        for name, labels in fitted.items()
    }
    row["best windowed fit of n, 2n and 3n merged (partition='best_fit')"] = error(
        fitted[min(residuals, key=residuals.get)]
    )
    row["truth, refined by kernel k-means"] = error(refined(y.copy()))
    return setting, seed, row


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--first-seed", type=int, default=100)
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--output", default="benchmarks/results/perspective_merges.md")
    args = parser.parse_args()
    seeds = range(args.first_seed, args.first_seed + args.seeds)
    results = Parallel(n_jobs=args.jobs)(
        delayed(one)(setting, params, seed)
        for setting, params in SETTINGS
        for seed in seeds
    )
    rows = []
    for setting, _ in SETTINGS:
        mine = [r for s, _, r in results if s == setting]
        for rule in mine[0]:
            errors = np.array([r[rule] for r in mine])
            rows.append(
                f"| {setting} | {rule} | {errors.mean():.1f} | "
                f"{' / '.join(f'{e:.1f}' for e in errors)} |"
            )
    command = "python benchmarks/diagnose_perspective_merges.py"
    command += f" --seeds {args.seeds} --first-seed {args.first_seed}"
    text = "\n".join(
        [
            "# Perspective route: segment and merge rules against the truth",
            "",
            f"`{command}` (see the script's docstring). The fused votes of "
            "`PerspectiveClustering`'s defaults, computed once per draw, "
            "clustered by each rule; `make_tracks(scene='driving', "
            f"outlier_fraction=0)`, tracks seen in {MIN_FRAMES} frames or "
            f"more, seeds {seeds.start}-{seeds.stop - 1}; misclassification "
            "in percent.",
            "",
            "| setting | rule | error % mean | error % per seed |",
            "|---|---|---|---|",
            *rows,
            "",
        ]
    )
    write_markdown(Path(args.output), text)
    print(text)


if __name__ == "__main__":
    main()
