"""Where segment_motions' default errs on tracker-like draws, against the oracle.

For the ``make_tracks`` settings of ``bench_segment.py`` (``--draws`` seeds
each, outlier tracks removed): the misclassification of the default
``segment_motions(X, n)``, of the oracle
(:func:`sklearn_gpca.metrics.oracle_labels`) and of the refinement started
from the true labels (``segment_motions(X, n, init=y)``), by how many frames
a track is seen in; and the confusion matrix of the default against the
truth (rows: true motions, 0 the background; columns: labels found), which
shows whether motions were merged or cut. Writes
``benchmarks/results/segment_tracks_diagnosis.md``.

Usage::

    python benchmarks/diagnose_segment_tracks.py --draws 2 --jobs 2
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import time
import warnings
from pathlib import Path

import numpy as np
from _tables import markdown_table, write_markdown
from bench_segment import TRACK_SETTINGS
from joblib import Parallel, delayed
from scipy.optimize import linear_sum_assignment
from sklearn.metrics import confusion_matrix
from threadpoolctl import threadpool_limits

from sklearn_gpca import segment_motions
from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.metrics import oracle_labels

#: Bins of the number of frames a track is seen in.
FRAME_BINS = ((1, 5), (6, 15), (16, None))


def _matched(y, labels):
    """``labels`` renamed to the true motions by the best one-to-one match."""
    counts = confusion_matrix(y, labels)
    rows, cols = linear_sum_assignment(-counts)
    names = dict(zip(cols, rows, strict=True))
    return np.array([names.get(label, -1) for label in labels])


def run_one(setting, seed, threads):
    with threadpool_limits(threads), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        X, y = make_tracks(**TRACK_SETTINGS[setting], random_state=seed)
        X, y = X[y >= 0], y[y >= 0]
        n = int(np.unique(y).size)
        found = segment_motions(X, n, random_state=0)
        from_truth = segment_motions(X, n, init=y, random_state=0)
        oracle = oracle_labels(X, y)
    seen = np.count_nonzero(~np.isnan(X), axis=1) // 2
    return {
        "setting": setting,
        "seed": seed,
        "y": y,
        "seen": seen,
        "default": _matched(y, found),
        "oracle": oracle,
        "from truth": _matched(y, from_truth),
        "confusion": confusion_matrix(y, found),
    }


def breakdown_table(rows):
    header = [
        "setting",
        "frames seen",
        "share of tracks (%)",
        "default (%)",
        "oracle (%)",
        "refined from the truth (%)",
    ]
    body = []
    for setting in dict.fromkeys(r["setting"] for r in rows):
        mine = [r for r in rows if r["setting"] == setting]
        total = sum(r["y"].size for r in mine)
        for low, high in FRAME_BINS:
            cells = [setting, f"{low}-{high or ''}"]
            picks = [(r["seen"] >= low) & (r["seen"] <= (high or np.inf)) for r in mine]
            size = sum(int(p.sum()) for p in picks)
            cells.append(f"{100 * size / total:.0f}")
            for key in ("default", "oracle", "from truth"):
                wrong = sum(
                    int(np.sum(r[key][p] != r["y"][p]))
                    for r, p in zip(mine, picks, strict=True)
                )
                cells.append(f"{100 * wrong / max(size, 1):.1f}")
            body.append(cells)
    return markdown_table(header, body)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--draws", type=int, default=2, help="seeds per setting")
    parser.add_argument("--jobs", type=int, default=2)
    args = parser.parse_args()
    threads = 1 if args.jobs > 1 else None
    start = time.perf_counter()
    rows = Parallel(n_jobs=args.jobs)(
        delayed(run_one)(setting, seed, threads)
        for setting in TRACK_SETTINGS
        for seed in range(args.draws)
    )
    elapsed = time.perf_counter() - start
    lines = [
        "# segment_motions on tracker-like draws: where the default errs",
        "",
        f"`python benchmarks/diagnose_segment_tracks.py --draws {args.draws} "
        f"--jobs {args.jobs}` ({elapsed:.0f} s wall time). Settings of "
        "`bench_segment.py --setting tracks`, seeds 0 .. draws - 1, outlier "
        "tracks removed. Misclassification (%) of the tracks seen in the given "
        "number of frames, pooled over the draws: the default "
        "`segment_motions(X, n)`, the oracle (nearest true 4-D subspace on "
        "observed entries) and the default refinement started from the true "
        "labels (`init=y`).",
        "",
        *breakdown_table(rows),
        "",
        "Confusion of the default against the truth (rows: true motions, 0 the "
        "background; columns: labels found):",
        "",
    ]
    for r in rows:
        matrix = "; ".join(" ".join(str(v) for v in line) for line in r["confusion"])
        lines.append(f"- {r['setting']} #{r['seed']}: `{matrix}`")
    out = Path(__file__).parent / "results" / "segment_tracks_diagnosis.md"
    write_markdown(out, "\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
