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
from sklearn.utils import check_random_state
from threadpoolctl import threadpool_limits

from sklearn_gpca import segment_motions
from sklearn_gpca._observed_subspaces import observed_entries
from sklearn_gpca._refine_observed import refinement_objective
from sklearn_gpca._segment import track_graph
from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.metrics import misclassification_rate, oracle_labels

#: segment_motions' defaults of the refinement objective.
N_NEIGHBORS, SMOOTHING = 10, 3.0
#: Bins of the number of frames a track is seen in.
FRAME_BINS = ((1, 5), (6, 15), (16, None))


def _matched(y, labels):
    """``labels`` renamed to the true motions by the best one-to-one match."""
    counts = confusion_matrix(y, labels)
    rows, cols = linear_sum_assignment(-counts)
    names = dict(zip(cols, rows, strict=True))
    return np.array([names.get(label, -1) for label in labels])


def _objective_terms(X, labels, n_motions):
    """Data and smoothing terms of the refinement objective, as segment_motions."""
    X0, mask = observed_entries(X)
    X0 = X0 / np.sqrt(np.mean(X0[mask] ** 2))
    neighbors, _, _, weights = track_graph(
        X0, mask, N_NEIGHBORS, random_state=check_random_state(0)
    )
    kwargs = dict(neighbors=neighbors[:, : weights.shape[1]], neighbor_weights=weights)
    data = refinement_objective(X0, mask, labels, n_motions, smoothing=0.0, **kwargs)
    total = refinement_objective(
        X0, mask, labels, n_motions, smoothing=SMOOTHING, **kwargs
    )
    return data, total - data


def run_one(setting, seed, threads):
    with threadpool_limits(threads), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        X, y = make_tracks(**TRACK_SETTINGS[setting], random_state=seed)
        X, y = X[y >= 0], y[y >= 0]
        n = int(np.unique(y).size)
        # every track in every candidate: no outlier screening
        kwargs = dict(screen_outliers=False, random_state=0)
        found, info = segment_motions(X, n, return_info=True, **kwargs)
        from_truth = segment_motions(X, n, init=y, **kwargs)
        oracle = oracle_labels(X, y)
        from_oracle = segment_motions(X, n, init=oracle, **kwargs)
        errors = [misclassification_rate(y, r) for r in info.refined]
        best = int(np.argmin(info.objectives))
        starts = {
            "chosen": info.refined[info.chosen],
            "lowest objective": info.refined[best],
            "hindsight": info.refined[int(np.argmin(errors))],
            "truth": y,
            "from truth": from_truth,
            "from oracle": from_oracle,
        }
        objective = {
            key: (misclassification_rate(y, labels), *_objective_terms(X, labels, n))
            for key, labels in starts.items()
        }
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
        "objective": objective,
        "n_tracks": y.size,
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


#: Starts compared by the refinement objective: key -> row label.
STARTS = {
    "chosen": "default (the candidate kept)",
    "lowest objective": "the candidate of lowest objective",
    "hindsight": "the candidate of lowest error (hindsight)",
    "truth": "the true labels (not refined)",
    "from truth": "refined from the true labels",
    "from oracle": "refined from the oracle's labels",
}


def objective_table(rows):
    """Error and refinement objective of each start, per setting.

    The objective (:func:`sklearn_gpca._refine_observed.refinement_objective`,
    lower is better) is given per track relative to the default's: ``d obj``
    is the mean over the draws of ``(objective - default's) / n_tracks``, and
    ``lower`` counts the draws where it is below the default's.
    """
    header = [
        "setting",
        "start",
        "error (%)",
        "d objective / track",
        "draws lower",
        "d data / track",
        "d smoothing / track",
    ]
    body = []
    for setting in dict.fromkeys(r["setting"] for r in rows):
        mine = [r for r in rows if r["setting"] == setting]
        for key, label in STARTS.items():
            errors = [100 * r["objective"][key][0] for r in mine]
            deltas = np.array(
                [
                    (
                        np.subtract(
                            r["objective"][key][1:], r["objective"]["chosen"][1:]
                        )
                        / r["n_tracks"]
                    )
                    for r in mine
                ]
            )
            total = deltas.sum(axis=1)
            body.append(
                [
                    setting,
                    label,
                    f"{np.mean(errors):.1f}",
                    f"{np.mean(total):+.3f}",
                    f"{np.sum(total < -1e-9)} of {len(mine)}"
                    if key != "chosen"
                    else "",
                    f"{np.mean(deltas[:, 0]):+.3f}",
                    f"{np.mean(deltas[:, 1]):+.3f}",
                ]
            )
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
        "## Search or model? The refinement objective of each start",
        "",
        "The refinement (`_refine_observed.refine_observed`) descends the "
        "objective of `_refine_observed.refinement_objective` (Gaussian "
        "negative log-likelihood of each track on its observed entries under "
        "its motion's subspace and misfit scale, plus the smoothing penalty; "
        "lower is better). Per setting, mean over the draws: the error and the "
        "objective (per track, minus the default's) of the default's kept "
        "candidate, of the candidate with the lowest objective, of the "
        "candidate with the lowest error, and of the refinement started from "
        "the true labels and from the oracle's labels. Where the starts from "
        "the truth end lower in both, the refinement's objective is right and "
        "the candidates miss its minimum (a search problem); where the kept "
        "candidate is lower in objective but higher in error, the objective "
        "is wrong.",
        "",
        *objective_table(rows),
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
