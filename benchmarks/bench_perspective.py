"""The perspective route against the affine route on strong-perspective tracks.

Run from the project root::

    python benchmarks/bench_perspective.py [--seeds 5] [--first-seed 0]
        [--skip-affine] [--output benchmarks/results/perspective.md]

For each setting and seed, draws ``make_tracks(n_motions, scene="driving",
outlier_fraction=0, random_state=seed, ...)``, keeps the tracks observed in 5
frames or more (KT3DMoSeg keeps those; the affine route needs 3 frames per
track), and segments them with:

- the affine route, the library's default pipeline
  ``make_pipeline(PowerFactorization(random_state=0), GPCAClustering(n,
  random_state=0))``;
- the affine oracle: each track to the nearest true rank-4 subspace on its
  observed entries (``sklearn_gpca.metrics.oracle_labels`` when the package
  has it, else the same definition below); it is given the true groups;
- the perspective route, ``PerspectiveClustering(n, random_state=0)`` with
  its defaults (fundamental matrices, homographies and windowed subspaces
  fused); with ``n_segments = 2 n`` (the kernel cut into twice as many
  segments, merged back greedily by association); the same merged by
  average linkage (``merge="average"``); and with ``partition="best_fit"``
  (the partition among those, each refined, whose clusters fit rank-4
  subspaces on windows of 4 frames best). (``n_rounds=3``, balanced guided
  samples, was in this table until commit c75158c: 12.0 / 37.2 / 18.3 % at
  4-6 times the time; each model alone until commit caf793b, fundamental
  matrices 10.9 / 50.6 / 9.2 %, homographies 25.0 / 49.3 / 32.9 %, windowed
  subspaces 6.1 / 37.8 / 20.8 %; left out to keep the run short.)
- ``segment_motions(X, n, random_state=0)``, the library's route for tracker
  output, whose candidates are also refined with the largest motion seen by
  a perspective camera (``perspective_background=True``, its default), and
  the same with ``perspective_background=False``: the affine route it is
  also judged against. (Both added on 6 Dec 2026; nothing of
  ``segment_motions`` was tuned on these settings.)

Errors are misclassification rates of the inlier tracks (outliers are a
separate item of issue 17 and left out of the draws), in percent, mean and
median over seeds; seconds are per sequence, wall clock, default BLAS threads.

What counts as strong perspective: a pinhole camera moving forward through a
scene whose depths vary by a factor 10 (``make_tracks`` "driving" scene,
KT3DMoSeg-like: focal length 721.5 px for a 1242 px wide image, about 81
degrees of horizontal field of view, depths 8-80 m, 8 m/s at 10 Hz), and the
same with a wide-angle lens closer to the scene (focal length 360 px, about
120 degrees, depths 4-40 m): the nearer and wider, the further a rigid motion
is from one rank-4 subspace over the sequence (``benchmarks/results/tracks.md``
measures the deviation for the default).

Tuning: ``PerspectiveClustering``'s defaults (``top``, ``n_neighbors``,
``window``, ``gaps``, the hypergraph normalisation and the kernel k-means
refinement) were chosen by hand on seeds 100-105 of the default "driving"
setting; the seeds reported here (0 .. seeds - 1) were not used for tuning,
and nothing was tuned on the wide-angle setting. ``n_segments = 2 n`` and
``n_rounds=3`` were chosen on seeds 100-104 of the 5-motion setting (also
tried: ``n + 2`` and ``3 n`` segments, 4 rounds; the stage diagnostics that
led to them looked at seeds 0-2 too), then checked on seeds 0-4 (this table)
and 5-9 (``--first-seed 5 --output ...``). ``merge="average"`` was chosen
among the merge rules of ``benchmarks/diagnose_perspective_merges.py``
(greedy association, average and complete linkage, greedy modularity, the
lowest normalised cut of all merges, with 2 n and 3 n segments) on seeds
100-109 of the three settings (``perspective_merges.md``), then run here.
``partition="best_fit"`` and its candidates (n, 2 n and 3 n segments, both
merge rules) and score (the windowed rank-4 residual on the windows of the
subspace votes) were chosen on seeds 100-109 of the three settings, among
other rules measured there and rejected (model-fit greedy merges of the
segments by two-view and windowed-subspace F-tests, and by rank-4 subspaces
of the whole sequence on observed entries; a robust background fit peeled
off first; divisive normalised cuts; threshold and global-sample votes;
selection by normalised cut, ratio cut, modularity, two-view residuals;
exploratory scripts, not committed; the best on 5 motions, divisive
normalised cuts, erred 28.8 % there but 12.5 % on 3 motions, default 10.7
%); seeds 0-4 (this table) and 5-9 were run once, after that choice: it
held on the wide-angle setting, not on driving 3 motions seeds 0-4 nor on
5 motions, so the default stays ``partition="spectral"``.
Writes ``benchmarks/results/perspective.md``.
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import time
import warnings
from functools import partial
from pathlib import Path

import numpy as np
from _tables import write_markdown
from sklearn.pipeline import make_pipeline

from sklearn_gpca import (
    GPCAClustering,
    PerspectiveClustering,
    PowerFactorization,
    segment_motions,
)
from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.metrics import misclassification_rate

SETTINGS = [
    ("driving (KT3DMoSeg-like), 3 motions", {"n_motions": 3}),
    ("driving, 5 motions", {"n_motions": 5}),
    (
        "driving, wide angle (f = 360 px), depths 4-40 m, 3 motions",
        {"n_motions": 3, "focal_length": 360, "depth_range": (4, 40), "n_tracks": 800},
    ),
]

#: Tracks seen in fewer frames are left out, as KT3DMoSeg does.
MIN_FRAMES = 5

FUSED = "perspective route (F + H + subspace)"
BEST_FIT = "perspective route, partition='best_fit'"
SEGMENTS = "perspective route, n_segments = 2 n_clusters (merged)"
AVERAGE = "perspective route, n_segments = 2 n_clusters, merge='average'"

#: Name: parameters of PerspectiveClustering; "n_segments" is a multiple of
#: the number of motions.
PERSPECTIVE_ROUTES = {
    FUSED: {},
    BEST_FIT: {"partition": "best_fit"},
    SEGMENTS: {"n_segments": 2},
    AVERAGE: {"n_segments": 2, "merge": "average"},
}

AFFINE = "affine route (default pipeline)"

SEGMENT = "segment_motions (largest motion by a perspective camera)"
SEGMENT_AFFINE = "segment_motions, perspective_background=False (affine)"

#: Each route beside the affine route it is judged against.
RATIOS = [
    (FUSED, AFFINE),
    (BEST_FIT, AFFINE),
    (SEGMENTS, AFFINE),
    (AVERAGE, AFFINE),
    (SEGMENT, AFFINE),
    (SEGMENT, SEGMENT_AFFINE),
]


def _oracle_fallback(X, y, subspace_dim=4, n_iter=50):
    """Nearest true rank-d subspace on each track's observed entries.

    The definition of ``sklearn_gpca.metrics.oracle_labels``: a subspace per
    group fitted to its observed entries (alternating least squares from the
    zero-filled SVD), each track to the group with the smallest residual per
    residual degree of freedom on its own observed entries.
    """
    mask = ~np.isnan(X)
    X0 = np.where(mask, X, 0.0)
    groups = np.unique(y[y != -1])
    per_dof = np.full((X.shape[0], groups.size), np.inf)
    for k, g in enumerate(groups):
        Xg, Mg = X0[y == g], mask[y == g]
        B = np.linalg.svd(Xg, full_matrices=False)[2][:subspace_dim].T
        for _ in range(n_iter):
            # rows: coefficients of each track; then the basis, row by row.
            G = np.einsum("pf,fi,fj->pij", Mg, B, B) + 1e-12 * np.eye(subspace_dim)
            Z = np.linalg.solve(G, np.einsum("pf,fi->pi", Xg, B)[..., None])[..., 0]
            H = np.einsum("pf,pi,pj->fij", Mg, Z, Z) + 1e-12 * np.eye(subspace_dim)
            B = np.linalg.solve(H, np.einsum("pf,pi->fi", Xg, Z)[..., None])[..., 0]
        G = np.einsum("pf,fi,fj->pij", mask, B, B) + 1e-12 * np.eye(subspace_dim)
        Z = np.linalg.solve(G, np.einsum("pf,fi->pi", X0, B)[..., None])[..., 0]
        residual = (np.where(mask, X0 - Z @ B.T, 0.0) ** 2).sum(axis=1)
        dof = mask.sum(axis=1) - subspace_dim
        per_dof[:, k] = np.where(dof > 0, residual / np.maximum(dof, 1), np.inf)
    return groups[np.argmin(per_dof, axis=1)]


try:
    from sklearn_gpca.metrics import oracle_labels
except ImportError:  # not merged on this branch yet
    oracle_labels = _oracle_fallback


def _timed(fit_labels):
    start = time.perf_counter()
    labels = fit_labels()
    return labels, time.perf_counter() - start


def _affine_route(X, y, n_motions):
    pipe = make_pipeline(
        PowerFactorization(random_state=0), GPCAClustering(n_motions, random_state=0)
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        labels, seconds = _timed(lambda: pipe.fit(X)[-1].labels_)
    return 100 * misclassification_rate(y, labels, noise="ignore"), seconds


def run_sequence(X, y, n_motions, affine):
    """{method: (error, seconds)} on one sequence.

    ``affine`` is a callable returning the affine route's (error, seconds),
    or None to leave the affine route out.
    """
    results = {}
    labels, seconds = _timed(lambda: oracle_labels(X, y))
    results["affine oracle (true groups given)"] = (labels, seconds)
    for name, params in PERSPECTIVE_ROUTES.items():
        params = dict(params)
        if "n_segments" in params:
            params["n_segments"] *= n_motions
        model = PerspectiveClustering(n_motions, random_state=0, **params)
        labels, seconds = _timed(lambda m=model: m.fit(X).labels_)
        results[name] = (labels, seconds)
    for name, perspective_background in [(SEGMENT, True), (SEGMENT_AFFINE, False)]:
        labels, seconds = _timed(
            lambda p=perspective_background: segment_motions(
                X, n_motions, perspective_background=p, random_state=0
            )
        )
        results[name] = (labels, seconds)
    scores = {
        name: (100 * misclassification_rate(y, labels, noise="ignore"), seconds)
        for name, (labels, seconds) in results.items()
    }
    if affine is not None:
        scores = {AFFINE: affine(), **scores}
    return scores


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument(
        "--first-seed", type=int, default=0, help="seeds first-seed .. + seeds - 1"
    )
    parser.add_argument("--skip-affine", action="store_true")
    parser.add_argument("--output", default="benchmarks/results/perspective.md")
    args = parser.parse_args()

    rows, ratios = [], []
    for setting, params in SETTINGS:
        params = dict(params)
        n_motions = params.pop("n_motions")
        per_seed, sizes = [], []
        for seed in range(args.first_seed, args.first_seed + args.seeds):
            X, y = make_tracks(
                n_motions,
                scene="driving",
                outlier_fraction=0,
                random_state=seed,
                **params,
            )
            keep = np.isfinite(X[:, 0::2]).sum(axis=1) >= MIN_FRAMES
            X, y = X[keep], y[keep]
            sizes.append((X.shape[0], np.isnan(X).mean()))
            affine = None
            if not args.skip_affine:
                affine = partial(_affine_route, X, y, n_motions)
            per_seed.append(run_sequence(X, y, n_motions, affine))
            print(setting, seed, {k: round(v[0], 1) for k, v in per_seed[-1].items()})
        tracks = np.mean([s[0] for s in sizes])
        missing = np.mean([s[1] for s in sizes])
        for name in per_seed[0]:
            errors = np.array([r[name][0] for r in per_seed])
            seconds = np.array([r[name][1] for r in per_seed])
            rows.append(
                f"| {setting} | {tracks:.0f} | {100 * missing:.0f} | {name} | "
                f"{errors.mean():.1f} | {np.median(errors):.1f} | "
                f"{' / '.join(f'{e:.1f}' for e in errors)} | {seconds.mean():.1f} |"
            )
        mean = {name: np.mean([r[name][0] for r in per_seed]) for name in per_seed[0]}
        for route, against in RATIOS:
            if against in mean:
                ratio = mean[route] / max(mean[against], 1e-12)
                ratios.append(
                    f"| {setting} | {route} | {against} | {mean[against]:.1f} | "
                    f"{mean[route]:.1f} | {ratio:.2f} |"
                )

    command = "python benchmarks/bench_perspective.py --seeds " + str(args.seeds)
    if args.first_seed:
        command += f" --first-seed {args.first_seed}"
    if args.output != parser.get_default("output"):
        command += f" --output {args.output}"
    if args.skip_affine:
        command += " --skip-affine"
    text = "\n".join(
        [
            "# Perspective route vs affine route on strong-perspective tracks",
            "",
            f"`{command}` (see the script's docstring for the settings, what "
            "counts as strong perspective and what was tuned). `make_tracks("
            "scene='driving', outlier_fraction=0)`, tracks seen in "
            f"{MIN_FRAMES} frames or more, seeds {args.first_seed}-"
            f"{args.first_seed + args.seeds - 1}; errors are "
            "misclassification rates of the tracks in percent; seconds per "
            "sequence, wall clock, default BLAS threads, on a shared 2-core "
            "machine (noisy).",
            "",
            "| setting | tracks | missing % | method | error % mean | error % "
            "median | error % per seed | s per sequence |",
            "|---|---|---|---|---|---|---|---|",
            *rows,
            "",
        ]
        + (
            [
                "Mean error of each perspective route over an affine route's "
                "(the issue asks for less than 0.5): the default pipeline, and "
                "for `segment_motions` also itself without the perspective "
                "camera:",
                "",
                "| setting | perspective route | affine route | affine route % | "
                "perspective route % | ratio |",
                "|---|---|---|---|---|---|",
                *ratios,
                "",
            ]
            if ratios
            else []
        )
    )
    write_markdown(Path(args.output), text)
    print(text)


if __name__ == "__main__":
    main()
