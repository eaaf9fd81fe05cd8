"""Time of the perspective-camera fit, as a ratio to an affine fit of the same tracks.

Run from the project root::

    python benchmarks/bench_projective_fit.py \
        --out benchmarks/results/projective_fit.md

The tracks are the background (the largest motion, about 580 tracks) of
``make_tracks(scene="handheld", random_state=seed)``: 100 frames, half the
entries missing in windows. Timed, each the least of ``--repeats`` runs:

- *from scratch*: ``fit_projective_motion(X0, mask)``, the sequential fit
  (frames added one at a time, forwards and backwards) that the refinement of
  ``segment_motions`` runs at the start of every perspective candidate;
- *warm*: ``fit_projective_motion(X0, mask, cameras=...)`` from the fitted
  cameras, then ``projective_residuals`` of every track of the scene: what
  each later refinement round and the selection run;
- the baseline, in the same process: ``fit_observed_subspace`` of the same
  tracks at dimension 4 (the affine model, 30 rounds).

``--against FILE`` also times another version of
``sklearn_gpca/_projective_motion.py`` in the same process, e.g. the one
before a change::

    git show REV:sklearn_gpca/_projective_motion.py > /tmp/projective_old.py
    python benchmarks/bench_projective_fit.py --against /tmp/projective_old.py

Set ``OMP_NUM_THREADS=1`` to time one BLAS thread; the page records the count.
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import datetime
import importlib.util
import os
import time

import numpy as np
from _tables import write_markdown

import sklearn_gpca._projective_motion as current
from sklearn_gpca._observed_subspaces import fit_observed_subspace, observed_entries
from sklearn_gpca.datasets import make_tracks


def _load(path):
    spec = importlib.util.spec_from_file_location("projective_against", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _least(function, repeats):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - start)
    return min(times), result


def _time_module(module, X0, mask, members, repeats):
    scratch, (cameras, _) = _least(
        lambda: module.fit_projective_motion(X0[members], mask[members]), repeats
    )

    def warm():
        fitted, kept = module.fit_projective_motion(
            X0[members], mask[members], cameras=cameras
        )
        return module.projective_residuals(X0, mask, fitted, kept)

    warm_time, (residuals, dofs) = _least(warm, repeats)
    per_dof = residuals[members][dofs[members] > 0] / dofs[members][dofs[members] > 0]
    return scratch, warm_time, float(np.median(per_dof))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=2)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--against", default=None, help="another module file")
    parser.add_argument("--out", default=None, help="also write the page here")
    args = parser.parse_args(argv)
    modules = [("this version", current)]
    if args.against:
        modules.append((f"`{os.path.basename(args.against)}`", _load(args.against)))
    header = (
        "| draw | tracks | version | from scratch s | warm s | affine s | "
        "scratch / affine | warm / affine | median residual per dof |"
    )
    lines = [header, "|---|---|---|---|---|---|---|---|---|"]
    print(*lines, sep="\n")
    for seed in range(args.seeds):
        X, y = make_tracks(scene="handheld", random_state=seed)[:2]
        X0, mask = observed_entries(X)
        X0 = X0 / np.sqrt(np.mean(X0[mask] ** 2))
        members = y == np.argmax(np.bincount(y[y >= 0]))
        for name, module in modules:
            tracks, seen = X0[members], mask[members]
            affine, _ = _least(
                lambda: fit_observed_subspace(tracks, seen, 4),  # noqa: B023
                args.repeats,
            )
            scratch, warm, residual = _time_module(
                module, X0, mask, members, args.repeats
            )
            row = (
                f"| {seed} | {int(members.sum())} | {name} | {scratch:.2f} | "
                f"{warm:.3f} | {affine:.3f} | {scratch / affine:.1f} | "
                f"{warm / affine:.2f} | {residual:.3g} |"
            )
            lines.append(row)
            print(row, flush=True)
    threads = os.environ.get("OMP_NUM_THREADS", "the default")
    stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%d %b %Y %H:%M")
    command = "python benchmarks/bench_projective_fit.py" + (
        f" --against {args.against}" if args.against else ""
    )
    if args.out:
        command += f" --out {args.out}"
    if "OMP_NUM_THREADS" in os.environ:
        command = f"OMP_NUM_THREADS={threads} {command}"
    page = (
        "# Perspective-camera fit: time against an affine fit of the same tracks\n\n"
        f"`{command}`, {stamp} UTC, BLAS threads: {threads}. Each time is the "
        f"least of {args.repeats} runs in one process; the ratios divide by the "
        "affine fit timed beside it (see the script's docstring).\n\n"
        + "\n".join(lines)
        + "\n"
    )
    if args.out:
        write_markdown(args.out, page)


if __name__ == "__main__":
    main()
