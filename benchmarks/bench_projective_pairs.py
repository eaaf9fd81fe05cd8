"""The perspective fit's steps on the seen point-frames against the dense steps.

Run from the project root::

    python benchmarks/bench_projective_pairs.py \
        --out benchmarks/results/projective_pairs.md

``sklearn_gpca._projective_pairs`` runs the perspective fit's steps on the
seen point-frames alone when fewer than ``MAX_DENSITY`` of them are seen; the
dense steps of ``sklearn_gpca._projective_motion`` batch every track over
every frame. Both are timed here in the same process on the same tracks (each
the least of ``--repeats`` runs), the route forced by setting
``MAX_DENSITY`` to 0 (dense) or above 1 (seen point-frames):

- *warm*: ``fit_projective_motion(X0, mask, cameras=...)`` from fitted
  cameras, then ``projective_residuals`` of the same tracks: what every
  refinement round and the selection of ``segment_motions`` run;
- *from scratch*: ``fit_projective_motion(X0, mask)``, the sequential fit,
  dense against the shipped ``MAX_DENSITY`` (the alternations on each
  window of frames and the last one on all frames then choose their route
  by their own share of seen point-frames).

Tracks: the background (largest motion) of ``make_tracks(scene="handheld",
n_frames=100, missing=m)`` for several ``m``, and, when ``--data-home``
holds the low-rank benchmarks, the giraffe video's background tracks
(an eighth of ``Um_giraffe_bg``, as ``check_real_composite.py`` draws
them: 190 frames, 7 % of the point-frames seen). The table
gives the fraction of point-frames seen, each route's seconds, the ratio
(dense / the other: above 1 the latter is faster), the number of tracks
whose warm residual differs between the two routes by more than 1e-6 of
itself (or of the median residual, where smaller), and the residuals'
medians. The routes sum in another order, which on a well-posed fit changes
the residuals by rounding only; on an ill-posed one (the giraffe's) the
rounding steers some tracks' Levenberg-Marquardt steps elsewhere. The
column beside it measures the same on the dense route alone, the tracks
permuted (another order of the same sums).

Set ``OMP_NUM_THREADS=1`` to time one BLAS thread; the page records the count.
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import datetime
import os
from pathlib import Path

import numpy as np
from _tables import write_markdown
from bench_projective_fit import _least

import sklearn_gpca._projective_pairs as pairs
from sklearn_gpca._observed_subspaces import observed_entries
from sklearn_gpca._projective_motion import (
    fit_projective_motion,
    projective_residuals,
)
from sklearn_gpca.datasets import make_tracks


def _routes(X, repeats):
    X0, mask = observed_entries(X)
    cameras, _ = fit_projective_motion(X0, mask)
    row = {}
    residuals = {}

    def warm():
        fitted, seen = fit_projective_motion(X0, mask, cameras=cameras)
        return projective_residuals(X0, mask, fitted, seen)[0]

    for route, density in (("dense", 0.0), ("pairs", 1.01), ("default", None)):
        pairs.MAX_DENSITY = DEFAULT_DENSITY if density is None else density
        if route != "default":
            row[f"warm {route}"], residuals[route] = _least(warm, repeats)
        if route != "pairs":
            row[f"scratch {route}"], _ = _least(
                lambda: fit_projective_motion(X0, mask), max(1, repeats // 3)
            )
    # the dense route on the tracks in another order: rounding alone
    pairs.MAX_DENSITY = 0.0
    order = np.random.RandomState(0).permutation(X0.shape[0])
    fitted, seen = fit_projective_motion(X0[order], mask[order], cameras=cameras)
    residuals["permuted"] = np.empty(X0.shape[0])
    residuals["permuted"][order] = projective_residuals(
        X0[order], mask[order], fitted, seen
    )[0]
    pairs.MAX_DENSITY = DEFAULT_DENSITY
    # relative to the residual, or to the median one for a track fitted exactly
    scale = np.maximum(residuals["dense"], np.median(residuals["dense"]))
    for other in ("pairs", "permuted"):
        difference = np.abs(residuals["dense"] - residuals[other]) / scale
        row[f"difference {other}"] = int(np.count_nonzero(difference > 1e-6))
    row["median"] = [float(np.median(residuals[r])) for r in ("dense", "pairs")]
    seen = mask[:, 0::2] & mask[:, 1::2]
    return float(seen.mean()), row


def _giraffe(data_home, seed):
    """An eighth of the giraffe's background tracks, as ``check_real_composite``."""
    from sklearn_gpca.datasets import load_lowrank

    X = load_lowrank("Um_giraffe_bg", data_home=data_home).X
    return X[np.random.RandomState(seed).rand(len(X)) < 0.125]


DEFAULT_DENSITY = pairs.MAX_DENSITY


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--missing", type=float, nargs="+", default=[0.3, 0.5, 0.7, 0.8, 0.9]
    )
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--data-home", default="../shared/data/lowrank")
    parser.add_argument("--out", type=Path)
    args = parser.parse_args()
    cases = []
    for missing in args.missing:
        X, y = make_tracks(
            scene="handheld", n_frames=100, missing=missing, random_state=args.seed
        )
        background = np.bincount(y[y >= 0]).argmax()
        cases.append((f"handheld, 100 frames, missing={missing}", X[y == background]))
    if Path(args.data_home).is_dir():
        cases.append(
            ("giraffe background, an eighth", _giraffe(args.data_home, args.seed))
        )
    header = [
        "tracks",
        "n",
        "seen point-frames",
        "warm, dense s",
        "warm, seen point-frames s",
        "warm ratio",
        "from scratch, dense s",
        "from scratch, shipped s",
        "from scratch ratio",
        "tracks whose warm residual differs",
        "the same, dense on the tracks permuted",
        "median, dense / seen point-frames",
    ]
    rows = []
    for name, X in cases:
        density, r = _routes(X, args.repeats)
        rows.append(
            [
                name,
                str(X.shape[0]),
                f"{density:.2f}",
                f"{r['warm dense']:.3f}",
                f"{r['warm pairs']:.3f}",
                f"{r['warm dense'] / r['warm pairs']:.2f}",
                f"{r['scratch dense']:.2f}",
                f"{r['scratch default']:.2f}",
                f"{r['scratch dense'] / r['scratch default']:.2f}",
                str(r["difference pairs"]),
                str(r["difference permuted"]),
                "{:.4g} / {:.4g}".format(*r["median"]),
            ]
        )
        print(" | ".join(rows[-1]), flush=True)
    threads = os.environ.get("OMP_NUM_THREADS", "the default")
    command = "python benchmarks/bench_projective_pairs.py"
    if args.out:
        command += f" --out {args.out}"
    intro = (
        f"`{command}`, "
        f"{datetime.datetime.now(datetime.UTC):%d %b %Y %H:%M} UTC, BLAS threads: "
        f"{threads}, the least of {args.repeats} runs (from scratch: of "
        f"{max(1, args.repeats // 3)}). `MAX_DENSITY` = {DEFAULT_DENSITY}: the "
        "seen point-frames' route is taken below it. See the script's docstring."
    )
    table = [
        "| " + " | ".join(header) + " |",
        "|" + "---|" * len(header),
        *("| " + " | ".join(row) + " |" for row in rows),
    ]
    text = "\n\n".join(
        ["# The perspective fit on the seen point-frames", intro, "\n".join(table)]
    )
    print(intro)
    if args.out:
        write_markdown(args.out, text + "\n")


if __name__ == "__main__":
    main()
