"""False alarms of the local outlier test on real tracks.

The local test (:func:`sklearn_gpca._local_outliers.local_outlier_pvalues`)
promises a false-alarm probability per track: at ``1e-3``, about one inlier
in a thousand flagged. Its settings were chosen on ``make_tracks`` draws, whose
noise is one Gaussian level. This script measures the share of real tracks
flagged, with the window's empirical null (the default) and against the F law
alone (``empirical_null=False``), and the share that
``segment_motions(X, n, outlier_threshold=1e-3)`` labels ``-1`` (the local
test's flags that no segmented motion's model explains,
:mod:`sklearn_gpca._explained_outliers`; ``n`` the true number of motions):

- Hopkins155: all 155 sequences, complete, and the 120 two-motion ones with
  30 % occlusion (``make_missing(X, 0.3, random_state=0)``); the benchmark's
  tracks were cleaned by hand, so every flag is a false alarm;
- ``Dino`` and ``Dino_trimmed`` (one rigid object on a turntable, a tracker's
  output with 77-91 % missing): a few flags may be real mistracks.

Usage::

    python benchmarks/check_false_alarms.py --hopkins ../shared/data/hopkins155 \\
        --lowrank ../shared/data/lowrank --jobs 2
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import time
import warnings

import numpy as np
from _tables import markdown_table, write_markdown
from joblib import Parallel, delayed
from threadpoolctl import threadpool_limits

from sklearn_gpca import segment_motions
from sklearn_gpca._local_outliers import local_outlier_pvalues
from sklearn_gpca._observed_subspaces import observed_entries
from sklearn_gpca.datasets import load_hopkins155, load_lowrank, make_missing

THRESHOLDS = (1e-3, 1e-6)
#: ``outlier_threshold`` of the segment_motions column.
SEGMENT_THRESHOLD = 1e-3


def collections(hopkins, lowrank, step=1):
    """``(name, list of (X, number of motions))`` of the real track sets."""
    if hopkins:
        bunches = list(load_hopkins155(hopkins))[::step]
        every = f"every {step}-th sequence, " if step > 1 else ""
        yield (
            f"Hopkins155, complete ({every}{len(bunches)} sequences)",
            [(b.X, b.n_motions) for b in bunches],
        )
        occluded = [
            (make_missing(b.X, 0.3, random_state=0), 2)
            for b in bunches
            if b.n_motions == 2
        ]
        yield (
            f"Hopkins155, 2 motions, 30 % occlusion ({every}{len(occluded)} sequences)",
            occluded,
        )
    if lowrank:
        for name in ("Dino_trimmed", "Dino"):
            yield name, [(load_lowrank(name, data_home=lowrank).X, 1)]


def count_flags(X, n_motions):
    """Tracks flagged by the local test (each null, threshold) and segment_motions."""
    with threadpool_limits(1), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        X0, mask = observed_entries(X)
        local = {}
        for null in (True, False):
            p = local_outlier_pvalues(X0, mask, empirical_null=null)
            local[null] = [np.count_nonzero(p < t) for t in THRESHOLDS]
        labels = segment_motions(
            X, n_motions, outlier_threshold=SEGMENT_THRESHOLD, random_state=0
        )
    return local, int(np.count_nonzero(labels == -1))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--hopkins", default=None, help="Hopkins155 folder")
    parser.add_argument("--lowrank", default=None, help="lowrank folder")
    parser.add_argument("--out", default="benchmarks/results/false_alarms.md")
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--step", type=int, default=1, help="every k-th sequence")
    args = parser.parse_args(argv)
    begin = time.perf_counter()
    rows = []
    for name, sets in collections(args.hopkins, args.lowrank, args.step):
        counts = Parallel(n_jobs=args.jobs)(delayed(count_flags)(X, n) for X, n in sets)
        n_tracks = sum(X.shape[0] for X, _ in sets)
        flagged = {
            null: np.sum([local[null] for local, _ in counts], axis=0)
            for null in (True, False)
        }
        labelled = sum(segmented for _, segmented in counts)
        cells = [
            f"{100 * flagged[null][k] / n_tracks:.1f}"
            for k in range(len(THRESHOLDS))
            for null in (True, False)
        ]
        rows.append([name, str(n_tracks), *cells, f"{100 * labelled / n_tracks:.1f}"])
    header = [
        "tracks",
        "n",
        *[
            f"flagged at {t:g} %, {label}"
            for t in THRESHOLDS
            for label in ("empirical null (default)", "F law alone")
        ],
        f"labelled -1 by segment_motions(outlier_threshold={SEGMENT_THRESHOLD:g}) %",
    ]
    command = "python benchmarks/check_false_alarms.py"
    if args.hopkins:
        command += " --hopkins ../shared/data/hopkins155"
    if args.lowrank:
        command += " --lowrank ../shared/data/lowrank"
    command += f" --jobs {args.jobs}"
    if args.step > 1:
        command += f" --step {args.step}"
    text = "\n".join(
        [
            "# The local outlier test on real tracks: false alarms",
            "",
            f"`{command}` ({time.perf_counter() - begin:.0f} s, one BLAS thread "
            "per job). "
            "Share of all tracks whose p-value of "
            "`sklearn_gpca._local_outliers.local_outlier_pvalues` is below the "
            "threshold (a false-alarm probability per track), with the window's "
            "empirical null (default) and against the F law alone (a track seen "
            "in 2 frames or fewer of every window is not tested and counts as "
            "not flagged); and the share that `segment_motions(X, n, "
            f"outlier_threshold={SEGMENT_THRESHOLD:g}, random_state=0)` labels "
            "-1 (n the true number of motions, 1 for Dino): the local test's "
            "flags that no segmented motion's model explains. Hopkins155's "
            "tracks were cleaned "
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
