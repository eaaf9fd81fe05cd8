"""Randomized voting in a wider space, full-space refinement, selection (issue 16).

For every Hopkins155 sequence (complete data) it runs the default pipeline
(``PowerFactorization`` to ``R^5`` + :func:`sklearn_gpca.gpca`,
``random_state=0``: six candidates refined in ``R^5``, one kept) and measures,
against the ground truth:

(a) a new candidate, ``rvW``: the Ng-Jordan-Weiss spectral clustering of the
    vote graph of ``--n-votes`` randomized-voting runs (Jung, Ju & Kim, CVPR
    2014) in the leading ``min(2F, 4n)`` principal coordinates of the complete
    trajectories (``U_r S_r``), each run a plain K-subspaces of 4-dimensional
    subspaces started from minimal local samples (a track and 3 of its
    nearest neighbours among the ``gpca`` neighbourhood size); ``rv5`` is the
    same in ``R^5`` with hyperplanes (the graph the default builds to select);
(b) full-space smoothed K-subspaces (:func:`refine_full_space`, 4-D
    subspaces, smoothing 1, neighbours by angle between the complete tracks)
    as the refinement of every candidate, and from the truth; and the same
    with the settings of :func:`segment_motions` (``refine_observed``: one
    misfit scale per motion, smoothing 3 on the 10 nearest tracks, each
    weighted by the motion affinity of the two tracks);
(c) selection rules on the default's six candidates plus ``rvW``: the
    default (kNN cut + confidence x cut on the ``R^5`` vote graph, fit gate
    3), the cut on the wide vote graph instead or in addition, the wide vote
    cut alone, the kNN cut alone, the full-space residual; with their mean
    Spearman correlation with the error over the candidates (sequences where
    both vary) and how often they keep a best candidate.

The votes are drawn with ``--seeds`` different seeds (the default's own
candidates do not change): the spread between seeds is the noise of one
draw. Times are ratios to the default pipeline's time in the same process.
Writes ``benchmarks/results/wide_votes.md``.

Usage::

    python benchmarks/bench_wide_votes.py --data ../shared/data/hopkins155 --jobs 1
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import time
import warnings
from pathlib import Path

import numpy as np
from _tables import write_markdown
from joblib import Parallel, delayed
from scipy.stats import spearmanr
from threadpoolctl import threadpool_limits

from sklearn_gpca import PowerFactorization, gpca, k_subspaces
from sklearn_gpca._observed_subspaces import observed_entries
from sklearn_gpca._refine_observed import refine_observed, refinement_objective
from sklearn_gpca._segment import track_graph
from sklearn_gpca._selection import FIT_GATE, candidate_residuals
from sklearn_gpca._spectral import spectral_clustering_lowrank
from sklearn_gpca._voting import (
    VOTING_ROUNDS,
    vote_confidence,
    vote_cut,
    vote_features,
    voting_runs,
)
from sklearn_gpca.datasets import load_hopkins155
from sklearn_gpca.metrics import misclassification_rate
from sklearn_gpca.stages import (
    normalized_cut,
    refine_full_space,
    sign_invariant_neighbors,
    unit_rows,
)

#: The failing sequences of ``selection.md`` shown one by one.
SHOWN = (
    "2RT3RCR",
    "2RT3RCR_g23",
    "1RT2RTCRT_B_g23",
    "1RT2RCR_g23",
    "two_cranes_g23",
    "2T3RCTP",
    "2T3RCRTP",
    "2T3RCRTP_g23",
    "1RT2RCR",
    "1RT2RTCRT_A",
    "2R3RTCRT",
    "2T3RCRT",
    "cars2_06_g13",
    "cars3",
)


def full_residual(X, labels, n_clusters, dim=4):
    """Squared distances of the tracks to their cluster's best ``dim``-D
    subspace of ``R^{2F}``, over the tracks' squared norm."""
    total = 0.0
    for k in range(n_clusters):
        rows = X[labels == k]
        if rows.shape[0] == 0:
            return np.inf
        total += np.sum(np.linalg.svd(rows, compute_uv=False)[dim:] ** 2)
    return total / np.sum(X**2)


def vote_graph(points, n_clusters, n_local, n_runs, dim, rng):
    """Factor ``B`` of the vote graph of ``n_runs`` runs on ``points``."""
    unit = unit_rows(points)
    neighbors = sign_invariant_neighbors(unit, min(n_local, unit.shape[0] - 1))
    runs = voting_runs(
        unit,
        n_clusters,
        neighbors,
        n_runs=n_runs,
        dim=dim,
        n_iter=VOTING_ROUNDS,
        random_state=rng,
    )
    return vote_features(runs, n_clusters)


def weighted_refiner(X):
    """Full-space refinement with the settings of :func:`segment_motions`:
    one misfit scale per motion, smoothing 3 on the 10 nearest tracks, each
    neighbour weighted by how alike the two tracks move. Returns the
    refinement and the objective it descends (comparable across labellings)."""
    X0, mask = observed_entries(X)
    rng = np.random.RandomState(0)
    neighbors, _, _, weights = track_graph(X0, mask, 10, random_state=rng)
    graph = dict(neighbors=neighbors[:, : weights.shape[1]], neighbor_weights=weights)
    refine = lambda labels, n: refine_observed(  # noqa: E731
        X0, mask, labels, n, random_state=rng, **graph
    )[0]
    objective = lambda labels, n: refinement_objective(  # noqa: E731
        X0, mask, labels, n, **graph
    )
    return refine, objective


def _rho(values, errors):
    if np.ptp(errors) == 0 or np.ptp(values) == 0 or not np.all(np.isfinite(values)):
        return np.nan
    return spearmanr(values, errors).statistic


def criteria(labels_list, *, X, unit5, graph, B5, BW, n, objective):
    """Each selection rule's value for each labelling (lower is kept)."""
    conf5, confW = vote_confidence(B5, n), vote_confidence(BW, n)
    kc = np.array([normalized_cut(graph, c, n) for c in labels_list])
    v5 = np.array([vote_cut(B5, c, n) for c in labels_list])
    vW = np.array([vote_cut(BW, c, n) for c in labels_list])
    r5 = candidate_residuals(unit5, labels_list, n, unit5.shape[1] - 1, 0.05)
    gate = np.where(r5 <= FIT_GATE * r5.min(), 0.0, np.inf)
    full = np.array([full_residual(X, c, n) for c in labels_list])
    return {
        "default rule: kNN cut + conf x R^5 vote cut": kc + conf5 * v5 + gate,
        "kNN cut + conf x wide vote cut": kc + confW * vW + gate,
        "kNN cut + both confidence-weighted vote cuts": kc
        + conf5 * v5
        + confW * vW
        + gate,
        "wide vote cut alone": vW,
        "kNN cut alone": kc + gate,
        "full-space residual (4-D)": full,
        "weighted refinement objective": np.array(
            [objective(c, n) for c in labels_list]
        ),
    }


def run_one(bunch, seeds, n_votes):
    threadpool_limits(1)
    warnings.simplefilter("ignore")
    n, X, y = bunch.n_motions, np.asarray(bunch.X, dtype=float), bunch.y
    error = lambda labels: misclassification_rate(y, labels)  # noqa: E731
    t0 = time.perf_counter()
    Z = PowerFactorization(random_state=0).fit_transform(X)
    result = gpca(Z, n, random_state=0)
    t_default = time.perf_counter() - t0
    unit5, local = unit_rows(Z), result.local_neighbors
    graph, six = result.selection_graph, list(result.candidate_labels)
    truth = np.unique(y, return_inverse=True)[1]
    weighted, objective = weighted_refiner(X)
    row = dict(
        name=bunch.name,
        n=n,
        kept=error(result.labels),
        truth_r5=error(k_subspaces(unit5, truth, n, neighbors=local)[0]),
        truth_full=error(refine_full_space(X, truth, X, random_state=0)[0]),
        kept_full=error(refine_full_space(X, result.labels, X, random_state=0)[0]),
        truth_weighted=error(weighted(truth, n)),
        kept_weighted=error(weighted(result.labels, n)),
        t_default=t_default,
        seeds={},
    )
    rank = min(X.shape[1], 4 * n)
    for seed in seeds:
        rng = np.random.RandomState(seed)
        B5 = vote_graph(Z, n, local.shape[1], n_votes, Z.shape[1] - 1, rng)
        t0 = time.perf_counter()
        U, s, _ = np.linalg.svd(X, full_matrices=False)
        BW = vote_graph(U[:, :rank] * s[:rank], n, local.shape[1], n_votes, 4, rng)
        rvW = spectral_clustering_lowrank(BW, n, random_state=0)
        t_rvw = time.perf_counter() - t0
        rv5 = spectral_clustering_lowrank(B5, n, random_state=0)
        cands = [*six, rvW]
        refined = []
        t0 = time.perf_counter()
        for c in cands:
            refined.append(refine_full_space(X, c, X, random_state=0)[0])
        t_full = (time.perf_counter() - t0) / len(cands)
        t0 = time.perf_counter()
        weighted_refined = [weighted(c, n) for c in cands]
        t_weighted = (time.perf_counter() - t0) / len(cands)
        context = dict(
            X=X, unit5=unit5, graph=graph, B5=B5, BW=BW, n=n, objective=objective
        )

        row["seeds"][seed] = dict(
            rvW=error(rvW),
            rv5=error(rv5),
            errors=np.array([error(c) for c in cands]),
            refined=np.array([error(c) for c in refined]),
            crit=criteria(cands, **context),
            crit_refined=criteria(refined, **context),
            weighted=np.array([error(c) for c in weighted_refined]),
            crit_weighted=criteria(weighted_refined, **context),
            t_weighted=t_weighted,
            t_rvw=t_rvw,
            t_full=t_full,
        )
    return row


def _fmt(errors, n):
    e = 100 * np.asarray(errors)
    return [f"{e[n == 2].mean():.2f}", f"{e[n == 3].mean():.2f}", f"{e.mean():.2f}"]


def _spread(per_seed, n):
    """'mean (min-max)' over the seeds of each of the three means."""
    cells = np.array([[float(c) for c in _fmt(e, n)] for e in per_seed])
    if len(per_seed) == 1:
        return [f"{v:.2f}" for v in cells[0]]
    return [
        f"{m:.2f} ({lo:.2f}-{hi:.2f})"
        for m, lo, hi in zip(cells.mean(0), cells.min(0), cells.max(0), strict=True)
    ]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", default="../shared/data/hopkins155")
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--n-votes", type=int, default=100)
    parser.add_argument(
        "--output", default=str(Path(__file__).parent / "results" / "wide_votes.md")
    )
    args = parser.parse_args()
    seeds = list(range(args.seeds))
    started = time.strftime("%d %b %Y %H:%M UTC", time.gmtime())
    rows = Parallel(n_jobs=args.jobs)(
        delayed(run_one)(b, seeds, args.n_votes) for b in load_hopkins155(args.data)
    )
    n = np.array([r["n"] for r in rows])
    per = lambda key: [[r["seeds"][s][key] for r in rows] for s in seeds]  # noqa: E731
    per_row = lambda key: [[r[key] for r in rows]]  # noqa: E731
    errs = [np.array(e) for e in per("errors")]  # (seed) -> (P, 7)
    refd = [np.array(e) for e in per("refined")]
    wrefd = [np.array(e) for e in per("weighted")]
    lines = [
        "# Randomized voting in a wider space, full-space refinement, selection",
        "",
        "`python benchmarks/bench_wide_votes.py --data ../shared/data/hopkins155 "
        f"--jobs {args.jobs} --seeds {args.seeds} --n-votes {args.n_votes}` "
        f"(issue 16; run {started}). Complete data, all 155 sequences. The "
        "default's six candidates (`random_state=0`) are fixed; the votes are "
        f"drawn with seeds {seeds}: each cell is the mean over the seeds (min-max "
        "over the seeds in brackets). Mean misclassification (%) over 2-motion / "
        "3-motion / all sequences.",
        "",
        "## Candidates and their refinement",
        "",
        "| segmentation | 2 motions | 3 motions | all |",
        "|---|---|---|---|",
    ]
    table = [
        ("default pipeline (kept candidate)", [[r["kept"] for r in rows]]),
        ("best of the default's six in hindsight", [e[:, :6].min(1) for e in errs]),
        ("rv5: vote graph in R^5 (hyperplanes), spectral", per("rv5")),
        ("rvW: vote graph in rank min(2F, 4n), 4-D, spectral", per("rvW")),
        ("best of the six + rvW in hindsight", [e.min(1) for e in errs]),
        ("six + rvW, each refined in R^{2F}: best", [e.min(1) for e in refd]),
        ("the kept candidate refined in R^{2F}", [[r["kept_full"] for r in rows]]),
        ("rvW refined in R^{2F}", [e[:, 6] for e in refd]),
        ("six + rvW, each refined in R^{2F} weighted: best", [e.min(1) for e in wrefd]),
        ("the kept candidate refined in R^{2F} weighted", per_row("kept_weighted")),
        ("rvW refined in R^{2F} weighted", [e[:, 6] for e in wrefd]),
        ("smoothed K-subspaces in R^5 from the truth", per_row("truth_r5")),
        ("smoothed K-subspaces in R^{2F} from the truth", per_row("truth_full")),
        ("the same, weighted, from the truth", per_row("truth_weighted")),
    ]
    for name, values in table:
        lines.append(f"| {name} | " + " | ".join(_spread(values, n)) + " |")
    for title, key, source in (
        ("Selection among the six + rvW", "crit", errs),
        ("Selection among the six + rvW, each refined in R^{2F}", "crit_refined", refd),
        (
            "Selection among the six + rvW, each refined in R^{2F} weighted",
            "crit_weighted",
            wrefd,
        ),
    ):
        lines += [
            "",
            f"## {title}",
            "",
            "Kept error (%), mean Spearman correlation of the criterion with the "
            "error over the seven candidates (sequences where both vary), share of "
            "the sequences where the candidates' errors differ on which the "
            "criterion keeps a best one, and sequences above 5 % (mean over seeds).",
            "",
            "| rule | 2 motions | 3 motions | all | rank correlation | hindsight best "
            "| > 5 % |",
            "|---|---|---|---|---|---|---|",
        ]
        for rule in rows[0]["seeds"][seeds[0]][key]:
            kept, rhos, hits, fails = [], [], [], []
            for s, e in zip(seeds, source, strict=True):
                values = np.array([r["seeds"][s][key][rule] for r in rows])
                chosen = e[np.arange(len(rows)), values.argmin(1)]
                kept.append(chosen)
                rhos += [_rho(v, x) for v, x in zip(values, e, strict=True)]
                varies = np.ptp(e, axis=1) > 0
                hits.append(np.mean(chosen[varies] <= e.min(1)[varies] + 1e-12))
                fails.append(np.sum(chosen > 0.05))
            lines.append(
                f"| {rule} | "
                + " | ".join(_spread(kept, n))
                + f" | {np.nanmean(rhos):.2f} | {np.mean(hits):.2f} | "
                f"{np.mean(fails):.1f} |"
            )
    t_default = np.array([r["t_default"] for r in rows])
    t_rvw = np.array(per("t_rvw"))
    t_full = np.array(per("t_full"))
    t_weighted = np.array(per("t_weighted"))
    lines += [
        "",
        "## Time (ratios to the default pipeline, same process, one thread)",
        "",
        "| stage | median ratio | ratio of the medians |",
        "|---|---|---|",
        f"| rvW candidate (SVD, {args.n_votes} runs, spectral clustering) | "
        f"{np.median(t_rvw / t_default):.2f} | "
        f"{np.median(t_rvw) / np.median(t_default):.2f} |",
        "| full-space refinement of one candidate | "
        f"{np.median(t_full / t_default):.2f} | "
        f"{np.median(t_full) / np.median(t_default):.2f} |",
        "| weighted full-space refinement of one candidate | "
        f"{np.median(t_weighted / t_default):.2f} | "
        f"{np.median(t_weighted) / np.median(t_default):.2f} |",
        "",
        "## The failing sequences",
        "",
        "Error (%) of the default's kept candidate, of its best candidate, of rvW "
        "for each seed, of the default rule and of the wide-vote rule on the six "
        "+ rvW (seed 0), and of the full-space refinement from the truth.",
        "",
        "| sequence | motions | default | best of six | rvW per seed | default rule "
        "| kNN + conf x wide | R^{2F} from truth |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        if r["name"] not in SHOWN:
            continue
        s0 = r["seeds"][seeds[0]]
        pick = {
            k: 100 * s0["errors"][int(np.argmin(s0["crit"][k]))]
            for k in (
                "default rule: kNN cut + conf x R^5 vote cut",
                "kNN cut + conf x wide vote cut",
            )
        }
        rvw = ", ".join(f"{100 * r['seeds'][s]['rvW']:.1f}" for s in seeds)
        lines.append(
            f"| {r['name']} | {r['n']} | {100 * r['kept']:.1f} | "
            f"{100 * s0['errors'][:6].min():.1f} | {rvw} | "
            + " | ".join(f"{v:.1f}" for v in pick.values())
            + f" | {100 * r['truth_full']:.1f} |"
        )
    text = "\n".join(lines) + "\n"
    print(text)
    write_markdown(args.output, text)


if __name__ == "__main__":
    main()
