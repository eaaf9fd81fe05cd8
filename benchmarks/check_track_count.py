"""segment_motions as a tracker returns more (or fewer) tracks of a scene.

A tracker run at a finer grid returns more tracks of the same motions, one
run at a coarser grid fewer. For each setting and seed,
``make_tracks(n_tracks=round(m * base), random_state=seed, ...)`` for the
multiples ``m`` of ``--multiples`` (fractions allowed; the draws differ beyond
their number of tracks: same scene parameters, other random points), outlier
tracks removed: the misclassification of ``segment_motions(X, n,
random_state=0)`` (default BLAS threads, one job), of the oracle
(:func:`sklearn_gpca.metrics.oracle_labels`) and the wall seconds, with the
ratio of the seconds to those of the first multiple of the same seed, timed
in the same process (the machine is shared: compare ratios, not seconds).

Usage::

    python benchmarks/check_track_count.py --seeds 0 1 2 3 --multiples 1 2 4 \
        --out benchmarks/results/track_count.md
    python benchmarks/check_track_count.py --seeds 0 1 2 3 4 5 \
        --multiples 0.25 0.5 1 --out benchmarks/results/track_count_fewer.md
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

#: Settings and their number of tracks at multiple 1 (the scenes' defaults).
SETTINGS = {
    "driving, 3 motions, 20 frames": ({"scene": "driving"}, 500),
    "handheld, 3 motions, 40 frames": (
        {"scene": "handheld", "n_frames": 40, "missing": 0.5},
        800,
    ),
}


def _row(setting, seed, multiple):
    keywords, base = SETTINGS[setting]
    n_tracks = round(multiple * base)
    X, y = make_tracks(n_tracks=n_tracks, random_state=seed, **keywords)[:2]
    X, y = X[y >= 0], y[y >= 0]
    n = np.unique(y).size
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        start = time.perf_counter()
        labels = segment_motions(X, n, random_state=0)
        seconds = time.perf_counter() - start
    oracle = oracle_labels(X, y)
    return (
        X.shape[0],
        misclassification_rate(y, labels),
        misclassification_rate(y, oracle),
        seconds,
    )


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2, 3])
    parser.add_argument("--multiples", type=float, nargs="+", default=[1, 2, 4])
    parser.add_argument("--out", default=None, help="also write the page here")
    args = parser.parse_args(argv)
    header = ["setting", "seed", "multiple", "tracks", "error %", "oracle %"]
    header += ["s", "s / s at the first multiple", "tracks ratio"]
    rows, errors = [], {}
    print(" | ".join(header), flush=True)
    for setting in SETTINGS:
        for seed in args.seeds:
            first = None
            for multiple in args.multiples:
                tracks, error, oracle, seconds = _row(setting, seed, multiple)
                first = first or (tracks, seconds)
                errors.setdefault((setting, multiple), []).append((error, oracle))
                cells = [setting, str(seed), f"{multiple:g}", str(tracks)]
                cells += [f"{100 * error:.2f}", f"{100 * oracle:.2f}"]
                cells += [f"{seconds:.1f}", f"{seconds / first[1]:.2f}"]
                cells += [f"{tracks / first[0]:.2f}"]
                rows.append(cells)
                print(" | ".join(cells), flush=True)
    summary = [
        [setting, f"{multiple:g}", *(f"{100 * m:.2f}" for m in np.mean(v, axis=0))]
        for (setting, multiple), v in errors.items()
    ]
    for cells in summary:
        print(" | ".join(cells))
    if args.out:
        means = ["setting", "multiple", "error %", "oracle %"]
        write_check_page(
            args.out,
            command_line("check_track_count.py", args, ["seeds", "multiples"]),
            __doc__,
            "segment_motions with more or fewer tracks of the same scenes",
            [("Mean over the seeds", means, summary), ("Per draw", header, rows)],
            stamp_note=", one job",
        )


if __name__ == "__main__":
    main()
