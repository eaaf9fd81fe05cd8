"""segment_motions with and without the misfit moves, beside the oracle.

For each scene of ``check_motion_count.py``, number of motions ``n`` of
``--motions`` and seed, ``make_tracks(scene=..., n_motions=n,
random_state=seed)``, outlier tracks removed: the misclassification of
``segment_motions(X, n, random_state=0, misfit_moves=False)`` and of the
default (``misfit_moves=True``, :mod:`sklearn_gpca._misfit_moves`), their
wall seconds (one BLAS thread per job; the two calls run one after the other
in the same process, so compare the ratio, not the seconds) and the oracle
(:func:`sklearn_gpca.metrics.oracle_labels`, each track to the nearest of the
true motions' 4-D subspaces on its observed entries).

Usage::

    python benchmarks/check_misfit_moves.py --seeds 400 401 402 403 404 405 \
        --motions 4 5 --jobs 2 --out benchmarks/results/misfit_moves.md
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import time
import warnings

import numpy as np
from _tables import command_line, write_check_page
from check_motion_count import SCENES
from joblib import Parallel, delayed
from threadpoolctl import threadpool_limits

from sklearn_gpca import segment_motions
from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.metrics import misclassification_rate, oracle_labels


def _row(scene, n_motions, seed):
    X, y = make_tracks(n_motions=n_motions, random_state=seed, **SCENES[scene])[:2]
    X, y = X[y >= 0], y[y >= 0]
    errors, seconds = [], []
    with threadpool_limits(1), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for moves in (False, True):
            clock = time.perf_counter()
            labels = segment_motions(X, n_motions, random_state=0, misfit_moves=moves)
            seconds.append(time.perf_counter() - clock)
            errors.append(misclassification_rate(y, labels))
        oracle = misclassification_rate(y, oracle_labels(X, y))
    return scene, n_motions, seed, errors, seconds, oracle


def _summary_cells(names, values):
    """Mean errors (without, with, oracle), draws better / worse and the
    total time ratio of rows ``[without, with, oracle, s without, s with]``."""
    values = np.array(values)
    better = int(np.sum(values[:, 1] < values[:, 0]))
    worse = int(np.sum(values[:, 1] > values[:, 0]))
    cells = [*names, str(len(values))]
    cells += [f"{100 * values[:, j].mean():.2f}" for j in range(3)]
    cells += [f"{better} / {worse}", f"{values[:, 4].sum() / values[:, 3].sum():.2f}"]
    return cells


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=list(range(400, 406)))
    parser.add_argument("--motions", type=int, nargs="+", default=[4, 5])
    parser.add_argument("--scenes", nargs="+", default=list(SCENES), choices=SCENES)
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--out", default=None, help="also write the page here")
    args = parser.parse_args(argv)
    jobs = [
        (scene, n, seed)
        for scene in args.scenes
        for n in args.motions
        for seed in args.seeds
    ]
    results = Parallel(n_jobs=args.jobs)(delayed(_row)(*job) for job in jobs)
    header = ["scene", "motions", "seed", "without moves %", "with moves %"]
    header += ["oracle %", "s without", "s with", "time ratio"]
    rows, by_setting = [], {}
    for scene, n, seed, errors, seconds, oracle in results:
        by_setting.setdefault((scene, n), []).append([*errors, oracle, *seconds])
        cells = [scene, str(n), str(seed)]
        cells += [f"{100 * e:.2f}" for e in (*errors, oracle)]
        cells += [f"{s:.1f}" for s in seconds] + [f"{seconds[1] / seconds[0]:.2f}"]
        rows.append(cells)
        print(" | ".join(cells), flush=True)
    means = ["scene", "motions", "draws", "without moves %", "with moves %"]
    means += ["oracle %", "draws better / worse", "total time ratio"]
    all_draws = [v for values in by_setting.values() for v in values]
    summary = [
        _summary_cells([scene, str(n)], values)
        for (scene, n), values in by_setting.items()
    ] + [_summary_cells(["all", ""], all_draws)]
    for cells in summary:
        print(" | ".join(cells))
    if args.out:
        write_check_page(
            args.out,
            command_line(
                "check_misfit_moves.py", args, ["seeds", "motions", "scenes", "jobs"]
            ),
            __doc__,
            "segment_motions: the misfit moves",
            [("Mean over the seeds", means, summary), ("Per draw", header, rows)],
        )


if __name__ == "__main__":
    main()
