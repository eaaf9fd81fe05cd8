"""segment_motions on long hand-held sequences: make_tracks' own defaults.

Run from the project root (about a minute per draw on a quiet machine)::

    python benchmarks/check_long_tracks.py --seeds 4 \
        --out benchmarks/results/long_tracks.md

``make_tracks(scene="handheld", random_state=seed)`` at the scene's defaults
(800 tracks, 100 frames, 50 % of the entries missing in windows, 3 motions,
perspective camera), outlier tracks removed. Prints, per draw, the
misclassification (%) of ``segment_motions(X, n, random_state=0)`` (the
default, outliers screened) and its wall time, of each refined candidate of
the same call without screening (every track in every candidate), with the
value of the selection criteria (``selection="consistency"``, the default:
the share of tracks nearer another motion's model and the robust fit;
``selection="separability"``: the ambiguous fraction), and of the oracle
(nearest true 4-D subspace on observed entries). ``bench_segment.py
--setting tracks`` measures 40-frame hand-held draws; this script shows what
changes at 100 frames.
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import datetime
import os
import time
import warnings

import numpy as np
from _tables import write_markdown
from bench_segment import fitted_ambiguities

from sklearn_gpca import segment_motions
from sklearn_gpca._segment import AMBIGUITY_TOLERANCE
from sklearn_gpca._segment_selection import select_segmentation
from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.metrics import misclassification_rate, oracle_labels


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=4)
    parser.add_argument("--first-seed", type=int, default=0)
    parser.add_argument("--out", default=None, help="also write the page here")
    args = parser.parse_args(argv)
    lines = [
        "| draw | tracks | missing % | default % | fitted_separability % | "
        "candidate: error % (inconsistency, robust fit, "
        "ambiguous fraction) | oracle % | s |",
        "|---|---|---|---|---|---|---|---|",
    ]
    print(*lines, sep="\n")
    rows = []
    for seed in range(args.first_seed, args.first_seed + args.seeds):
        X, y = make_tracks(scene="handheld", random_state=seed)[:2]
        X, y = X[y >= 0], y[y >= 0]
        n = np.unique(y).size
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            start = time.perf_counter()
            labels = segment_motions(X, n, random_state=0)
            seconds = time.perf_counter() - start
            # the candidates on every track: without the outlier screening
            _, info = segment_motions(
                X, n, screen_outliers=False, random_state=0, return_info=True
            )
            info.fitted_ambiguity = fitted_ambiguities(X, info)
        candidates = [
            f"{name}: {100 * misclassification_rate(y, r):.1f} "
            f"({a:.2f}, {b:.0f}, {c:.2f})"
            for name, r, a, b, c in zip(
                info.candidates,
                info.refined,
                info.inconsistency,
                info.residuals,
                info.ambiguity,
                strict=True,
            )
        ]
        # selection="fitted_separability" on the same candidates
        fitted = info.refined[
            select_segmentation(
                info.coding_lengths,
                np.fmax(info.ambiguity, info.fitted_ambiguity),
                selection="separability",
                tolerance=AMBIGUITY_TOLERANCE,
            )
        ]
        fitted = 100 * misclassification_rate(y, fitted)
        default = 100 * misclassification_rate(y, labels)
        oracle = 100 * misclassification_rate(y, oracle_labels(X, y))
        rows.append((default, fitted, oracle))
        lines.append(
            f"| {seed} | {X.shape[0]} | {100 * np.isnan(X).mean():.0f} | "
            f"{default:.1f} | {fitted:.1f} | {'; '.join(candidates)} | {oracle:.1f} | "
            f"{seconds:.1f} |"
        )
        print(lines[-1], flush=True)
    default, fitted, oracle = np.mean(rows, axis=0)
    summary = (
        f"mean: default {default:.1f} %, fitted_separability {fitted:.1f} %, "
        f"oracle {oracle:.1f} %"
    )
    print("\n" + summary)
    if args.out:
        when = datetime.datetime.now(datetime.timezone.utc).strftime("%d %b %Y %H:%M")
        threads = os.environ.get("OMP_NUM_THREADS", "the default")
        header = [
            "# segment_motions on long hand-held sequences (make_tracks' "
            "100-frame defaults)",
            "",
            f"`python benchmarks/check_long_tracks.py --seeds {args.seeds}`, "
            f"{when} UTC, BLAS threads: {threads}. Misclassification (%) of the "
            "inlier tracks; *default*: `segment_motions(X, n, random_state=0)` "
            '(outliers screened, `selection="consistency"`), with its wall '
            "time (*s*); the candidates are those of the same call without "
            "screening (every track in every candidate), each after its "
            "refinement, with its share of tracks nearer another motion's "
            "model, its robust fit (sum of log(1 + residual / noise); the "
            "default's criteria) and its "
            'ambiguous fraction at 3-D subspaces (`selection="separability"`\'s); '
            "*fitted_separability*: that rule on these candidates; the oracle "
            "is the nearest true 4-D subspace on observed entries.",
            "",
        ]
        write_markdown(args.out, "\n".join([*header, *lines, "", summary, ""]))


if __name__ == "__main__":
    main()
