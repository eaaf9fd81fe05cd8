"""segment_motions with a tracker's outlier tracks kept: screening on and off.

Run from the project root (about 10 minutes with 2 draws per setting)::

    python benchmarks/bench_screening.py --draws 2

Every ``bench_segment.py --setting tracks`` setting, drawn with
``make_tracks``' own outlier tracks (3-5 % of the tracks: random walks and
drifts from one motion to another), which ``bench_segment.py`` removes. Per
setting, the misclassification (%) of the inlier tracks (mean over the
draws) of ``segment_motions(X, n, random_state=0)`` with
``screen_outliers=True`` (the default: tracks flagged by the outlier test at
1e-3 set aside while the motions are found, then given the nearest motion)
and ``False``, of the default on the draw with its outlier tracks removed
(what a perfect outlier filter would give) and of the oracle (nearest true
4-D subspace on observed entries). Seconds: median wall time per draw of
each ``segment_motions`` call, in this process. With ``--hopkins DATA``, the
same two settings of ``screen_outliers`` on every ``--step``-th Hopkins155
sequence (complete data, no outlier tracks). Writes
``benchmarks/results/screening.md`` and its CSV tables.
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import os
import time
import warnings
from pathlib import Path

import numpy as np
from _tables import write_markdown
from bench_segment import TRACK_SETTINGS

from sklearn_gpca import segment_motions
from sklearn_gpca.datasets import load_hopkins155, make_tracks
from sklearn_gpca.metrics import misclassification_rate, oracle_labels

RESULTS = Path(__file__).parent / "results"


def _timed(X, n, **params):
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        labels = segment_motions(X, n, random_state=0, **params)
    return labels, time.perf_counter() - start


def track_rows(n_draws, first_seed):
    rows = []
    for setting, params in TRACK_SETTINGS.items():
        errors, seconds = [], []
        for seed in range(first_seed, first_seed + n_draws):
            X, y = make_tracks(**params, random_state=seed)
            inliers = y >= 0
            n = int(np.unique(y[inliers]).size)
            screened, t_on = _timed(X, n)
            plain, t_off = _timed(X, n, screen_outliers=False)
            clean, _ = _timed(X[inliers], n)
            oracle = oracle_labels(X[inliers], y[inliers])
            errors.append(
                [
                    misclassification_rate(y[inliers], screened[inliers]),
                    misclassification_rate(y[inliers], plain[inliers]),
                    misclassification_rate(y[inliers], clean),
                    misclassification_rate(y[inliers], oracle),
                    np.mean(~inliers),
                ]
            )
            seconds.append([t_on, t_off])
            print(setting, seed, np.round(100 * np.array(errors[-1]), 1), flush=True)
        rows.append((setting, np.mean(errors, axis=0), np.median(seconds, axis=0)))
    return rows


def hopkins_rows(data, step):
    errors, seconds = [], []
    for i, bunch in enumerate(load_hopkins155(data)):
        if i % step:
            continue
        on, t_on = _timed(bunch.X, bunch.n_motions)
        off, t_off = _timed(bunch.X, bunch.n_motions, screen_outliers=False)
        errors.append(
            [misclassification_rate(bunch.y, on), misclassification_rate(bunch.y, off)]
        )
        seconds.append([t_on, t_off])
    return len(errors), np.mean(errors, axis=0), np.median(seconds, axis=0)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--draws", type=int, default=2)
    parser.add_argument("--first-seed", type=int, default=0)
    parser.add_argument("--hopkins", default=None, help="Hopkins155 data home")
    parser.add_argument("--step", type=int, default=5)
    parser.add_argument("--out", default=str(RESULTS / "screening.md"))
    args = parser.parse_args(argv)
    command = "python benchmarks/bench_screening.py --draws {}{}".format(
        args.draws,
        "" if args.hopkins is None else f" --hopkins {args.hopkins} --step {args.step}",
    )
    if args.first_seed:
        command += f" --first-seed {args.first_seed}"
    threads = os.environ.get("OMP_NUM_THREADS", "the machine default")
    start = time.perf_counter()
    rows = track_rows(args.draws, args.first_seed)
    lines = [
        "# segment_motions with a tracker's outlier tracks kept",
        "",
        f"`{command}` ({time.perf_counter() - start:.0f} s, OMP_NUM_THREADS="
        f"{threads}). Misclassification (%) of the inlier tracks, mean over "
        f"draws {args.first_seed}-{args.first_seed + args.draws - 1} of each "
        "setting of `bench_segment.py --setting tracks`, drawn with "
        "`make_tracks`' own outlier tracks (kept here, removed there). "
        "*screened*: `segment_motions(X, n)` (default `screen_outliers=True`: "
        "the tracks the outlier test flags at 1e-3 are set aside while the "
        "motions are found, then given the nearest motion); *not screened*: "
        "`screen_outliers=False`; *outliers removed*: the default on the "
        "inlier tracks only; *oracle*: the nearest true 4-D subspace on "
        "observed entries. Seconds: median wall time of one call.",
        "",
        "| setting | outlier tracks % | screened | not screened | outliers removed "
        "| oracle | s screened | s not screened |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for setting, e, s in rows:
        lines.append(
            f"| {setting} | {100 * e[4]:.1f} | {100 * e[0]:.2f} | {100 * e[1]:.2f} "
            f"| {100 * e[2]:.2f} | {100 * e[3]:.2f} | {s[0]:.1f} | {s[1]:.1f} |"
        )
    mean = np.mean([e for _, e, _ in rows], axis=0)
    lines.append(
        f"| all | {100 * mean[4]:.1f} | {100 * mean[0]:.2f} | {100 * mean[1]:.2f} "
        f"| {100 * mean[2]:.2f} | {100 * mean[3]:.2f} | | |"
    )
    if args.hopkins is not None:
        count, e, s = hopkins_rows(args.hopkins, args.step)
        lines += [
            "",
            f"Hopkins155, every {args.step}th sequence ({count}, complete data, "
            "no outlier tracks): misclassification (%) and median seconds.",
            "",
            "| screen_outliers | error % | s |",
            "|---|---|---|",
            f"| True (default) | {100 * e[0]:.2f} | {s[0]:.2f} |",
            f"| False | {100 * e[1]:.2f} | {s[1]:.2f} |",
        ]
    text = "\n".join(lines) + "\n"
    print(text)
    write_markdown(args.out, text)


if __name__ == "__main__":
    main()
