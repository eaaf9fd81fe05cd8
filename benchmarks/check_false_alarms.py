"""False alarms of the local outlier test on real tracks.

The local test (:func:`sklearn_gpca._local_outliers.local_outlier_pvalues`)
promises a false-alarm probability per track: at ``1e-3``, about one inlier
in a thousand flagged. Its settings were chosen on ``make_tracks`` draws, whose
noise is one Gaussian level. This script measures the share of real tracks
flagged, with the window's empirical null (the default) and against the F law
alone (``empirical_null=False``):

- Hopkins155: all 155 sequences, complete, and the 120 two-motion ones with
  30 % occlusion (``make_missing(X, 0.3, random_state=0)``); the benchmark's
  tracks were cleaned by hand, so every flag is a false alarm;
- ``Dino`` and ``Dino_trimmed`` (one rigid object on a turntable, a tracker's
  output with 77-91 % missing): a few flags may be real mistracks.

Usage::

    python benchmarks/check_false_alarms.py --hopkins ../shared/data/hopkins155 \\
        --lowrank ../shared/data/lowrank
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import time

import numpy as np
from _tables import markdown_table, write_markdown
from threadpoolctl import threadpool_limits

from sklearn_gpca._local_outliers import local_outlier_pvalues
from sklearn_gpca._observed_subspaces import observed_entries
from sklearn_gpca.datasets import load_hopkins155, load_lowrank, make_missing

THRESHOLDS = (1e-3, 1e-6)


def collections(hopkins, lowrank):
    """``(name, list of X)`` of the real track sets."""
    if hopkins:
        bunches = list(load_hopkins155(hopkins))
        yield "Hopkins155, complete (155 sequences)", [b.X for b in bunches]
        yield (
            "Hopkins155, 2 motions, 30 % occlusion (120 sequences)",
            [
                make_missing(b.X, 0.3, random_state=0)
                for b in bunches
                if b.n_motions == 2
            ],
        )
    if lowrank:
        for name in ("Dino_trimmed", "Dino"):
            yield name, [load_lowrank(name, data_home=lowrank).X]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--hopkins", default=None, help="Hopkins155 folder")
    parser.add_argument("--lowrank", default=None, help="lowrank folder")
    parser.add_argument("--out", default="benchmarks/results/false_alarms.md")
    args = parser.parse_args(argv)
    begin = time.perf_counter()
    rows = []
    with threadpool_limits(1):
        for name, sets in collections(args.hopkins, args.lowrank):
            flagged = {
                True: np.zeros(len(THRESHOLDS)),
                False: np.zeros(len(THRESHOLDS)),
            }
            n_tracks = 0
            for X in sets:
                X0, mask = observed_entries(X)
                n_tracks += X.shape[0]
                for null in (True, False):
                    p = local_outlier_pvalues(X0, mask, empirical_null=null)
                    flagged[null] += [np.count_nonzero(p < t) for t in THRESHOLDS]
            cells = [
                f"{100 * flagged[null][k] / n_tracks:.1f}"
                for k in range(len(THRESHOLDS))
                for null in (True, False)
            ]
            rows.append([name, str(n_tracks), *cells])
    header = ["tracks", "n"] + [
        f"flagged at {t:g} %, {label}"
        for t in THRESHOLDS
        for label in ("empirical null (default)", "F law alone")
    ]
    command = "python benchmarks/check_false_alarms.py"
    if args.hopkins:
        command += " --hopkins ../shared/data/hopkins155"
    if args.lowrank:
        command += " --lowrank ../shared/data/lowrank"
    text = "\n".join(
        [
            "# The local outlier test on real tracks: false alarms",
            "",
            f"`{command}` ({time.perf_counter() - begin:.0f} s, one BLAS thread). "
            "Share of all tracks whose p-value of "
            "`sklearn_gpca._local_outliers.local_outlier_pvalues` is below the "
            "threshold (a false-alarm probability per track), with the window's "
            "empirical null (default) and against the F law alone (a track seen "
            "in 2 frames or fewer of every window is not tested and counts as "
            "not flagged). Hopkins155's tracks were cleaned "
            "by hand: every flag is a false alarm; Dino's may hold a few real "
            "mistracks.",
            "",
            *markdown_table(header, rows),
            "",
        ]
    )
    write_markdown(args.out, text)
    print(text)


if __name__ == "__main__":
    main()
