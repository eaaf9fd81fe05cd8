"""segment_motions on dense lab scenes with small motions.

Dense tracks (more than 600 seen per frame) are also segmented by random
subsamples of 400 tracks per frame (``sklearn_gpca._segment``,
``subsample_candidates``). A subsample keeps few tracks of a small motion:
this page checks the lab scenes where that bites. For each number of
motions, number of frames and seed, ``make_tracks(n, scene="lab",
n_tracks=..., n_frames=F, random_state=seed)`` (complete tracks; the motions
after the first share the tracks left by a dominant one), outlier tracks
removed: the misclassification of ``segment_motions(X, n, random_state=0)``
(default BLAS threads, one job), of the oracle
(:func:`sklearn_gpca.metrics.oracle_labels`), the size of the smallest true
group and the wall seconds (the machine is shared: compare runs made side by
side, not seconds across pages).

Usage::

    python benchmarks/check_dense_lab.py --seeds 2 3 \
        --out benchmarks/results/dense_lab.md
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import time
import warnings

import numpy as np
from _tables import command_line, write_check_page

from sklearn_gpca import segment_motions
from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.metrics import misclassification_rate, oracle_labels


def _row(n_motions, n_frames, n_tracks, seed):
    X, y = make_tracks(
        n_motions,
        scene="lab",
        n_tracks=n_tracks,
        n_frames=n_frames,
        random_state=seed,
    )[:2]
    X, y = X[y >= 0], y[y >= 0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        start = time.perf_counter()
        labels = segment_motions(X, n_motions, random_state=0)
        seconds = time.perf_counter() - start
    return (
        X.shape[0],
        int(np.bincount(y).min()),
        misclassification_rate(y, labels),
        misclassification_rate(y, oracle_labels(X, y)),
        seconds,
    )


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[2, 3])
    parser.add_argument("--motions", type=int, nargs="+", default=[2, 3, 5])
    parser.add_argument("--frames", type=int, nargs="+", default=[8, 20])
    parser.add_argument("--tracks", type=int, default=1000)
    parser.add_argument("--out", default=None, help="also write the page here")
    args = parser.parse_args(argv)
    header = ["motions", "frames", "seed", "tracks", "smallest group"]
    header += ["error %", "oracle %", "s"]
    rows, errors, total = [], [], 0.0
    print(" | ".join(header), flush=True)
    for n_motions in args.motions:
        for n_frames in args.frames:
            for seed in args.seeds:
                tracks, smallest, error, oracle, seconds = _row(
                    n_motions, n_frames, args.tracks, seed
                )
                errors.append((error, oracle))
                total += seconds
                cells = [str(n_motions), str(n_frames), str(seed), str(tracks)]
                cells += [str(smallest), f"{100 * error:.2f}", f"{100 * oracle:.2f}"]
                cells += [f"{seconds:.1f}"]
                rows.append(cells)
                print(" | ".join(cells), flush=True)
    error, oracle = 100 * np.mean(errors, axis=0)
    summary = [[str(len(rows)), f"{error:.2f}", f"{oracle:.2f}", f"{total:.0f}"]]
    print(" | ".join(summary[0]))
    if args.out:
        means = ["draws", "error %", "oracle %", "total s"]
        write_check_page(
            args.out,
            command_line(
                "check_dense_lab.py", args, ["seeds", "motions", "frames", "tracks"]
            ),
            __doc__,
            "segment_motions on dense lab scenes",
            [("Mean over the draws", means, summary), ("Per draw", header, rows)],
            stamp_note=", one job",
        )


if __name__ == "__main__":
    main()
