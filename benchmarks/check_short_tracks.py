"""How tracks seen in one frame are labelled, against the longer tracks.

Run from the project root (a few seconds per draw)::

    python benchmarks/check_short_tracks.py --seeds 2

``make_tracks(3, scene="driving", random_state=seed)`` (500 tracks, about a
sixth of them seen in one frame only). Prints, per draw, the error (%) of
``PerspectiveClustering(3, random_state=0)`` and of
``segment_motions(X, 3, random_state=0)`` on the tracks seen in one frame and
on the others, each label matched to the truth by the best one-to-one map of
the whole draw. ``PerspectiveClustering`` gives a one-frame track the label
most common among its 5 nearest longer tracks in that frame.
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import warnings

import numpy as np
from scipy.optimize import linear_sum_assignment

from sklearn_gpca import PerspectiveClustering, segment_motions
from sklearn_gpca.datasets import make_tracks


def _matched(y, labels):
    """``labels`` mapped one-to-one onto ``y`` (unmatched labels: -2)."""
    counts = np.zeros((y.max() + 1, labels.max() + 1))
    np.add.at(counts, (y, labels), 1)
    rows, cols = linear_sum_assignment(-counts)
    lookup = np.full(labels.max() + 1, -2)
    lookup[cols] = rows
    return lookup[labels]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=2)
    parser.add_argument("--first-seed", type=int, default=0)
    args = parser.parse_args(argv)
    print(
        "| draw | tracks | seen in one frame | method | error %, one frame "
        "| error %, two frames or more |"
    )
    print("|---|---|---|---|---|---|")
    for seed in range(args.first_seed, args.first_seed + args.seeds):
        X, y = make_tracks(3, scene="driving", random_state=seed)[:2]
        short = (np.isfinite(X[:, 0::2]) & np.isfinite(X[:, 1::2])).sum(1) == 1
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            methods = {
                "PerspectiveClustering": PerspectiveClustering(
                    3, random_state=0
                ).fit_predict(X),
                "segment_motions": segment_motions(X, 3, random_state=0),
            }
        for name, labels in methods.items():
            wrong = _matched(y, labels) != y
            print(
                f"| {seed} | {X.shape[0]} | {short.sum()} | {name} "
                f"| {100 * wrong[short].mean():.1f} "
                f"| {100 * wrong[~short].mean():.1f} |"
            )


if __name__ == "__main__":
    main()
