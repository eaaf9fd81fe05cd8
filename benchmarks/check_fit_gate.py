"""Hopkins155 and make_motions draws with GPCAClustering's selection rules.

``GPCAClustering`` keeps the candidate with the lowest normalised cut on the
polynomial-normal kNN graph plus the normalised cut on the vote graph of
``n_votes`` randomized-voting runs times the vote graph's confidence
(``vote_weighting="confidence"``, the default; ``"equal"`` adds the vote cut
as is), among those whose residual is within ``fit_gate`` (3) times the
smallest (``sklearn_gpca._selection.select_candidate``). Without votes
(``n_votes=0``) the kNN cut alone chooses: on the 3x10^5 draw of
``bench_scaling.py`` that keeps a candidate merging two motions (30 % error),
as does the confidence-weighted default (confidence 0.24); the equal-weight
vote cut or the lowest residual fix that draw, and a tighter gate costs
Hopkins155. This script measures the rules on Hopkins155 (complete data, the
default pipeline, random_state=0) and, with ``--motions``, on the 40
``make_motions`` draws of ``check_votes_synthetic.py`` (2 and 3 motions, 300
and 1,000 tracks, 10 frames, noise 1, 0 and 10 % missing, seeds 0-4), and
prints the means of 2-motion, 3-motion and all draws.

Usage::

    python benchmarks/check_fit_gate.py --data-home ../shared/data/hopkins155 --jobs 2
    python benchmarks/check_fit_gate.py --motions --jobs 2

Last run: see ``benchmarks/results/selection.md``.
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import itertools
import warnings

import numpy as np
from joblib import Parallel, delayed

#: name -> (GPCAClustering keyword arguments, fit gate)
RULES = {
    "kNN cut + confidence x vote cut, gate 3 (default)": ({}, 3.0),
    "kNN cut + vote cut, gate 3 (vote_weighting='equal')": (
        {"vote_weighting": "equal"},
        3.0,
    ),
    "kNN cut, gate 3 (n_votes=0)": ({"n_votes": 0}, 3.0),
    "kNN cut, gate 1.5 (n_votes=0)": ({"n_votes": 0}, 1.5),
    "lowest residual (gate 1)": ({"n_votes": 0}, 1.0),
}


def one(X, y, n):
    warnings.simplefilter("ignore")
    import sklearn_gpca._gpca as gpca_module
    from sklearn_gpca import GPCAClustering, PowerFactorization
    from sklearn_gpca.metrics import misclassification_rate

    original = gpca_module.select_candidate
    Z = PowerFactorization(random_state=0).fit_transform(X)
    errors = {}
    try:
        for name, (kwargs, gate) in RULES.items():

            def select(unit, candidates, n_clusters, gate=gate, **kwargs):
                kwargs["fit_gate"] = gate
                return original(unit, candidates, n_clusters, **kwargs)

            gpca_module.select_candidate = select
            model = GPCAClustering(n, random_state=0, **kwargs)
            errors[name] = 100 * misclassification_rate(y, model.fit_predict(Z))
    finally:
        gpca_module.select_candidate = original
    return n, errors


def motion_draws():
    """The make_motions draws of check_votes_synthetic.py: (X, y, n) each."""
    from sklearn_gpca.datasets import make_motions

    for n, p, m in itertools.product([2, 3], [300, 1000], [0.0, 0.1]):
        for seed in range(5):
            X, y = make_motions(
                n, n_points=p, n_frames=10, noise=1.0, missing=m, random_state=seed
            )
            yield X, y, n


def main():
    from sklearn_gpca.datasets import load_hopkins155

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data-home", default="../shared/data/hopkins155")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument(
        "--motions", action="store_true", help="make_motions draws, not Hopkins155"
    )
    args = parser.parse_args()
    if args.motions:
        draws = list(motion_draws())
    else:
        draws = [(s.X, s.y, s.n_motions) for s in load_hopkins155(args.data_home)]
    results = Parallel(n_jobs=args.jobs)(delayed(one)(*draw) for draw in draws)
    print("| selection | 2 motions | 3 motions | all |")
    print("|---|---|---|---|")
    for name in RULES:
        two = [e[name] for n, e in results if n == 2]
        three = [e[name] for n, e in results if n == 3]
        print(
            f"| {name} | {np.mean(two):.2f} | {np.mean(three):.2f} "
            f"| {np.mean(two + three):.2f} |"
        )


if __name__ == "__main__":
    main()
