"""Time of GPCAClustering's two vote weightings, same process, alternating.

Run from the project root (about a minute on a quiet machine)::

    python benchmarks/check_vote_weighting_time.py --data-home ../shared/data/hopkins155

The 120 two-motion Hopkins155 sequences with 30 % occlusion
(``make_missing(X, 0.3, pattern="occlusion", random_state=0)``); per sequence,
``PowerFactorization`` alone, then the pipeline with
``vote_weighting="confidence"`` (the default) and ``"equal"`` (the previous
default), one after the other, with the machine's default BLAS threads.
Prints the median wall seconds of each and the median per-sequence ratio.
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import time
import warnings

import numpy as np
from sklearn.pipeline import make_pipeline

from sklearn_gpca import GPCAClustering, PowerFactorization
from sklearn_gpca.datasets import load_hopkins155, make_missing


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data-home", default=None, help="Hopkins155 folder")
    args = parser.parse_args()
    seconds = {"PowerFactorization": [], "confidence": [], "equal": []}
    warnings.simplefilter("ignore")
    for sequence in load_hopkins155(args.data_home, n_motions=2):
        X = make_missing(sequence.X, 0.3, pattern="occlusion", random_state=0)
        start = time.perf_counter()
        PowerFactorization(random_state=0).fit(X)
        seconds["PowerFactorization"].append(time.perf_counter() - start)
        for rule in ("confidence", "equal"):
            pipeline = make_pipeline(
                PowerFactorization(random_state=0),
                GPCAClustering(sequence.n_motions, random_state=0, vote_weighting=rule),
            )
            start = time.perf_counter()
            pipeline.fit_predict(X)
            seconds[rule].append(time.perf_counter() - start)
    for name, values in seconds.items():
        print(f"{name:20s} median {np.median(values):.4f} s")
    ratio = np.array(seconds["confidence"]) / np.array(seconds["equal"])
    print(f"confidence / equal, median per sequence: {np.median(ratio):.3f}")


if __name__ == "__main__":
    main()
