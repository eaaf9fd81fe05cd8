"""Sequences of short tracks: how far the segmentation falls from the oracle.

Run from the project root (about fifteen minutes)::

    python benchmarks/check_short_sequences.py \\
        --out benchmarks/results/short_sequences.md

Three tables of ``segment_motions(X, n, random_state=0)`` errors (%), outlier
tracks removed, ``n`` the true number of motions:

1. ``make_tracks`` draws (seeds 0-2; lab with complete tracks, driving and
   hand-held with their scene's defaults, 12 frames) cut to their first two
   and three frames (tracks seen in none of them dropped): with two frames a
   4-D motion subspace fits every track, and ``segment_motions`` warns;
2. hand-held draws of 40 frames (400 tracks, 50 % missing, seeds 0-2) alone,
   then with 200 copies of their tracks cut to one or two of their frames
   (noise 1e-3 added): the long tracks' error, and how often a copy gets its
   parent's label;
3. hand-held draws of 60 frames (600 tracks, seeds 0-3) whose tracks live
   ``mean_lifetime`` 3, 5 and 10 frames: nearly every track short; whether
   ``segment_motions`` warns that most tracks are seen in three frames or
   fewer. Beside them the oracle (``metrics.oracle_labels``, which gives a
   track that no subspace can test the largest group's label, the
   background's) and the error of labelling every track background.

Writes a markdown page with ``--out`` (also printed).
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import time
import warnings
from pathlib import Path

import numpy as np

from sklearn_gpca import segment_motions
from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.metrics import misclassification_rate, oracle_labels


def _inliers(**kwargs):
    X, y = make_tracks(**kwargs)[:2]
    return X[y >= 0], y[y >= 0]


def _segmented(X, y):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return segment_motions(X, len(np.unique(y)), random_state=0)


def _error(y, labels):
    return f"{100 * misclassification_rate(y, labels):.1f}"


def cut_frames(seeds):
    scenes = {
        "lab, complete tracks": dict(scene="lab", missing=0.0),
        "driving": dict(scene="driving"),
        "hand-held": dict(scene="handheld"),
    }
    lines = [
        "| scene | seed | 2 frames | 3 frames | all 12 frames |",
        "|---|---|---|---|---|",
    ]
    for name, kwargs in scenes.items():
        for seed in seeds:
            X, y = _inliers(n_frames=12, random_state=seed, **kwargs)
            errors = []
            for n_frames in (2, 3, 12):
                cut = X[:, : 2 * n_frames]
                seen = ~np.isnan(cut).all(axis=1)
                errors.append(_error(y[seen], _segmented(cut[seen], y[seen])))
            lines.append(f"| {name} | {seed} | " + " | ".join(errors) + " |")
    return lines


def short_copies(seeds, n_copies=200):
    lines = [
        "| seed | tracks | long tracks alone | long tracks, short copies added "
        "| copies with their parent's label % |",
        "|---|---|---|---|---|",
    ]
    for seed in seeds:
        X, y = _inliers(
            scene="handheld", n_frames=40, n_tracks=400, missing=0.5, random_state=seed
        )
        rng = np.random.RandomState(seed)
        parents = rng.choice(y.size, n_copies)
        copies = np.full((n_copies, X.shape[1]), np.nan)
        for row, parent in enumerate(parents):  # a benchmark helper: 200 rows
            frames = np.flatnonzero(~np.isnan(X[parent, 0::2]))
            length = rng.randint(1, 3)
            first = rng.randint(0, max(frames.size - length, 0) + 1)
            for f in frames[first : first + length]:
                copies[row, 2 * f : 2 * f + 2] = X[parent, 2 * f : 2 * f + 2]
        copies += rng.normal(0, 1e-3, copies.shape)
        alone = _segmented(X, y)
        both = _segmented(np.vstack([X, copies]), np.r_[y, y[parents]])
        same = 100 * np.mean(both[y.size :] == both[parents])
        lines.append(
            f"| {seed} | {y.size} | {_error(y, alone)} | "
            f"{_error(y, both[: y.size])} | {same:.0f} |"
        )
    return lines


def short_lifetimes(lifetimes, seeds):
    lines = [
        "| mean lifetime (frames) | seed | missing % | median frames per track "
        "| tracks in <= 3 frames % | warns | segment_motions | s | oracle "
        "| every track background |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for lifetime in lifetimes:
        for seed in seeds:
            X, y = _inliers(
                scene="handheld",
                n_frames=60,
                n_tracks=600,
                mean_lifetime=lifetime,
                random_state=seed,
            )
            frames = np.count_nonzero(~np.isnan(X[:, 0::2]), axis=1)
            start = time.perf_counter()
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                labels = segment_motions(X, len(np.unique(y)), random_state=0)
            seconds = time.perf_counter() - start
            warns = any("Most tracks of X" in str(w.message) for w in caught)
            oracle = oracle_labels(X, y)
            lines.append(
                f"| {lifetime} | {seed} | {100 * np.isnan(X).mean():.0f} "
                f"| {np.median(frames):.0f} | {100 * np.mean(frames <= 3):.0f} "
                f"| {'yes' if warns else 'no'} | {_error(y, labels)} "
                f"| {seconds:.0f} | {_error(y, oracle)} "
                f"| {_error(y, np.zeros_like(y))} |"
            )
    return lines


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=None)
    args = parser.parse_args(argv)
    seeds = (0, 1, 2)
    page = [
        "# Sequences of short tracks",
        "",
        "`python benchmarks/check_short_sequences.py"
        + (f" --out {args.out}`" if args.out else "`")
        + f", {time.strftime('%d %b %Y')}; see the script's docstring for the "
        "draws. Misclassification (%) of `segment_motions(X, n, random_state=0)`, "
        "outlier tracks removed; seconds are wall time with the default BLAS "
        "threads.",
        "",
        "## Cut to two and three frames",
        "",
        *cut_frames(seeds),
        "",
        "## Short copies among long tracks (hand-held, 40 frames)",
        "",
        *short_copies(seeds),
        "",
        "## Nearly every track short (hand-held, 60 frames)",
        "",
        *short_lifetimes((3, 5, 10), (0, 1, 2, 3)),
        "",
    ]
    text = "\n".join(page)
    print(text)
    if args.out:
        Path(args.out).write_text(text)


if __name__ == "__main__":
    main()
