"""``segment_motions``'s default call on every Hopkins155 sequence.

Run from the project root (about 4-8 minutes with two jobs)::

    python benchmarks/check_hopkins_default.py --jobs 2

Prints the mean misclassification (%) over the 2-motion, the 3-motion and
all 155 sequences, the median wall seconds per sequence (one BLAS thread per
job, so that two jobs share two cores: not the time of a user's call with
the default threads) and every sequence's error; ``--out`` also writes the per-sequence
errors as CSV, to compare two revisions (``PYTHONPATH`` on a copy of the
other's package). ``--occluded`` runs instead the 120 two-motion sequences
with 30 % of the entries removed (``make_missing(X, 0.3, random_state=0)``,
as ``check_perspective_background.py --hopkins`` draws them; about 5
minutes).
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import time
import warnings

import numpy as np
from joblib import Parallel, delayed
from threadpoolctl import threadpool_limits

from sklearn_gpca import segment_motions
from sklearn_gpca.datasets import load_hopkins155, make_missing
from sklearn_gpca.metrics import misclassification_rate


def run_one(bunch):
    with threadpool_limits(1), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        clock = time.perf_counter()
        labels = segment_motions(bunch.X, bunch.n_motions, random_state=0)
        seconds = time.perf_counter() - clock
    error = 100 * misclassification_rate(bunch.y, labels)
    return bunch.name, bunch.n_motions, error, seconds


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", default="../shared/data/hopkins155")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--out", default=None, help="CSV of per-sequence errors")
    parser.add_argument(
        "--occluded",
        action="store_true",
        help="the two-motion sequences with 30 %% of the entries removed",
    )
    args = parser.parse_args(argv)
    sequences = load_hopkins155(args.data, n_motions=2 if args.occluded else None)
    if args.occluded:
        for bunch in sequences:
            bunch.X = make_missing(bunch.X, 0.3, random_state=0)
    rows = Parallel(n_jobs=args.jobs)(delayed(run_one)(bunch) for bunch in sequences)
    motions = np.array([row[1] for row in rows])
    errors = np.array([row[2] for row in rows])
    for name, n_motions, error, seconds in rows:
        print(f"{name},{n_motions},{error:.2f},{seconds:.2f}")
    for n_motions in np.unique(motions):
        chosen = motions == n_motions
        print(f"{n_motions} motions ({chosen.sum()}): {errors[chosen].mean():.2f} %")
    seconds = np.median([row[3] for row in rows])
    print(f"all ({len(rows)}): {errors.mean():.2f} %, median {seconds:.2f} s")
    if args.out:
        with open(args.out, "w") as out:
            out.write("sequence,n_motions,error,seconds\n")
            for name, n_motions, error, seconds in rows:
                out.write(f"{name},{n_motions},{error:.4f},{seconds:.3f}\n")


if __name__ == "__main__":
    main()
