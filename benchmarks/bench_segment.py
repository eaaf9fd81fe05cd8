"""segment_motions against the default pipeline and the oracle.

Settings (``--setting``):

- ``hopkins``: the 155 Hopkins155 sequences, complete data;
- ``occlusion``: the 120 two-motion sequences with ~30 % of the point-frames
  removed in windows (``make_missing(X, 0.3, pattern="occlusion",
  random_state=seed)``, seed = index of the sequence);
- ``tracks``: tracker-like draws (``make_tracks`` when the datasets module has
  it, with the scene given by ``--scene``; outlier tracks removed).

For every sequence: the misclassification of ``segment_motions(X, n)``, of
its two refined candidates, of the default ``make_pipeline(
PowerFactorization(), GPCAClustering(n))`` and of the oracle
(:func:`sklearn_gpca.metrics.oracle_labels`: the nearest true 4-D subspace on
each track's observed entries); the wall time of each method; the Spearman
correlation between coding length and error over the candidates. Writes
``benchmarks/results/segment_<setting>.md``.

Usage::

    python benchmarks/bench_segment.py --setting hopkins --jobs 2
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import time
import warnings
from pathlib import Path

import numpy as np
from joblib import Parallel, delayed
from scipy.stats import spearmanr
from threadpoolctl import threadpool_limits

from sklearn_gpca import GPCAClustering, PowerFactorization
from sklearn_gpca._segment import segment_motions
from sklearn_gpca.datasets import load_hopkins155, make_missing
from sklearn_gpca.metrics import misclassification_rate, oracle_labels


def _default(X, n):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            Z = PowerFactorization(random_state=0).fit_transform(X)
            return GPCAClustering(n, random_state=0).fit_predict(Z)
        except ValueError:
            return None


def run_one(name, X, y, n, threads):
    with threadpool_limits(threads):
        inliers = y >= 0
        X, y = X[inliers], y[inliers]
        row = {"name": name, "n": n, "missing": float(np.isnan(X).mean())}
        start = time.perf_counter()
        labels, info = segment_motions(X, n, random_state=0, return_info=True)
        row["segment_s"] = time.perf_counter() - start
        row["segment"] = misclassification_rate(y, labels)
        row["candidates"] = {
            c: misclassification_rate(y, r)
            for c, r in zip(info.candidates, info.refined, strict=True)
        }
        errors = list(row["candidates"].values())
        row["coding_agrees"] = (
            float(spearmanr(info.coding_lengths, errors)[0])
            if len(errors) > 2 and np.ptp(errors) > 0
            else np.nan
        )
        # with two candidates: did the coding length pick the better one?
        row["coding_right"] = (
            float(errors[info.chosen] == min(errors)) if np.ptp(errors) > 0 else np.nan
        )
        start = time.perf_counter()
        default = _default(X, n)
        row["default_s"] = time.perf_counter() - start
        row["default"] = (
            np.nan if default is None else misclassification_rate(y, default)
        )
        row["oracle"] = misclassification_rate(y, oracle_labels(X, y))
    return row


def sequences(setting, data, scene, n_draws):
    if setting in ("hopkins", "occlusion"):
        for index, bunch in enumerate(load_hopkins155(data)):
            if setting == "hopkins":
                yield bunch.name, bunch.X, bunch.y, bunch.n_motions
            elif bunch.n_motions == 2:
                X = make_missing(bunch.X, 0.3, pattern="occlusion", random_state=index)
                yield bunch.name, X, bunch.y, 2
        return
    from sklearn_gpca import datasets

    make_tracks = datasets.make_tracks
    found, seed = 0, 0
    while found < n_draws and seed < 10 * n_draws:
        try:
            X, y = make_tracks(scene=scene, random_state=seed)
        except ValueError:
            seed += 1
            continue
        yield f"{scene}-{seed}", X, y, int(np.unique(y[y >= 0]).size)
        found += 1
        seed += 1


def _mean(rows, key, n=None):
    values = [r[key] for r in rows if n is None or r["n"] == n]
    return 100 * np.nanmean(values) if values else np.nan


def write(rows, setting, command, out):
    names = sorted({c for r in rows for c in r["candidates"]})
    for r in rows:
        for c in names:
            r[f"cand_{c}"] = r["candidates"].get(c, np.nan)
    groups = [("all", None)] + [
        (f"{k} motions", k) for k in sorted({r["n"] for r in rows})
    ]
    header = (
        "| method | "
        + " | ".join(g for g, _ in groups)
        + " | median | > 5 % | median s |"
    )
    lines = [
        f"# segment_motions: {setting}",
        "",
        f"`{command}`. Misclassification (%) of inlier tracks, mean per group of "
        "sequences; median over all; number of sequences above 5 %; median wall "
        "time per sequence. *oracle*: nearest true 4-D subspace on each track's "
        "observed entries (`sklearn_gpca.metrics.oracle_labels`).",
        "",
        header,
        "|---" * (len(groups) + 4) + "|",
    ]
    methods = [("segment_motions", "segment", "segment_s")]
    methods += [(f"  candidate {c}, refined", f"cand_{c}", None) for c in names]
    methods += [
        ("default pipeline", "default", "default_s"),
        ("oracle", "oracle", None),
    ]
    for label, key, tkey in methods:
        values = 100 * np.array([r[key] for r in rows], dtype=float)
        cells = [f"{_mean(rows, key, n):.2f}" for _, n in groups]
        cells += [
            f"{np.nanmedian(values):.2f}",
            f"{int(np.sum(values > 5))}",
            f"{np.median([r[tkey] for r in rows]):.3f}" if tkey else "",
        ]
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    right = np.array([r["coding_right"] for r in rows], dtype=float)
    best = 100 * np.mean([min(r["candidates"].values()) for r in rows])
    lines += [
        "",
        f"Best refined candidate in hindsight: {best:.2f} %. Where the candidates' "
        f"errors differ ({int(np.isfinite(right).sum())} sequences), the shortest "
        f"coding length is the better candidate on {int(np.nansum(right))}.",
        "",
    ]
    Path(out).write_text("\n".join(lines))
    print("\n".join(lines))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--setting", default="hopkins", choices=["hopkins", "occlusion", "tracks"]
    )
    parser.add_argument("--data", default="../shared/data/hopkins155")
    parser.add_argument("--scene", default="handheld")
    parser.add_argument("--draws", type=int, default=10)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--subset", type=int, default=1, help="every k-th sequence")
    parser.add_argument("--out", default=None)
    args = parser.parse_args()
    threads = 1 if args.jobs > 1 else None
    todo = list(sequences(args.setting, args.data, args.scene, args.draws))[
        :: args.subset
    ]
    rows = Parallel(n_jobs=args.jobs)(
        delayed(run_one)(name, X, y, n, threads) for name, X, y, n in todo
    )
    suffix = args.setting if args.setting != "tracks" else f"tracks_{args.scene}"
    out = args.out or str(Path(__file__).parent / "results" / f"segment_{suffix}.md")
    command = (
        "python benchmarks/bench_segment.py"
        f" --setting {args.setting} --jobs {args.jobs}"
        + (f" --subset {args.subset}" if args.subset > 1 else "")
        + (
            f" --scene {args.scene} --draws {args.draws}"
            if args.setting == "tracks"
            else ""
        )
    )
    write(rows, args.setting, command, out)


if __name__ == "__main__":
    main()
