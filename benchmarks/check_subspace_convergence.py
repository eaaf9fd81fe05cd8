"""How far 30 alternations leave a subspace fit with missing entries from its optimum.

``fit_observed_subspace`` fits a 4-D subspace to a group of tracks by
alternating least squares on the observed entries (30 alternations by
default); ``polish=True`` then runs variable projection to the least-squares
optimum. On every true motion of ``make_tracks`` draws (the settings of
``bench_segment.py --setting tracks``, outlier tracks removed) this script
prints, per setting, how many groups the alternations leave more than 1.1
and 1.5 times above the polished residual, the seconds of both fits, and the
misclassification (%) of ``oracle_labels`` (the nearest true subspace on each
track's observed entries) with either fit::

    python benchmarks/check_subspace_convergence.py \\
        --first-seeds 0 20 40 60 80 --draws 4 \\
        --out benchmarks/results/subspace_convergence.md

one table per seed set (seeds ``first .. first + draws - 1``: the seed sets
of the ``perspective_background*.md`` pages, whose oracle column is the one
with 30 alternations).
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import os
import time
import warnings
from pathlib import Path
from unittest import mock

import numpy as np
from _tables import markdown_table
from bench_segment import TRACK_SETTINGS

from sklearn_gpca._observed_subspaces import (
    fit_observed_subspace,
    observed_entries,
    subspace_residuals,
)
from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.metrics import _oracle, misclassification_rate


def _fit_residual(X0, mask, polish):
    start = time.perf_counter()
    basis, support = fit_observed_subspace(X0, mask, 4, polish=polish)
    seconds = time.perf_counter() - start
    residual = subspace_residuals(X0, mask, [basis], [support])[0].sum()
    return residual, seconds


def _oracle_error(X, y, polish):
    """``oracle_labels(X, y)`` with 30 alternations only, or polished fits."""
    fit = _oracle.fit_observed_subspace

    def fixed(*args, **kwargs):
        return fit(*args, **{**kwargs, "polish": polish})

    with mock.patch.object(_oracle, "fit_observed_subspace", fixed):
        return 100 * misclassification_rate(y, _oracle.oracle_labels(X, y))


def _row(name, ratios, seconds, errors):
    """One table row: the fits' ratios and seconds, the oracle's errors."""
    return [
        name,
        ratios.size,
        int(np.sum(ratios > 1.1)),
        int(np.sum(ratios > 1.5)),
        f"{ratios.max():.2f}",
        f"{seconds[0]:.2f}",
        f"{seconds[1]:.2f}",
        f"{errors[:, 0].mean():.2f}",
        f"{errors[:, 1].mean():.2f}",
    ]


def run(seeds):
    rows, every = [], []
    for setting, params in TRACK_SETTINGS.items():
        ratios, seconds, errors = [], np.zeros(2), np.zeros((len(seeds), 2))
        for s, seed in enumerate(seeds):
            X, y = make_tracks(**params, random_state=seed)[:2]
            X, y = X[y >= 0], y[y >= 0]
            X0, mask = observed_entries(X)
            for group in np.unique(y):
                members = y == group
                plain, t0 = _fit_residual(X0[members], mask[members], False)
                polished, t1 = _fit_residual(X0[members], mask[members], True)
                ratios.append(plain / polished)
                seconds += (t0, t1)
            errors[s] = [_oracle_error(X, y, False), _oracle_error(X, y, True)]
        every.append((np.array(ratios), seconds, errors))
        rows.append(_row(setting, *every[-1]))
    rows.append(
        _row(
            "all make_tracks settings",
            np.concatenate([r for r, _, _ in every]),
            np.sum([t for _, t, _ in every], axis=0),
            np.concatenate([e for _, _, e in every]),
        )
    )
    return rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--first-seeds", type=int, nargs="+", default=[0])
    parser.add_argument("--draws", type=int, default=4)
    parser.add_argument("--out", type=Path)
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    header = [
        "setting",
        "true motions",
        "30 alternations > 1.1 x polished",
        "> 1.5 x",
        "largest ratio",
        "alternations s",
        "polished s",
        "oracle, 30 alternations %",
        "oracle, polished %",
    ]
    sections = []
    for first in args.first_seeds:
        seeds = list(range(first, first + args.draws))
        table = "\n".join(markdown_table(header, run(seeds)))
        sections.append(f"## Seeds {seeds[0]} .. {seeds[-1]}\n\n{table}\n")
    command = (
        "python benchmarks/check_subspace_convergence.py --first-seeds "
        + " ".join(map(str, args.first_seeds))
        + f" --draws {args.draws}"
        + (f" --out {args.out}" if args.out else "")
    )
    text = (
        "# Subspace fits with missing entries: 30 alternations against the "
        f"optimum\n\n`{command}`, "
        + time.strftime("%d %b %Y")
        + ", BLAS threads: "
        + os.environ.get("OMP_NUM_THREADS", "the default")
        + ". Each true motion of "
        "the draws (outlier tracks removed) fitted by "
        "`fit_observed_subspace(X0, mask, 4)` (30 alternations of "
        "alternating least squares) and with `polish=True` (then variable "
        "projection); the ratio of their residuals on the motion's own "
        "tracks; seconds summed over the motions; the error of "
        "`oracle_labels(X, y)` (the nearest true subspace) with either fit, "
        "mean over the seeds.\n\n" + "\n".join(sections)
    )
    print(text)
    if args.out:
        args.out.write_text(text)


if __name__ == "__main__":
    main()
