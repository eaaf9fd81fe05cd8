"""Hopkins155 with GPCAClustering's candidate selection gated more tightly.

``GPCAClustering`` keeps the candidate with the lowest normalised cut among
those whose residual is within ``fit_gate`` (3) times the smallest
(``sklearn_gpca._selection.select_candidate``). On the 3x10^5 draw of
``bench_scaling.py`` that keeps a candidate merging two motions (30 % error);
keeping the lowest residual fixes that draw. This script measures what the
tighter gates cost on Hopkins155 (complete data, the default pipeline,
random_state=0). It prints the means of 2-motion, 3-motion and all sequences
for gates 3 (the default), 1.5 and 1 (the lowest residual).

Usage::

    python benchmarks/check_fit_gate.py --data-home ../shared/data/hopkins155 --jobs 2

Last run (30 Nov 2026): gate 3: 1.55 / 2.62 / 1.79 %; gate 1.5: 1.69 / 4.94 /
2.42 %; gate 1: 1.68 / 5.15 / 2.47 %.
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import warnings

import numpy as np
from joblib import Parallel, delayed

GATES = {"gate 3 (default)": 3.0, "gate 1.5": 1.5, "gate 1 (lowest residual)": 1.0}


def one(X, y, n):
    warnings.simplefilter("ignore")
    import sklearn_gpca._gpca as gpca_module
    from sklearn_gpca import GPCAClustering, PowerFactorization
    from sklearn_gpca.metrics import misclassification_rate

    original = gpca_module.select_candidate
    Z = PowerFactorization(random_state=0).fit_transform(X)
    errors = {}
    try:
        for name, gate in GATES.items():

            def select(unit, candidates, n_clusters, gate=gate, **kwargs):
                kwargs["fit_gate"] = gate
                return original(unit, candidates, n_clusters, **kwargs)

            gpca_module.select_candidate = select
            labels = GPCAClustering(n, random_state=0).fit_predict(Z)
            errors[name] = 100 * misclassification_rate(y, labels)
    finally:
        gpca_module.select_candidate = original
    return n, errors


def main():
    from sklearn_gpca.datasets import load_hopkins155

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data-home", default="../shared/data/hopkins155")
    parser.add_argument("--jobs", type=int, default=2)
    args = parser.parse_args()
    sequences = load_hopkins155(args.data_home)
    results = Parallel(n_jobs=args.jobs)(
        delayed(one)(s.X, s.y, s.n_motions) for s in sequences
    )
    print("| selection | 2 motions | 3 motions | all |")
    print("|---|---|---|---|")
    for name in GATES:
        two = [e[name] for n, e in results if n == 2]
        three = [e[name] for n, e in results if n == 3]
        print(
            f"| {name} | {np.mean(two):.2f} | {np.mean(three):.2f} "
            f"| {np.mean(two + three):.2f} |"
        )


if __name__ == "__main__":
    main()
