"""segment_motions against the default and paper pipelines and the oracle.

Settings (``--setting``):

- ``tracks``: tracker-like draws of :func:`sklearn_gpca.datasets.make_tracks`
  in the realistic settings of ``TRACK_SETTINGS`` (scenes driving, handheld
  and lab; 2-5 motions; 30-65 % missing; perspective and affine cameras),
  ``--draws`` seeds each. The outlier tracks are removed for the
  segmentation table; a second table segments the handheld setting with
  10 % outlier tracks and ``outlier_threshold=OUTLIER_THRESHOLD``.
- ``hopkins``: the 155 Hopkins155 sequences, complete data;
- ``occlusion``: the 120 two-motion sequences with 30 % of the point-frames
  removed by ``make_missing(X, 0.3, random_state=0)``, as in
  ``benchmarks/bench_hopkins155.py`` (whose occlusion table has the default
  pipeline at this fraction).

For every sequence: the misclassification of ``segment_motions(X, n)``, of its
refined candidates (and of the best of them in hindsight: the criterion that
picks one is not always right), of the candidate kept by each selection rule
(``init`` "auto" or "all" x ``selection`` "coding_length", "separability",
"fitted_separability" or "consistency",
all from one ``init="all"`` run: its gpca and fragments candidates are those of
``init="auto"``, drawn first from the same seed), of the default
``make_pipeline(PowerFactorization(), GPCAClustering(n))``, of
:func:`sklearn_gpca.paper_pipeline` (tracks settings) and of the oracle
(:func:`sklearn_gpca.metrics.oracle_labels`: the nearest true 4-D subspace on
each track's observed entries); the wall time of each method. The pipelines
refuse tracks with too few observed entries (a tracker's 1-2-frame tracks):
they run on the tracks and coordinates ``sklearn_gpca._segment.projectable``
keeps (at least 3 observed frames), scored on those tracks only, as a user who
drops the short tracks would run them; ``segment_motions`` and the oracle label
and are scored on every track. Writes
``benchmarks/results/segment_<setting>.md`` and its CSV tables.

Usage::

    python benchmarks/bench_segment.py --setting tracks --draws 3 --jobs 2
    python benchmarks/bench_segment.py --setting hopkins --jobs 2
    python benchmarks/bench_segment.py --setting occlusion --jobs 2
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import time
import warnings
from pathlib import Path

import numpy as np
from _tables import markdown_table, write_markdown
from joblib import Parallel, delayed
from scipy.stats import kendalltau
from threadpoolctl import threadpool_limits

from sklearn_gpca import (
    GPCAClustering,
    PowerFactorization,
    paper_pipeline,
    segment_motions,
)
from sklearn_gpca._fitted_dimensions import (
    EXTRA_DIMENSIONS,
    fitted_ambiguous_fraction,
)
from sklearn_gpca._observed_subspaces import observed_entries
from sklearn_gpca._segment import (
    AMBIGUITY_DIM_DROP,
    AMBIGUITY_TOLERANCE,
    CONSISTENCY_TOLERANCE,
    MISFIT_COST,
    projectable,
)
from sklearn_gpca._segment_selection import select_segmentation
from sklearn_gpca.datasets import load_hopkins155, make_missing, make_tracks
from sklearn_gpca.metrics import misclassification_rate, oracle_labels

#: Realistic make_tracks settings: name -> keyword arguments. Sizes are kept
#: small enough for a short run (the pipelines' PowerFactorization dominates),
#: but one setting is a long sequence at its scene's defaults.
TRACK_SETTINGS = {
    "driving, 3 motions": {"scene": "driving"},
    "driving, 4 motions, affine": {
        "scene": "driving",
        "n_motions": 4,
        "camera": "affine",
    },
    "handheld, 3 motions, 40 frames": {
        "scene": "handheld",
        "n_frames": 40,
        "missing": 0.5,
    },
    # the scene's own defaults: 800 tracks, 100 frames, 50 % missing
    "handheld, 3 motions, 100 frames": {"scene": "handheld"},
    "handheld, 5 motions, 40 frames, affine": {
        "scene": "handheld",
        "n_motions": 5,
        "n_frames": 40,
        "missing": 0.5,
        "camera": "affine",
    },
    "lab, 2 motions, 30 frames, 40% missing": {
        "scene": "lab",
        "n_frames": 30,
        "missing": 0.4,
    },
    "lab, 3 motions, 30 frames, 30% missing": {
        "scene": "lab",
        "n_motions": 3,
        "n_frames": 30,
        "missing": 0.3,
    },
}
#: The setting drawn with 10 % outlier tracks.
OUTLIER_SETTING = "handheld, 3 motions, 40 frames"
#: ``outlier_threshold`` of the outlier table: a false-alarm probability per
#: track (see ``bench_outliers.py``, which chose it).
OUTLIER_THRESHOLD = 1e-3
#: Selection rules reported: row key -> (candidates, selection).
RULES = {
    "auto+coding": ("auto", "coding_length"),
    "auto+separability": ("auto", "separability"),
    "all+coding": ("all", "coding_length"),
    "all+separability": ("all", "separability"),
    "all+fitted_separability": ("all", "fitted_separability"),
    "auto+consistency": ("auto", "consistency"),
    "all+consistency": ("all", "consistency"),
}
#: Name prefixes of the candidates drawn after a first judgement (the peeled
#: fallback and the re-segmented objects): the rule rows leave them out.
SECOND_STAGE = ("peel ", "re-segmented ")
#: Criteria whose agreement with the error is reported: name -> info key.
CRITERIA = {
    "coding length": "coding_lengths",
    "ambiguous fraction": "ambiguity",
    "ambiguous fraction at fitted dimensions": "fitted_ambiguity",
    "share of tracks nearer another motion's model": "inconsistency",
    "robust fit to the own model": "residuals",
}


def fitted_ambiguities(X, info, subspace_dim=4):
    """``info.fitted_ambiguity`` of ``segment_motions(X, ..., return_info=True)``
    as ``selection="fitted_separability"`` computes it, for a call without
    screening or outliers (every track in every candidate)."""
    X0, mask = observed_entries(X)
    X0 = X0 / info.scale
    return np.array(
        [
            fitted_ambiguous_fraction(
                X0,
                mask,
                labels,
                info.noise,
                min_dim=max(subspace_dim - AMBIGUITY_DIM_DROP, 1),
                max_dim=subspace_dim + EXTRA_DIMENSIONS,
            )
            if np.unique(labels).size > 1
            else np.nan
            for labels in info.refined
        ]
    )


def _pipeline(X, n, paper):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            if paper:
                return paper_pipeline(n, random_state=0).fit_predict(X)
            Z = PowerFactorization(random_state=0).fit_transform(X)
            return GPCAClustering(n, random_state=0).fit_predict(Z)
        except ValueError:
            return None


def _timed(function):
    start = time.perf_counter()
    result = function()
    return result, time.perf_counter() - start


def run_one(setting, name, X, y, n, threads, paper):
    with threadpool_limits(threads):
        inliers = y >= 0
        X, y = X[inliers], y[inliers]
        row = {"setting": setting, "name": name, "n": n}
        row["missing"] = float(np.isnan(X).mean())
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            # the default, outlier screening included
            screened, row["segment_s"] = _timed(
                lambda: segment_motions(X, n, random_state=0)
            )
            # the candidates and rules on every track: without screening
            (labels, info), row["all_s"] = _timed(
                lambda: segment_motions(
                    X,
                    n,
                    init="all",
                    screen_outliers=False,
                    random_state=0,
                    return_info=True,
                )
            )
            # what selection="fitted_separability" would compute
            info.fitted_ambiguity = fitted_ambiguities(X, info)
        errors = [misclassification_rate(y, r) for r in info.refined]
        row["candidates"] = dict(zip(info.candidates, errors, strict=True))
        for key, (init, selection) in RULES.items():
            keep = [
                i
                for i, c in enumerate(info.candidates)
                if not c.startswith(SECOND_STAGE)
                and (init == "all" or not c.startswith("votes"))
            ]
            ambiguity = info.ambiguity
            if selection == "fitted_separability":
                # as segment_motions(selection="fitted_separability") does
                ambiguity = np.fmax(info.ambiguity, info.fitted_ambiguity)
                selection = "separability"
            chosen = select_segmentation(
                info.coding_lengths[keep],
                ambiguity[keep],
                selection=selection,
                tolerance=(
                    CONSISTENCY_TOLERANCE
                    if selection == "consistency"
                    else AMBIGUITY_TOLERANCE
                ),
                inconsistency=info.inconsistency[keep],
                residual=info.residuals[keep],
                misfit_cost=MISFIT_COST if selection == "consistency" else None,
                n_tracks=info.refined[0].size,
            )
            row[key] = errors[keep[chosen]]
        row["segment"] = misclassification_rate(y, screened)
        # the peeled starts (init="peel"), alone and pooled with the
        # default's candidates (same noise and scale: same seed, same graph)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            (peeled, peel_info), row["peel_s"] = _timed(
                lambda: segment_motions(
                    X,
                    n,
                    init="peel",
                    screen_outliers=False,
                    random_state=0,
                    return_info=True,
                )
            )
        row["peel"] = misclassification_rate(y, peeled)
        peel_errors = [misclassification_rate(y, r) for r in peel_info.refined]
        row["peel hindsight"] = min(peel_errors)
        pooled = select_segmentation(
            np.concatenate([info.coding_lengths, peel_info.coding_lengths]),
            np.concatenate([info.ambiguity, peel_info.ambiguity]),
            selection="separability",
            tolerance=AMBIGUITY_TOLERANCE,
        )
        row["all+peel"] = (errors + peel_errors)[pooled]
        # merge/split moves from the default's segmentation (its refinement
        # from itself is a fixed point): the moves' own time
        (moved, moves_info), row["moves_s"] = _timed(
            lambda: segment_motions(
                X,
                n,
                init=labels,
                merge_split=True,
                screen_outliers=False,
                random_state=0,
                return_info=True,
            )
        )
        row["moves"] = misclassification_rate(y, moved)
        row["n_moves"] = moves_info.n_moves
        for name, info_key in CRITERIA.items():
            values = np.asarray(info[info_key], dtype=float)
            row[f"hit {name}"] = float(
                errors[int(np.argmin(values))] <= min(errors) + 1e-12
            )
            row[f"tau {name}"] = (
                kendalltau(values, errors)[0]
                if np.ptp(errors) > 0 and np.ptp(values) > 0
                else np.nan
            )
        # what a perfect selection among the refined candidates would give
        row["hindsight"] = min(row["candidates"].values())
        # the pipelines take the tracks and coordinates they can project
        rows, cols = projectable(~np.isnan(X))
        row["projectable"] = float(rows.mean())
        Xp, yp = X[np.ix_(rows, cols)], y[rows]
        for key, use_paper in [("default", False), ("paper", True)]:
            if key == "paper" and not paper:
                continue
            found, row[f"{key}_s"] = _timed(lambda p=use_paper: _pipeline(Xp, n, p))
            row[key] = np.nan if found is None else misclassification_rate(yp, found)
        row["oracle"] = misclassification_rate(y, oracle_labels(X, y))
    return row


def run_outliers(name, X, y, n, threads):
    """Outlier precision / recall and inlier error, with and without outliers."""
    with threadpool_limits(threads), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        labels = segment_motions(
            X, n, outlier_threshold=OUTLIER_THRESHOLD, random_state=0
        )
        inliers = y >= 0
        clean = segment_motions(
            X[inliers], n, outlier_threshold=OUTLIER_THRESHOLD, random_state=0
        )
        plain = segment_motions(X[inliers], n, random_state=0)
    flagged, outliers = labels == -1, y == -1
    hits = np.sum(flagged & outliers)
    return {
        "name": name,
        "precision": hits / max(flagged.sum(), 1),
        "recall": hits / max(outliers.sum(), 1),
        # inlier tracks flagged as outliers count as errors (noise="class")
        "inlier_error": misclassification_rate(y[inliers], labels[inliers]),
        "clean_error": misclassification_rate(y[inliers], clean),
        "plain_error": misclassification_rate(y[inliers], plain),
    }


def track_draws(n_draws, outlier_fraction=None, first_seed=0):
    settings = (
        {OUTLIER_SETTING: TRACK_SETTINGS[OUTLIER_SETTING]}
        if outlier_fraction is not None
        else TRACK_SETTINGS
    )
    for setting, params in settings.items():
        extra = (
            {} if outlier_fraction is None else {"outlier_fraction": outlier_fraction}
        )
        for seed in range(first_seed, first_seed + n_draws):
            X, y = make_tracks(**params, **extra, random_state=seed)
            yield setting, f"{setting} #{seed}", X, y, int(np.unique(y[y >= 0]).size)


def hopkins_sequences(setting, data):
    for bunch in load_hopkins155(data):
        if setting == "hopkins":
            yield "hopkins", bunch.name, bunch.X, bunch.y, bunch.n_motions
        elif bunch.n_motions == 2:
            X = make_missing(bunch.X, 0.3, random_state=0)
            yield "occlusion", bunch.name, X, bunch.y, 2


def _cell(values, fmt="{:.2f}", scale=100.0):
    values = np.asarray(values, dtype=float)
    if values.size == 0 or np.all(np.isnan(values)):
        return "n/a"
    return fmt.format(scale * np.nanmean(values))


def _methods(rows):
    names = sorted({c for r in rows for c in r["candidates"]})
    methods = [
        (
            "segment_motions (default: init='all', consistency, screen_outliers)",
            "segment",
            None,
        )
    ]
    methods += [
        (
            f"segment_motions, init='{init}', selection='{selection}', "
            "screen_outliers=False",
            key,
            None,
        )
        for key, (init, selection) in RULES.items()
    ]
    methods += [
        ("segment_motions, merge_split=True, screen_outliers=False", "moves", "moves_s")
    ]
    methods += [(f"segment_motions, candidate {c} refined", c, None) for c in names]
    methods += [
        ("segment_motions, best refined candidate (hindsight)", "hindsight", None)
    ]
    methods += [("segment_motions, init='peel'", "peel", "peel_s")]
    methods += [
        (
            "segment_motions, best peeled start refined (hindsight)",
            "peel hindsight",
            None,
        )
    ]
    methods += [
        (
            "segment_motions, init='all' and 'peel' candidates, separability",
            "all+peel",
            None,
        )
    ]
    methods += [("(time of segment_motions, default)", None, "segment_s")]
    methods += [("default pipeline", "default", "default_s")]
    if any("paper" in r for r in rows):
        methods += [("paper pipeline", "paper", "paper_s")]
    methods += [("oracle", "oracle", None)]
    return methods


def _value(row, key):
    if key is None:
        return np.nan
    return row["candidates"].get(key, np.nan) if key not in row else row[key]


def criteria_table(rows):
    """Agreement of each criterion with the error over the refined candidates."""
    header = [
        "criterion (init='all')",
        "mean Kendall tau with the error",
        "sequences with a tau",
        "its minimum is the best candidate (share of sequences)",
    ]
    body = []
    for name in CRITERIA:
        taus = np.array([r[f"tau {name}"] for r in rows], dtype=float)
        body.append(
            [
                name,
                f"{np.nanmean(taus):.2f}" if np.isfinite(taus).any() else "n/a",
                f"{int(np.isfinite(taus).sum())} of {len(rows)}",
                f"{np.mean([r[f'hit {name}'] for r in rows]):.2f}",
            ]
        )
    return markdown_table(header, body)


def tracks_table(rows):
    settings = list(dict.fromkeys(r["setting"] for r in rows))
    header = ["method", *settings, "all", "median s / sequence"]
    body = []
    for label, key, tkey in _methods(rows):
        cells = [
            _cell([_value(r, key) for r in rows if r["setting"] == s]) for s in settings
        ]
        cells.append(_cell([_value(r, key) for r in rows]))
        if key is None:
            cells = [""] * len(cells)
        cells.append(f"{np.median([r[tkey] for r in rows]):.2f}" if tkey else "")
        body.append([label, *cells])
    missing = [
        _cell([r["missing"] for r in rows if r["setting"] == s], "{:.0f}")
        for s in settings
    ]
    body.append(["(missing entries, %)", *missing, "", ""])
    kept = [
        _cell([r["projectable"] for r in rows if r["setting"] == s], "{:.0f}")
        for s in settings
    ]
    body.append(["(tracks the pipelines take, %)", *kept, "", ""])
    return markdown_table(header, body)


def hopkins_table(rows):
    groups = [("all", None)] + [
        (f"{k} motions", k) for k in sorted({r["n"] for r in rows})
    ]
    header = ["method", *[g for g, _ in groups], "median", "> 5 %", "median s"]
    body = []
    for label, key, tkey in _methods(rows):
        values = 100 * np.array([_value(r, key) for r in rows], dtype=float)
        cells = [
            _cell([_value(r, key) for r in rows if n is None or r["n"] == n])
            for _, n in groups
        ]
        if key is None:
            cells = [""] * len(cells)
        cells += [
            f"{np.nanmedian(values):.2f}" if key else "",
            f"{int(np.sum(values > 5))}" if key else "",
            f"{np.median([r[tkey] for r in rows]):.3f}" if tkey else "",
        ]
        body.append([label, *cells])
    return markdown_table(header, body)


def outlier_table(rows):
    header = [
        "draws",
        "outlier precision",
        "outlier recall",
        "inlier error, outliers present (%)",
        "same inliers alone, with the threshold (%)",
        "same inliers alone, no threshold (%)",
    ]
    body = [
        [
            f"{OUTLIER_SETTING}, 10 % outliers ({len(rows)} draws)",
            _cell([r["precision"] for r in rows], scale=1.0),
            _cell([r["recall"] for r in rows], scale=1.0),
            _cell([r["inlier_error"] for r in rows]),
            _cell([r["clean_error"] for r in rows]),
            _cell([r["plain_error"] for r in rows]),
        ]
    ]
    return markdown_table(header, body)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--setting", default="tracks", choices=["tracks", "hopkins", "occlusion"]
    )
    parser.add_argument("--data", default="../shared/data/hopkins155")
    parser.add_argument("--draws", type=int, default=3, help="seeds per setting")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument(
        "--first-seed", type=int, default=0, help="seeds first-seed .. + draws - 1"
    )
    parser.add_argument("--subset", type=int, default=1, help="every k-th sequence")
    parser.add_argument("--out", default=None)
    args = parser.parse_args()
    threads = 1 if args.jobs > 1 else None
    tracks = args.setting == "tracks"
    todo = (
        list(track_draws(args.draws, first_seed=args.first_seed))
        if tracks
        else list(hopkins_sequences(args.setting, args.data))[:: args.subset]
    )
    start = time.perf_counter()
    rows = Parallel(n_jobs=args.jobs)(
        delayed(run_one)(*task, threads, tracks) for task in todo
    )
    elapsed = time.perf_counter() - start
    command = (
        f"python benchmarks/bench_segment.py --setting {args.setting}"
        + (f" --draws {args.draws}" if tracks else "")
        + (f" --first-seed {args.first_seed}" if tracks and args.first_seed else "")
        + f" --jobs {args.jobs}"
        + (f" --subset {args.subset}" if args.subset > 1 else "")
    )
    threads_note = (
        "OMP_NUM_THREADS=1 per job" if threads == 1 else "default BLAS threads"
    )
    lines = [
        f"# segment_motions: {args.setting}",
        "",
        f"`{command}` ({elapsed:.0f} s wall time, {threads_note}, machine shared "
        "with other jobs: timings are noisy). Misclassification (%) of the "
        "inlier tracks, mean over the sequences; median wall time per "
        "sequence. The default screens outliers (`screen_outliers=True`: "
        "tracks flagged by the outlier test at 1e-3 set aside, then given "
        "the nearest motion); the candidates, selection rules, peeled starts "
        "and moves are measured on every track, without screening, from "
        "one `segment_motions(..., screen_outliers=False, "
        "return_info=True)` call; each rule row judges the routes' "
        "candidates of that call alone (the peeled and re-segmented "
        "candidates, drawn after a first judgement by the consistency rule, "
        "are left out). "
        "*oracle*: the nearest true 4-D subspace on each track's "
        "observed entries (`sklearn_gpca.metrics.oracle_labels`), a reference "
        "that knows the groups. *default pipeline*: `PowerFactorization()` + "
        "`GPCAClustering(n)`; *paper pipeline*: `paper_pipeline(n)`; on tracks "
        "with missing entries both run on the tracks observed in at least 3 "
        "frames and are scored on those (the others are a tracker's shortest "
        "tracks, the hardest to label). n/a: the pipeline refused the data. "
        "*merge_split=True*: the moves started from the default's segmentation "
        "(`segment_motions(X, n, init=labels, merge_split=True)`); its time is "
        "that call's alone, to add to the default's.",
        "",
    ]
    if tracks:
        lines += [
            "Settings (`make_tracks` keyword arguments beside the scene "
            f"defaults, seeds {args.first_seed} .. {args.first_seed + args.draws - 1}"
            "; outlier tracks removed):",
            "",
        ]
        lines += [f"- {s}: `{p}`" for s, p in TRACK_SETTINGS.items()]
        lines += ["", *tracks_table(rows), "", *criteria_table(rows), ""]
        outlier_rows = Parallel(n_jobs=args.jobs)(
            delayed(run_outliers)(name, X, y, n, threads)
            for _, name, X, y, n in track_draws(
                args.draws, outlier_fraction=0.1, first_seed=args.first_seed
            )
        )
        lines += [
            "## Outliers",
            "",
            f"`make_tracks(..., outlier_fraction=0.1)` of the setting "
            f"'{OUTLIER_SETTING}', seeds {args.first_seed} .. "
            f"{args.first_seed + args.draws - 1}, segmented with "
            f"`outlier_threshold={OUTLIER_THRESHOLD:g}` (label -1). An inlier "
            "flagged -1 counts as an error. The last two columns segment the "
            "same draws with the outlier rows removed.",
            "",
            *outlier_table(outlier_rows),
            "",
        ]
    else:
        lines += [*hopkins_table(rows), "", *criteria_table(rows), ""]
    out = args.out or Path(__file__).parent / "results" / f"segment_{args.setting}.md"
    write_markdown(out, "\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
