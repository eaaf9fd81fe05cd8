"""Real tracker output with two motions: the giraffe video's background and foreground.

Run from the project root (about 4-5 minutes per draw with two jobs)::

    python benchmarks/check_real_composite.py --fraction 0.125 --seeds 0 \
        --out benchmarks/results/real_composite.md

``Um_giraffe_bg`` and ``Um_giraffe_fg`` of the low-rank benchmarks
(``../shared/data/lowrank``, Hong & Fitzgibbon's collection) are the
background and the foreground tracks of one hand-held video: 190 frames,
6,310 and 4,885 tracks, each seen on one window of 7 to 190 consecutive
frames (median 11), about 870 seen per frame, 92 % of the entries missing.
The camera pans to follow a walking giraffe (a non-rigid motion), and the
background has depth (parallax). Stacked, they are a real two-motion
segmentation problem shaped like a tracker's output, with labels (0 the
background, 1 the giraffe) that no library setting was chosen on.

A random share ``--fraction`` of the tracks is kept per draw (seeded). Each
draw reports the nearest-subspace oracle
(:func:`sklearn_gpca.metrics.oracle_labels`, 4-D subspaces fitted to the
true groups on the observed entries; also with the background's perspective
camera), ``segment_motions(X, 2, random_state=0, n_jobs=2)`` and, with
``--pipeline``, the default pipeline (``PowerFactorization()`` +
``GPCAClustering(2)``; 7 minutes on an eighth of the tracks), with seconds.
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import datetime
import os
import platform
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np
from _tables import write_markdown
from sklearn.pipeline import make_pipeline

from sklearn_gpca import GPCAClustering, PowerFactorization, segment_motions
from sklearn_gpca.datasets import load_lowrank
from sklearn_gpca.metrics import misclassification_rate, oracle_labels

DEFAULT_DATA = Path(__file__).resolve().parents[2] / "shared" / "data" / "lowrank"


def composite(data_home, fraction, seed):
    """Background and foreground tracks stacked; a random share of them kept."""
    background = load_lowrank("Um_giraffe_bg", data_home=data_home).X
    foreground = load_lowrank("Um_giraffe_fg", data_home=data_home).X
    X = np.vstack([background, foreground])
    y = np.r_[np.zeros(len(background), int), np.ones(len(foreground), int)]
    keep = np.random.RandomState(seed).rand(len(X)) < fraction
    return X[keep], y[keep]


def _timed(call):
    clock = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        labels = call()
    return labels, time.perf_counter() - clock


def _default_pipeline(X):
    pipeline = make_pipeline(
        PowerFactorization(random_state=0), GPCAClustering(2, random_state=0)
    )
    return pipeline.fit_predict(X)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data-home", default=os.fspath(DEFAULT_DATA))
    parser.add_argument("--fraction", type=float, default=0.125)
    parser.add_argument("--seeds", type=int, nargs="+", default=[0])
    parser.add_argument(
        "--pipeline",
        action="store_true",
        help="also run the default pipeline (slow)",
    )
    parser.add_argument("--out", default=None)
    args = parser.parse_args(argv)
    if not Path(args.data_home).is_dir():
        raise SystemExit(f"low-rank data not found at {args.data_home}")
    header = (
        "| seed | tracks | background % | missing % | tracks per frame | "
        "oracle % | oracle, perspective background % | segment_motions % | s | "
        "default pipeline % | s |"
    )
    rows = [header, "|" + "---|" * (header.count("|") - 1)]
    for seed in args.seeds:
        X, y = composite(args.data_home, args.fraction, seed)
        seen = np.isfinite(X[:, 0::2])
        oracle = misclassification_rate(y, oracle_labels(X, y))
        perspective = misclassification_rate(
            y, oracle_labels(X, y, perspective_background=True)
        )
        labels, seconds = _timed(
            lambda X=X: segment_motions(X, 2, random_state=0, n_jobs=2)
        )
        pipeline_error = pipeline_seconds = "--"
        if args.pipeline:
            pipeline, seconds_pipeline = _timed(lambda X=X: _default_pipeline(X))
            pipeline_error = f"{100 * misclassification_rate(y, pipeline):.2f}"
            pipeline_seconds = f"{seconds_pipeline:.0f}"
        rows.append(
            f"| {seed} | {len(X)} | {100 * np.mean(y == 0):.1f} | "
            f"{100 * np.mean(~seen):.1f} | {np.median(seen.sum(axis=0)):.0f} | "
            f"{100 * oracle:.2f} | {100 * perspective:.2f} | "
            f"{100 * misclassification_rate(y, labels):.2f} | {seconds:.0f} | "
            f"{pipeline_error} | {pipeline_seconds} |"
        )
        print(rows[-1], flush=True)
    revision = subprocess.run(
        ["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True
    ).stdout.strip()
    command = "python benchmarks/check_real_composite.py " + " ".join(
        argv if argv is not None else sys.argv[1:]
    )
    page = [
        "# Real tracker output: the giraffe video's background and foreground",
        "",
        f"`{command}`, {datetime.datetime.now(datetime.UTC):%d %b %Y %H:%M} UTC, "
        f"revision {revision}, {os.cpu_count()} cores, {platform.machine()}, "
        "BLAS threads: the default. Errors are misclassification rates (%), "
        "seconds are wall time. See the script's docstring for the data.",
        "",
        *rows,
        "",
    ]
    text = "\n".join(page)
    print(text)
    if args.out:
        write_markdown(args.out, text)


if __name__ == "__main__":
    main()
