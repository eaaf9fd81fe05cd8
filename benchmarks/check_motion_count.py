"""segment_motions against the oracle as the number of motions grows.

A tracker's scene holds 2 to 5 motions (KT3DMoSeg's driving clips, the
hand-held sequences of FBMS-59). For each scene, number of motions ``n`` of
``--motions`` and seed, ``make_tracks(scene=..., n_motions=n,
random_state=seed)`` (the scene's defaults otherwise: a perspective camera;
hand-held at 40 frames, half the entries missing), outlier tracks removed:
the misclassification of ``segment_motions(X, n, random_state=0)``, of the
oracle (:func:`sklearn_gpca.metrics.oracle_labels`, each track to the nearest
of the true motions' 4-D subspaces on its observed entries). The draws run in
``--jobs`` processes, one BLAS thread each, so that the labels do not depend
on the machine; no time is reported here (one thread per job is not how users
run it: the speed pages time ``segment_motions`` with the default threads).
The default seeds, 100 and up, were never used to choose a setting of the
library.

Usage::

    python benchmarks/check_motion_count.py --seeds 100 101 102 103 104 105 \
        --motions 2 3 4 5 --jobs 2 --out benchmarks/results/motion_count.md
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import warnings

import numpy as np
from _tables import command_line, write_check_page
from joblib import Parallel, delayed
from threadpoolctl import threadpool_limits

from sklearn_gpca import segment_motions
from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.metrics import misclassification_rate, oracle_labels

#: Scenes and their ``make_tracks`` keywords beside ``n_motions``.
SCENES = {
    "driving, 20 frames": {"scene": "driving"},
    "handheld, 40 frames": {"scene": "handheld", "n_frames": 40, "missing": 0.5},
}


def _row(scene, n_motions, seed):
    X, y = make_tracks(n_motions=n_motions, random_state=seed, **SCENES[scene])[:2]
    X, y = X[y >= 0], y[y >= 0]
    with threadpool_limits(1), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        labels = segment_motions(X, n_motions, random_state=0)
        oracle = oracle_labels(X, y)
    sizes = "/".join(map(str, np.bincount(y, minlength=n_motions)))
    return (
        scene,
        n_motions,
        seed,
        sizes,
        misclassification_rate(y, labels),
        misclassification_rate(y, oracle),
    )


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=list(range(100, 106)))
    parser.add_argument("--motions", type=int, nargs="+", default=[2, 3, 4, 5])
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
    header = ["scene", "motions", "seed", "tracks per motion", "error %"]
    header += ["oracle %", "gap (points)"]
    rows, by_setting = [], {}
    for scene, n, seed, sizes, error, oracle in results:
        by_setting.setdefault((scene, n), []).append((error, oracle))
        cells = [scene, str(n), str(seed), sizes, f"{100 * error:.2f}"]
        cells += [f"{100 * oracle:.2f}", f"{100 * (error - oracle):+.2f}"]
        rows.append(cells)
        print(" | ".join(cells), flush=True)
    means = ["scene", "motions", "draws", "error %", "oracle %", "gap (points)"]
    means += ["draws more than 3 points above the oracle"]
    summary = []
    for (scene, n), values in by_setting.items():
        values = np.array(values)
        error, oracle = 100 * values[:, 0].mean(), 100 * values[:, 1].mean()
        above = int(np.sum(values[:, 0] - values[:, 1] > 0.03))
        cells = [scene, str(n), str(len(values)), f"{error:.2f}", f"{oracle:.2f}"]
        cells += [f"{error - oracle:+.2f}", str(above)]
        summary.append(cells)
    for cells in summary:
        print(" | ".join(cells))
    if args.out:
        write_check_page(
            args.out,
            command_line(
                "check_motion_count.py", args, ["seeds", "motions", "scenes", "jobs"]
            ),
            __doc__,
            "segment_motions with 2 to 5 motions",
            [("Mean over the seeds", means, summary), ("Per draw", header, rows)],
        )


if __name__ == "__main__":
    main()
