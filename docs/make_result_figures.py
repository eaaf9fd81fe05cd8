"""Draw the figures of "How the results compare" from the committed results.

Run from anywhere (needs matplotlib; reads only ``benchmarks/results/``)::

    python docs/make_result_figures.py [--output-dir DIR]

The documentation build runs it (``docs/conf.py``), so the figures always
show the committed numbers. Each figure reads the files named in its
function's docstring; the benchmark scripts write them.
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import csv
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"
OUTPUT = ROOT / "docs" / "user_guide" / "_figures"

# One colour per role, the same in every figure.
OURS = "#1f77b4"
PAPER = "#ff7f0e"
MEASURED = "#8c8c8c"
PUBLISHED = "#c7e9c0"
COLOURS = {
    "default pipeline": OURS,
    "paper_pipeline": PAPER,
    "IterativeImputer + default": "#d62728",
    "KNNImputer + default": "#9467bd",
    "SoftImpute + default": "#8c564b",
}
DPI = 100


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def number(cell):
    """A table cell as a float: ``"1,000"`` is 1000, ``"—"`` or ``""`` NaN."""
    cell = cell.replace(",", "").rstrip("x").strip()
    try:
        return float(cell)
    except ValueError:
        return np.nan


def plain_log_ticks(axis):
    """Label a log axis 0.1, 0.2, 0.5, 1, 2, ... instead of 2 x 10^-1."""
    axis.set_major_locator(matplotlib.ticker.LogLocator(subs=(1, 2, 5)))
    axis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    axis.set_minor_formatter(matplotlib.ticker.NullFormatter())


def hopkins155_comparison(results=RESULTS):
    """Mean error of every method, measured here or published.

    Reads ``tables/hopkins155.csv`` (``benchmarks/bench_hopkins155.py``);
    rows without a timing are the published means.
    """
    rows = read_csv(results / "tables" / "hopkins155.csv")
    rows.sort(key=lambda r: -number(r["all mean"]))
    names = [r["method"] for r in rows]
    published = [r["median s / sequence"] == "" for r in rows]
    colours = [
        PUBLISHED if pub else COLOURS.get(name, MEASURED)
        for name, pub in zip(names, published, strict=True)
    ]
    columns = [
        ("2 motions mean", "two motions (120 sequences)"),
        ("3 motions mean", "three motions (35)"),
        ("all mean", "all 155"),
    ]
    fig, axes = plt.subplots(1, 3, figsize=(11, 5.2), sharey=True)
    y = np.arange(len(rows))
    for ax, (column, title) in zip(axes, columns, strict=True):
        values = np.array([number(r[column]) for r in rows])
        bars = ax.barh(y, values, color=colours, edgecolor="#444444", linewidth=0.5)
        ax.bar_label(bars, fmt="%.1f", padding=2, fontsize=8)
        ax.set_title(title, fontsize=11)
        ax.set_xlabel("mean misclassification (%)")
        ax.set_xlim(0, 1.2 * values.max())
        ax.grid(axis="x", alpha=0.3)
    labels = [
        f"{name} (published)" if pub and "published" not in name else name
        for name, pub in zip(names, published, strict=True)
    ]
    axes[0].set_yticks(y, labels)
    handles = [
        plt.Rectangle((0, 0), 1, 1, color=c, ec="#444444", lw=0.5)
        for c in (OURS, PAPER, MEASURED, PUBLISHED)
    ]
    fig.legend(
        handles,
        [
            "sklearn_gpca default pipeline",
            "the paper's algorithm (paper_pipeline)",
            "other baselines, measured here",
            "published means (literature)",
        ],
        loc="lower center",
        ncol=4,
        frameon=False,
        fontsize=9,
    )
    fig.suptitle("Hopkins155, complete trajectories: lower is better", fontsize=12)
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    return fig


def occlusion_curve(results=RESULTS):
    """Mean error against the fraction of point-frames occluded.

    Reads ``hopkins155_missing.csv`` (per sequence and fraction, from
    ``benchmarks/bench_hopkins155.py``). With nothing missing an imputer
    changes nothing, so the imputers start from the default's point at 0 %.
    """
    rows = read_csv(results / "hopkins155_missing.csv")
    fractions = sorted({float(r["missing"]) for r in rows})
    by_method = {}
    for r in rows:
        by_method.setdefault(r["method"], {}).setdefault(float(r["missing"]), [])
        by_method[r["method"]][float(r["missing"])].append(float(r["error"]))
    default = by_method["default pipeline"]
    fig, ax = plt.subplots(figsize=(8, 4.8))
    for method, errors in by_method.items():
        if 0.0 not in errors and 0.0 in default:
            errors = {0.0: default[0.0], **errors}
        xs = [f for f in fractions if f in errors]
        means = [np.mean(errors[f]) for f in xs]
        ours = method in ("default pipeline", "paper_pipeline")
        ax.plot(
            100 * np.array(xs),
            means,
            marker="o",
            lw=2.5 if ours else 1.5,
            ls="-" if ours else "--",
            color=COLOURS.get(method, MEASURED),
            label=method,
            zorder=3 if ours else 2,
        )
    ax.set_xlabel("point-frames removed by the occlusion mask (%)")
    ax.set_ylabel("mean misclassification (%)")
    n = len(next(iter(default.values())))
    ax.set_title(f"Hopkins155, the {n} two-motion sequences with occlusions")
    ax.set_xticks(100 * np.array(fractions))
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(loc="upper left", fontsize=9, frameon=True)
    fig.tight_layout()
    return fig


def scaling_law(results=RESULTS):
    """Time and peak memory against the number of trajectories, log-log.

    Reads ``tables/scaling.csv`` (``benchmarks/bench_scaling.py``).
    """
    rows = read_csv(results / "tables" / "scaling.csv")
    P = np.array([number(r["P"]) for r in rows])
    routes = [
        ("default", "default pipeline (PowerFactorization + GPCAClustering)", OURS),
        ("dense kernel", "paper's cos² kernel, factorised (GPCAClustering)", PAPER),
        ("sklearn", "SpectralClustering on the dense P x P kernel", MEASURED),
    ]
    time_columns = {
        "default": "default s",
        "dense kernel": "dense kernel s",
        "sklearn": "sklearn dense s",
    }
    memory_columns = {
        "default": "default peak GB",
        "dense kernel": "dense kernel peak GB",
        "sklearn": "sklearn peak GB",
    }
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.6))
    for key, label, colour in routes:
        for ax, column in ((left, time_columns[key]), (right, memory_columns[key])):
            values = np.array([number(r[column]) for r in rows])
            ax.loglog(P, values, marker="o", color=colour, lw=2, label=label)
    data = np.array([number(r["data only peak GB"]) for r in rows])
    right.loglog(P, data, ls=":", color="black", label="the data alone")
    # sklearn's dense kernel at the first size it was not run: 8 P^2 bytes
    done = P[~np.isnan([number(r["sklearn peak GB"]) for r in rows])]
    if done.size and done.max() < P.max():
        nxt = P[done.max() < P].min()
        gb = 8 * nxt**2 / 1e9
        right.loglog([nxt], [gb], marker="x", ms=9, color=MEASURED, ls="")
        right.annotate(
            f"dense {nxt:,.0f} x {nxt:,.0f} kernel:\n{gb:,.0f} GB, not run",
            (nxt, gb),
            xytext=(8, -4),
            textcoords="offset points",
            fontsize=8,
            va="top",
        )
    # a line of slope 1 through the default's largest size: linear growth
    t = np.array([number(r[time_columns["default"]]) for r in rows])
    left.loglog(P, t[-1] * P / P[-1], ls=":", color="black", lw=1, label="∝ P")
    left.set_ylabel("wall time of one fit (s)")
    right.set_ylabel("peak resident memory (GB)")
    left.set_title("time")
    right.set_title("memory")
    for ax in (left, right):
        ax.set_xlabel("number of trajectories P")
        ax.grid(alpha=0.3, which="both")
        plain_log_ticks(ax.yaxis)
    handles, labels = left.get_legend_handles_labels()
    handles.append(right.get_legend_handles_labels()[0][-1])
    labels.append("the data alone (memory)")
    fig.legend(handles, labels, loc="lower center", ncol=3, frameon=False, fontsize=9)
    fig.suptitle(
        "Three motions, 10 frames, 10 % missing: time and memory against P", fontsize=12
    )
    fig.tight_layout(rect=(0, 0.1, 1, 1))
    return fig


def lowrank_convergence(results=RESULTS):
    """How often each solver reaches the best fit, and how far it stops.

    Reads ``tables/lowrank_2.csv`` (per seed, ``benchmarks/bench_lowrank.py``).
    """
    rows = read_csv(results / "tables" / "lowrank_2.csv")
    matrices = list(dict.fromkeys(r["matrix"] for r in rows))
    solvers = list(dict.fromkeys(r["solver"] for r in rows))
    colours = dict(zip(solvers, [OURS, "#6baed6", PAPER], strict=False))
    known = [m for m in matrices if any(r["hit"] for r in rows if r["matrix"] == m)]
    fig, (left, right) = plt.subplots(
        1, 2, figsize=(11, 4.6), gridspec_kw={"width_ratios": [1, 2]}
    )
    width = 0.8 / len(solvers)
    for k, solver in enumerate(solvers):
        fractions, labels = [], []
        for m in known:
            hits = [
                r["hit"] == "yes"
                for r in rows
                if (r["matrix"], r["solver"]) == (m, solver)
            ]
            fractions.append(np.mean(hits))
            labels.append(f"{sum(hits)}/{len(hits)}")
        x = np.arange(len(known)) + (k - (len(solvers) - 1) / 2) * width
        bars = left.bar(x, fractions, width, color=colours[solver], label=solver)
        left.bar_label(bars, labels, fontsize=8, padding=2)
    left.set_xticks(np.arange(len(known)), known)
    left.set_ylim(0, 1.15)
    left.set_ylabel("fraction of seeds reaching the best known fit")
    left.set_title("reaching the optimum")
    left.grid(axis="y", alpha=0.3)

    rng = np.random.default_rng(0)
    for j, m in enumerate(matrices):
        best = min(number(r["RMS"]) for r in rows if r["matrix"] == m)
        for k, solver in enumerate(solvers):
            rms = np.array(
                [
                    number(r["RMS"])
                    for r in rows
                    if (r["matrix"], r["solver"]) == (m, solver)
                ]
            )
            x = j + (k - (len(solvers) - 1) / 2) * width
            jitter = rng.uniform(-0.3, 0.3, rms.size) * width
            right.scatter(
                x + jitter,
                rms / best,
                s=22,
                color=colours[solver],
                edgecolor="black",
                lw=0.4,
                zorder=3,
                label=solver if j == 0 else None,
            )
    right.set_yscale("log")
    plain_log_ticks(right.yaxis)
    right.axhline(1, color="black", lw=0.8)
    right.set_xticks(range(len(matrices)), matrices)
    right.set_ylabel("RMS / lowest RMS found (log)")
    right.set_title("where each seed stops")
    right.grid(axis="y", alpha=0.3, which="both")
    handles, labels = right.get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(solvers), frameon=False)
    fig.suptitle(
        "PowerFactorization on real matrices with missing entries", fontsize=12
    )
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    return fig


FIGURES = {
    "hopkins155_comparison": hopkins155_comparison,
    "occlusion_curve": occlusion_curve,
    "scaling_law": scaling_law,
    "lowrank_convergence": lowrank_convergence,
}


def main(output_dir=OUTPUT, results=RESULTS):
    """Write every figure as ``<name>.png`` to ``output_dir``; return the paths."""
    output_dir = Path(output_dir)
    output_dir.mkdir(parents=True, exist_ok=True)
    paths = []
    for name, draw in FIGURES.items():
        fig = draw(Path(results))
        path = output_dir / f"{name}.png"
        fig.savefig(path, dpi=DPI)
        plt.close(fig)
        paths.append(path)
    return paths


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output-dir", type=Path, default=OUTPUT)
    for written in main(parser.parse_args().output_dir):
        print(written)
