"""Hopkins155 benchmark: the methods, their runs and their tables.

The logic behind ``benchmarks/bench_hopkins155.py``: misclassification on the
155 sequences with complete trajectories beside the published methods, and on
the two-motion sequences with occlusion masks removing a growing fraction of
the point-frames. It lives outside the package: the ``SoftImpute`` baseline
below is a plain reference implementation for this benchmark, not a validated
estimator.
"""

# SPDX-License-Identifier: BSD-3-Clause

import csv
import sys
import time
import warnings
from pathlib import Path

import numpy as np
from _tables import markdown_table, write_markdown
from joblib import Parallel, delayed
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.cluster import AgglomerativeClustering, KMeans, SpectralClustering
from sklearn.experimental import enable_iterative_imputer  # noqa: F401
from sklearn.impute import IterativeImputer, KNNImputer
from sklearn.pipeline import make_pipeline

from sklearn_gpca import (
    GPCAClustering,
    PowerFactorization,
    ShapeInteractionClustering,
    paper_pipeline,
)
from sklearn_gpca.datasets import load_hopkins155, make_missing
from sklearn_gpca.metrics import misclassification_rate

#: Occlusion fractions of the missing-data table.
MISSING_FRACTIONS = (0.0, 0.1, 0.2, 0.3, 0.4, 0.5)

#: Mean misclassification (%) published for Hopkins155 (2 motions, 3, all),
#: as collected in ../shared/data/README.md.
PUBLISHED = {
    "GPCA (published)": (4.59, 28.67, 10.34),
    "RANSAC": (5.56, 22.94, 9.76),
    "LSA (4n)": (3.45, 9.73, 4.94),
    "LRR": (2.13, 4.03, 2.56),
    "SSC": (1.53, 4.40, 2.18),
    "SMR": (0.88, 1.92, 1.12),
    "FSASC": (0.80, 2.48, 1.18),
}


def default_pipeline(n, seed):
    return make_pipeline(
        PowerFactorization(random_state=seed), GPCAClustering(n, random_state=seed)
    )


#: Methods run on complete data: name -> factory(n_motions, seed).
METHODS = {
    "paper_pipeline": lambda n, seed: paper_pipeline(n, random_state=seed),
    "default pipeline": default_pipeline,
    "Costeira-Kanade (abs Q, spectral)": lambda n, seed: ShapeInteractionClustering(
        n, random_state=seed
    ),
    "SpectralClustering (kNN graph)": lambda n, seed: SpectralClustering(
        n, affinity="nearest_neighbors", random_state=seed
    ),
    "KMeans": lambda n, seed: KMeans(n, n_init=10, random_state=seed),
    "AgglomerativeClustering": lambda n, seed: AgglomerativeClustering(n),
}


class SoftImpute(TransformerMixin, BaseEstimator):
    """Soft-thresholded SVD imputation (Mazumder, Hastie & Tibshirani, 2010).

    Fills the missing entries by iterating ``Z <- S_lambda(P_obs(X) +
    P_miss(Z))``, where ``S_lambda`` shrinks the singular values by
    ``lambda = shrinkage * ||X_0||_2``.
    """

    def __init__(self, shrinkage=0.01, max_iter=200, tol=1e-5):
        self.shrinkage = shrinkage
        self.max_iter = max_iter
        self.tol = tol

    def fit(self, X, y=None):
        return self

    def transform(self, X):
        missing = np.isnan(X)
        Z = np.where(missing, 0.0, X)
        threshold = self.shrinkage * np.linalg.norm(Z, 2)
        for _ in range(self.max_iter):
            u, s, vt = np.linalg.svd(Z, full_matrices=False)
            low_rank = (u * np.maximum(s - threshold, 0.0)) @ vt
            change = np.linalg.norm((low_rank - Z)[missing])
            Z = np.where(missing, low_rank, X)
            if change <= self.tol * np.linalg.norm(Z):
                break
        return Z


def imputed(imputer_factory):
    """Impute, then the default pipeline (the projection sees complete data)."""

    def factory(n, seed):
        steps = default_pipeline(n, seed)
        return make_pipeline(imputer_factory(seed), *[s for _, s in steps.steps])

    return factory


#: Methods run on trajectories with missing entries.
MISSING_METHODS = {
    "paper_pipeline": METHODS["paper_pipeline"],
    "default pipeline": default_pipeline,
    "IterativeImputer + default": imputed(
        lambda seed: IterativeImputer(
            max_iter=5, n_nearest_features=20, random_state=seed
        )
    ),
    "KNNImputer + default": imputed(lambda seed: KNNImputer(n_neighbors=5)),
    "SoftImpute + default": imputed(lambda seed: SoftImpute()),
}


def run_one(method, factory, sequence, X, missing, seed):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        start = time.perf_counter()
        labels = factory(sequence.n_motions, seed).fit_predict(X)
        seconds = time.perf_counter() - start
    return {
        "method": method,
        "sequence": sequence.name,
        "category": sequence.category,
        "n_motions": sequence.n_motions,
        "missing": missing,
        "error": 100 * misclassification_rate(sequence.y, labels),
        "seconds": seconds,
    }


def print_progress(done, total):
    """Default progress display: ``done/total fits`` on stderr, every 10 fits."""
    if done % 10 == 0 or done == total:
        print(f"\r  {done}/{total} fits", end="", file=sys.stderr, flush=True)
    if done == total:
        print(file=sys.stderr)


def run_all(tasks, jobs, progress=print_progress):
    """Run the delayed ``tasks`` in parallel, calling ``progress(done, total)``."""
    results = []
    parallel = Parallel(n_jobs=jobs, return_as="generator_unordered")
    for i, result in enumerate(parallel(tasks), start=1):
        results.append(result)
        progress(i, len(tasks))
    if not tasks:
        print(file=sys.stderr)
    return results


def _stats(rows, key="error"):
    values = np.array([r[key] for r in rows])
    return values.mean(), np.median(values)


def complete_table(results):
    header = [
        "method",
        "2 motions mean",
        "median",
        "3 motions mean",
        "median",
        "all mean",
        "median",
        "checkerboard",
        "traffic",
        "articulated",
        "median s / sequence",
    ]
    rows = []
    for method in METHODS:
        rows_m = [r for r in results if r["method"] == method]
        cells = [method]
        for subset in (
            [r for r in rows_m if r["n_motions"] == 2],
            [r for r in rows_m if r["n_motions"] == 3],
            rows_m,
        ):
            cells += [f"{v:.2f}" for v in _stats(subset)]
        for category in ("checkerboard", "traffic", "articulated"):
            subset = [r for r in rows_m if r["category"] == category]
            cells.append(f"{_stats(subset)[0]:.2f}")
        cells.append(f"{np.median([r['seconds'] for r in rows_m]):.3f}")
        rows.append(cells)
    for method, (two, three, every) in PUBLISHED.items():
        rows.append(
            [method, f"{two:.2f}", "", f"{three:.2f}", "", f"{every:.2f}"] + [""] * 5
        )
    return markdown_table(header, rows)


_PIPELINES = ("paper_pipeline", "default pipeline")


def missing_table(results, fractions):
    header = ["method", *(f"{100 * f:.0f} %" for f in fractions)]
    header.append("median s / sequence")
    rows = []
    for method in MISSING_METHODS:
        rows_m = [r for r in results if r["method"] == method]
        if not rows_m:
            continue
        cells = [method]
        for fraction in fractions:
            subset = [r for r in rows_m if r["missing"] == fraction]
            if not subset:
                cells.append("= default")
                continue
            mean, median = _stats(subset)
            cells.append(f"{mean:.2f} ({median:.2f})")
        cells.append(f"{np.median([r['seconds'] for r in rows_m]):.3f}")
        rows.append(cells)
    return markdown_table(header, rows)


def _write_table(path, title, description, command, timing, rows):
    """Write a Markdown result table (and it as CSV) with how to regenerate it."""
    text = "\n".join(
        [
            title,
            "",
            f"{description} Regenerate with:",
            "",
            f"    {command}",
            "",
            timing,
            "",
            *rows,
            "",
        ]
    )
    write_markdown(path, text)
    print(text)


def write_csv(path, results):
    with path.open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(results[0]))
        writer.writeheader()
        writer.writerows(results)


def run_hopkins155(
    data_home,
    output_dir,
    *,
    command,
    jobs=2,
    seed=0,
    missing=MISSING_FRACTIONS,
    imputers=True,
    progress=print_progress,
):
    """Run the benchmark, write its tables and CSV files, print the tables.

    Parameters
    ----------
    data_home : str, path-like or None
        Hopkins155 folder, as in :func:`sklearn_gpca.datasets.load_hopkins155`.
    output_dir : path-like
        Folder receiving ``hopkins155.md``, ``hopkins155.csv`` and, unless
        ``missing`` is empty, ``hopkins155_missing.md`` and ``.csv``.
    command : str
        The command line quoted in the tables as the way to regenerate them.
    jobs : int, default=2
        Number of parallel jobs.
    seed : int, default=0
        ``random_state`` of the methods and of the occlusion masks.
    missing : sequence of float, default=MISSING_FRACTIONS
        Occlusion fractions for the two-motion sequences; empty to skip.
    imputers : bool, default=True
        Also run the imputer baselines (scikit-learn's IterativeImputer and
        KNNImputer, SoftImpute) on the occluded sequences; they take most of
        the time.
    progress : callable, default=print_progress
        Called as ``progress(done, total)`` after every fit.
    """
    output_dir = Path(output_dir)
    sequences = load_hopkins155(data_home)
    print(f"{len(sequences)} sequences", file=sys.stderr)
    output_dir.mkdir(parents=True, exist_ok=True)

    start = time.perf_counter()
    results = run_all(
        [
            delayed(run_one)(name, factory, seq, seq.X, 0.0, seed)
            for seq in sequences
            for name, factory in METHODS.items()
        ],
        jobs,
        progress,
    )
    elapsed = time.perf_counter() - start
    write_csv(output_dir / "hopkins155.csv", results)
    _write_table(
        output_dir / "hopkins155.md",
        "# Hopkins155: misclassification error (%)",
        f"All {len(sequences)} sequences with two or three motions (complete "
        "trajectories, normalised coordinates `x[:2]`), one run each with "
        f"random_state={seed}. Published rows are from the literature "
        "(means only).",
        command,
        f"Wall time {elapsed:.0f} s with {jobs} jobs.",
        complete_table(results),
    )

    if missing:
        two_motions = [s for s in sequences if s.n_motions == 2]
        start = time.perf_counter()
        results = run_all(
            [
                delayed(run_one)(
                    name,
                    factory,
                    seq,
                    make_missing(seq.X, fraction, random_state=seed),
                    fraction,
                    seed,
                )
                for fraction in missing
                for seq in two_motions
                for name, factory in MISSING_METHODS.items()
                # with nothing missing an imputer changes nothing
                if name in _PIPELINES or (imputers and fraction > 0)
            ],
            jobs,
            progress,
        )
        elapsed = time.perf_counter() - start
        write_csv(output_dir / "hopkins155_missing.csv", results)
        _write_table(
            output_dir / "hopkins155_missing.md",
            "# Hopkins155 with occlusions: misclassification error (%)",
            f"The {len(two_motions)} two-motion sequences; each track is visible "
            "on one contiguous window of frames (`sklearn_gpca.datasets."
            f"make_missing(X, fraction, pattern='occlusion', random_state="
            f"{seed})`), at least 3 frames per track. Mean (median) error "
            "against the fraction of point-frames removed; imputers run only "
            "where something is missing.",
            command,
            f"Wall time {elapsed:.0f} s with {jobs} jobs.",
            missing_table(results, missing),
        )
