"""Time and peak memory of the default pipeline against the number of points.

For P = 10^3 ... 10^6 trajectories of 10 frames, 3 motions, 10 % of the
entries missing (``make_motions(3, n_points=P, n_frames=10, noise=1.0,
missing=0.1, random_state=0)``), fits

- the default ``make_pipeline(PowerFactorization(), GPCAClustering(3))``,
- the paper's all-pairs ``cos^2`` kernel route ``GPCAClustering(3,
  normalize=False, point_normals="one_polynomial", affinity="all_pairs",
  affinity_power=1, refine=False)``
  on the default PowerFactorization output,
- :class:`sklearn.cluster.SpectralClustering` with ``affinity="precomputed"``
  on the same kernel as a dense ``P x P`` array (while it fits in memory),

each configuration and size in a fresh subprocess, whose peak resident set
size it reads from ``resource.getrusage(RUSAGE_SELF).ru_maxrss`` (kB on
Linux) before exiting. Time is the median
wall time of the fits in the subprocess (data generation excluded); peak
memory includes the data. Writes ``benchmarks/results/scaling.md``.

Usage::

    python benchmarks/bench_scaling.py
    python benchmarks/bench_scaling.py --sizes 100000 1000000  # update rows

The raw results are kept in ``benchmarks/results/scaling.json``; a run with
``--sizes`` replaces those rows and keeps the others.
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
from _tables import write_markdown

SIZES = [1_000, 3_000, 10_000, 30_000, 100_000, 300_000, 1_000_000]
# every time is the median of this many fits in one subprocess
REPEATS = 3
CONFIGS = ["default", "wide", "rank8", "dense_kernel", "sklearn_dense"]
# dense P x P float64 affinity: 10^4 is 0.8 GB; 10^5 would be 80 GB
DENSE_MAX = 10_000

CHILD = r"""
import json, sys, time
import numpy as np
from sklearn.pipeline import make_pipeline
from sklearn_gpca import GPCAClustering, PowerFactorization
from sklearn_gpca.datasets import make_motions
from sklearn_gpca.metrics import misclassification_rate

config, n, repeats = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
sizes = [n - 2 * (n // 3), n // 3, n // 3]
X, y = make_motions(3, n_points=sizes, n_frames=10, noise=1.0, missing=0.1,
                    random_state=0)
PAPER = dict(normalize=False, point_normals="one_polynomial",
             affinity="all_pairs", affinity_power=1, refine=False)
times, cpus, errors = [], [], []
if config != "none":
    Z = None
    if config in ("dense_kernel", "sklearn_dense"):
        Z = PowerFactorization(random_state=0).fit_transform(X)
    for _ in range(repeats):
        start = time.perf_counter()
        cpu = time.process_time()
        if config == "default":
            pipe = make_pipeline(
                PowerFactorization(random_state=0), GPCAClustering(3, random_state=0)
            )
            labels = pipe.fit_predict(X)
        elif config == "wide":
            labels = GPCAClustering(3, segmentation_dim=5, input_subspace_dim=4,
                                    random_state=0).fit_predict(X)
        elif config == "rank8":
            labels = make_pipeline(
                PowerFactorization(8, whiten=False, random_state=0),
                GPCAClustering(3, segmentation_dim=5, input_subspace_dim=4,
                               random_state=0),
            ).fit_predict(X)
        elif config == "dense_kernel":
            labels = GPCAClustering(3, random_state=0, **PAPER).fit_predict(Z)
        else:
            from sklearn.cluster import SpectralClustering
            from sklearn_gpca._spectral import normal_subspace_features
            gpca = GPCAClustering(3, random_state=0, **PAPER).fit(Z)
            phi = normal_subspace_features(gpca.point_normals_)
            affinity = phi @ phi.T
            labels = SpectralClustering(
                3, affinity="precomputed", random_state=0
            ).fit_predict(affinity)
            del affinity
        times.append(time.perf_counter() - start)
        cpus.append(time.process_time() - cpu)
        errors.append(misclassification_rate(y, labels))
oracle = full_oracle = refined = equal = None
if config == "default":
    from sklearn_gpca.metrics import oracle_labels
    # the nearest true subspace in R^{2F}, on each track's observed entries
    full_oracle = misclassification_rate(y, oracle_labels(X, y))
    # error floor of the draw in R^5: each point to the nearest of the
    # hyperplanes fitted to the true groups of the projected unit points
    from sklearn_gpca._subspaces import fit_subspace, sine_residuals
    Z = pipe[0].transform(X)
    U = Z / np.linalg.norm(Z, axis=1, keepdims=True)
    bases = [fit_subspace(U[y == k], 4, 0.0) for k in range(3)]
    oracle = misclassification_rate(y, np.argmin(sine_residuals(U, bases), axis=1))
    # the equal-weight vote cut on the same projection (selection rule only)
    equal = misclassification_rate(y, GPCAClustering(
        3, vote_weighting="equal", random_state=0).fit_predict(Z))
import resource
print(json.dumps({"time": float(np.median(times)) if times else 0.0,
                  "error": float(np.median(errors)) if errors else 0.0,
                  "cpu": float(np.median(cpus)) if cpus else 0.0,
                  "oracle": oracle, "full_oracle": full_oracle,
                  "refined": refined, "equal": equal,
                  "peak_gb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6}))
"""


def run(config, n, repeats):
    out = subprocess.run(
        [sys.executable, "-c", CHILD, config, str(n), str(repeats)],
        check=True,
        capture_output=True,
        text=True,
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=SIZES)
    parser.add_argument("--repeats", type=int, default=REPEATS)
    parser.add_argument("--out", default="benchmarks/results/scaling.md")
    parser.add_argument(
        "--configs",
        nargs="+",
        default=CONFIGS,
        choices=CONFIGS,
        help="the routes to run ('default' carries the references)",
    )
    args = parser.parse_args()
    # rows of earlier runs, replaced by the sizes run now: a subset of --sizes
    # updates those rows of the table and keeps the others
    raw = Path(args.out).with_suffix(".json")
    kept = json.loads(raw.read_text()) if raw.is_file() else []
    rows = [row for row in kept if row["n"] not in args.sizes]
    for n in args.sizes:
        row = {"n": n, "data": run("none", n, 1)}
        print(n, "data", row["data"], flush=True)
        for config in args.configs:
            if config == "sklearn_dense" and n > DENSE_MAX:
                continue
            row[config] = run(config, n, args.repeats)
            print(n, config, row[config], flush=True)
        rows.append(row)
        rows.sort(key=lambda row: row["n"])
        # after every size, so that an interrupted run keeps its rows
        raw.parent.mkdir(parents=True, exist_ok=True)
        raw.write_text(json.dumps(rows, indent=1) + "\n")
    write(rows, args.out, args.repeats)


def _fmt(result, key, digits):
    if result is None:
        return "—"
    value = result[key]
    return "—" if value is None else f"{value:.{digits}f}"


def write(rows, out, repeats=REPEATS):
    lines = [
        "# Scaling with the number of trajectories",
        "",
        "`python benchmarks/bench_scaling.py`. Data: `make_motions(3, "
        "n_points=P, n_frames=10, noise=1.0, missing=0.1, random_state=0)` "
        "(20 features, 10 % of the point-frames missing). Every cell runs in "
        "a fresh subprocess on a shared 2-core machine (default threading); "
        f"time is the median wall time of {repeats} fit(s) (data generation "
        "excluded; CPU s: the process's CPU time, all threads), peak is "
        "the subprocess's peak "
        "resident memory including the data (GB), error the misclassification "
        "(%). *default*: `make_pipeline(PowerFactorization(), "
        "GPCAClustering(3))`. *dense kernel*: the paper's `cos^2` kernel "
        "(`GPCAClustering(3, normalize=False, point_normals='one_polynomial', "
        "affinity='all_pairs', affinity_power=1, refine=False)`, computed through "
        "its rank-15 factor) on the default PowerFactorization output, whose "
        "time excludes the projection. *sklearn*: `SpectralClustering(3, "
        "affinity='precomputed')` on the same kernel as a dense `P x P` array "
        "(time includes building it, excludes the projection); '—' where it "
        "does not fit in memory (10^5 points: 80 GB). The ratio is sklearn's "
        "time over the dense-kernel route's. *Nearest true hyperplane*: each "
        "point of the default projection to the nearest of the hyperplanes "
        "fitted to the true groups: how much the motions of the draw overlap "
        "in R^5 (three 4-D motions span 12 dimensions; projected to R^5 they "
        "overlap, more in some draws than in others). The default's smoothing "
        "term lets it do better than this reference. *Nearest true subspace "
        "R^{2F}*: `sklearn_gpca.metrics.oracle_labels`, each track to the "
        "nearest of the 4-D subspaces fitted to the true groups in the full "
        "space, on its observed entries (no smoothing: the default can beat "
        "it). *raw tracks, full space*: `GPCAClustering(3, segmentation_dim=5, "
        "input_subspace_dim=4)` on the raw tracks (NaN where missing), the "
        "recommended estimator for many tracks: it projects them by "
        "`PowerFactorization(5)` and segments them there as the default does "
        "(the same labels), then reassigns every track once in R^{2F} on its "
        "observed entries (`sklearn_gpca.stages.reassign_full_space`: 4-D "
        "subspaces fitted to the groups on 20,000 tracks, refitted twice "
        "without the tracks another subspace fits better and each group's "
        "worst-fitted 20 %; a track leaves its R^5 label only when another "
        "subspace fits it better by more than one typical misfit). *gap*: "
        "its error minus the nearest true subspace's (issue 16: at most 0.5 "
        "point). *rank-8 pipeline*: `make_pipeline(PowerFactorization(8, "
        "whiten=False), GPCAClustering(3, segmentation_dim=5, "
        "input_subspace_dim=4))`, the same reassignment on the completed "
        "rank-8 coordinates. *Equal-weight vote cut*: "
        "`GPCAClustering(3, vote_weighting='equal')` "
        "on the default projection (the selection rule the default was before "
        "the confidence weighting). The default's peak includes these "
        "reference computations.",
        "",
        "| P | data only peak GB | default s | default CPU s "
        "| default µs / point "
        "| default peak GB | default error % "
        "| raw tracks, full space s (CPU s) | raw tracks, full space peak GB "
        "| raw tracks, full space error % "
        "| nearest true subspace R^{2F} error % | gap (points) "
        "| rank-8 pipeline s | rank-8 pipeline peak GB "
        "| rank-8 pipeline error % "
        "| equal-weight vote cut error % "
        "| nearest true hyperplane R^5 error % "
        "| dense kernel s | dense kernel peak GB | dense kernel error % "
        "| sklearn dense s | sklearn peak GB | sklearn error % | sklearn / ours |",
        "|" + "---|" * 24,
    ]
    for row in rows:
        sk = row.get("sklearn_dense")
        wide, rank8 = row.get("wide"), row.get("rank8")
        reference = row["default"]["full_oracle"]
        dense = row.get("dense_kernel")
        ratio = f"{sk['time'] / dense['time']:.0f}x" if sk else "—"
        cells = [
            f"{row['n']:,}",
            _fmt(row["data"], "peak_gb", 2),
            _fmt(row["default"], "time", 2),
            _fmt(row["default"], "cpu", 2),
            f"{1e6 * row['default']['time'] / row['n']:.1f}",
            _fmt(row["default"], "peak_gb", 2),
            f"{100 * row['default']['error']:.2f}",
            f"{wide['time']:.2f} ({wide['cpu']:.2f})" if wide else "—",
            _fmt(wide, "peak_gb", 2),
            f"{100 * wide['error']:.2f}" if wide else "—",
            f"{100 * reference:.2f}",
            f"{100 * (wide['error'] - reference):+.2f}" if wide else "—",
            _fmt(rank8, "time", 2),
            _fmt(rank8, "peak_gb", 2),
            f"{100 * rank8['error']:.2f}" if rank8 else "—",
            _fmt({"e": 100 * (row["default"].get("equal") or np.nan)}, "e", 2),
            f"{100 * row['default']['oracle']:.2f}",
            _fmt(dense, "time", 2),
            _fmt(dense, "peak_gb", 2),
            f"{100 * dense['error']:.2f}" if dense else "—",
            _fmt(sk, "time", 2),
            _fmt(sk, "peak_gb", 2),
            f"{100 * sk['error']:.2f}" if sk else "—",
            ratio,
        ]
        lines.append("| " + " | ".join(cells) + " |")
    sizes = np.array([row["n"] for row in rows], dtype=float)
    seconds = np.array([row["default"]["time"] for row in rows])
    if sizes.size >= 2:
        # time = fixed + per_point * P, least squares over the sizes
        (per_point, fixed), *_ = np.linalg.lstsq(
            np.c_[sizes, np.ones_like(sizes)], seconds, rcond=None
        )
        lines += [
            "",
            f"Growth of the default pipeline: time ~ {fixed:.1f} s + "
            f"{1e6 * per_point:.1f} µs x P (least squares over the rows). The "
            "fixed part is the work on bounded subsamples (PowerFactorization's "
            "restarts on at most 5,000 rows, the graph route of GPCAClustering "
            "on at most 5,000 points); the rest is linear in P (chunked "
            "least-squares polish, Veronese Gram matrix, gradients, smoothed "
            "K-subspaces on all points). Peak memory grows linearly with the "
            "data.",
        ]
    lines += [
        "",
        "Where the default's error comes from, and why the full space helps "
        "only anchored: `benchmarks/results/scaling_stages.md` "
        "(`benchmarks/check_scaling_stages.py`). The error is made by the "
        "graph route on its 5,000-point subsample in R^5 and carried over by "
        "the extension; K-subspaces on all points changes little. In R^5 the "
        "three motions overlap, and the neighbours of the smoothing term mix "
        "motions there: smoothed K-subspaces in R^{2F} with those neighbours "
        "(`refine_full_space`) keeps or adds errors, and unsmoothed rounds "
        "drift from the truth. One assignment in R^{2F}, anchored to the "
        "default's labels, keeps what the R^5 smoothing got right and "
        "corrects what the full space decides clearly.",
    ]
    write_markdown(out, "\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
