"""The vote-cut selection (``n_votes=100``) against the kNN cut alone on draws.

Synthetic draws through the default pipeline
``make_pipeline(PowerFactorization(random_state=0), GPCAClustering(n,
n_votes=..., random_state=0))``: ``make_motions`` (2 and 3 motions, 300 and
1,000 tracks, 10 frames, noise 1, 0 and 10 % missing) and ``make_tracks``
(scene "lab", 2 and 3 motions), seeds 0-4; outlier tracks of ``make_tracks``
(label -1) are scored as their own group. Prints the mean misclassification (%)
of each configuration with the two rules, and the number of draws where they
differ by more than one point.

Usage::

    python benchmarks/check_votes_synthetic.py --jobs 2
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import itertools
import warnings

import numpy as np
from joblib import Parallel, delayed

SEEDS = range(5)
MOTIONS = [
    dict(n_motions=n, n_points=p, missing=m)
    for n, p, m in itertools.product([2, 3], [300, 1000], [0.0, 0.1])
]
TRACKS = [dict(n_motions=n) for n in (2, 3)]


def one(kind, config, seed):
    warnings.simplefilter("ignore")
    from sklearn.pipeline import make_pipeline

    from sklearn_gpca import GPCAClustering, PowerFactorization
    from sklearn_gpca.datasets import make_motions, make_tracks
    from sklearn_gpca.metrics import misclassification_rate

    n = config["n_motions"]
    if kind == "make_motions":
        X, y = make_motions(
            n,
            n_points=config["n_points"],
            n_frames=10,
            noise=1.0,
            missing=config["missing"],
            random_state=seed,
        )
    else:
        X, y = make_tracks(n, scene="lab", random_state=seed)
    errors = {}
    for n_votes in (0, 100):
        pipeline = make_pipeline(
            PowerFactorization(random_state=0),
            GPCAClustering(n, n_votes=n_votes, random_state=0),
        )
        labels = pipeline.fit_predict(X)
        errors[n_votes] = 100 * misclassification_rate(y, labels)
    return kind, str(config), errors


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--jobs", type=int, default=2)
    args = parser.parse_args()
    tasks = [("make_motions", c, s) for c in MOTIONS for s in SEEDS]
    tasks += [("make_tracks", c, s) for c in TRACKS for s in SEEDS]
    results = Parallel(n_jobs=args.jobs)(delayed(one)(*t) for t in tasks)
    print("| draws | configuration | kNN cut (n_votes=0) | + vote cut (100) | differ |")
    print("|---|---|---|---|---|")
    keys = list(dict.fromkeys((k, c) for k, c, _ in results))
    for kind, config in keys:
        rows = [e for k, c, e in results if (k, c) == (kind, config)]
        plain = np.array([e[0] for e in rows])
        voted = np.array([e[100] for e in rows])
        differ = int(np.count_nonzero(np.abs(plain - voted) > 1))
        print(
            f"| {kind} | {config} | {plain.mean():.2f} | {voted.mean():.2f} "
            f"| {differ} of {len(rows)} |"
        )


if __name__ == "__main__":
    main()
