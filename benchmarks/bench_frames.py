"""PowerFactorization as the sequence grows: seconds and memory per fit.

Run from the project root (about an hour on a busy two-core machine)::

    python benchmarks/bench_frames.py

Data: 1,000 tracks of 3 motions from ``make_tracks(3, scene="lab",
n_tracks=1000, n_frames=F, missing=0.4, outlier_fraction=0)``, tracks born
and lost at random frames (some last a single frame), for F = 10, 30, 100,
300 and 1,000 frames; the frame rate grows with F beyond 100 frames so that
the same motion is filmed in more frames (otherwise the objects leave the
view and 40 % missing cannot be reached). Plus a 100 x 4000 matrix of rank 5
with noise and 10 % of its entries missing at random.

Every fit runs in a fresh process, ``PowerFactorization(random_state=0)``
with the default solver ("varpro") and with ``solver="als"``, under the
machine's default BLAS threads and under ``OMP_NUM_THREADS=1``. Reported:
wall and CPU seconds of ``fit``, the peak memory allocated during the fit
(``tracemalloc``, numpy arrays included), the RMS residual over the observed
entries, the number of random starts. A second table times the default with
the library's one-BLAS-thread limit on and off (``LIMIT_BLAS_THREADS``).
With ``--reference PATH``, a checkout of an earlier version (e.g. ``mkdir
/tmp/before && git archive <commit> | tar -x -C /tmp/before``), a third
table fits that version's default on the F <= 30 rows and compares the
residuals.

``--data motions`` takes the trajectories of ``make_motions(3,
n_points=1000, missing=0.4, missing_pattern="occlusion")`` instead (affine
cameras, every track one window of frames).

Writes ``benchmarks/results/frames.md`` (``frames_motions.md`` with ``--data
motions``) and its CSV tables. Timings are noisy on a shared machine:
compare columns within one run.
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
RESULTS = Path(__file__).parent / "results" / "frames.md"
FRAMES = (10, 30, 100, 300, 1000)
WIDE = "100 x 4000"


def make_data(name, generator, seed=0):
    """The data of one row of the table."""
    from sklearn_gpca.datasets import make_motions, make_tracks

    rng = np.random.RandomState(seed)
    if name == WIDE:
        X = rng.standard_normal((100, 5)) @ rng.standard_normal((5, 4000))
        X += 0.01 * rng.standard_normal(X.shape)
        X[rng.rand(*X.shape) < 0.1] = np.nan
        return X
    n_frames = int(name)
    if generator == "motions":
        return make_motions(
            3,
            n_points=1000,
            n_frames=n_frames,
            missing=0.4,
            missing_pattern="occlusion",
            random_state=seed,
        )[0]
    X, _ = make_tracks(
        3,
        scene="lab",
        n_tracks=1000,
        n_frames=n_frames,
        missing=0.4,
        outlier_fraction=0.0,
        frame_rate=30.0 * max(1.0, n_frames / 100),
        random_state=seed,
    )
    return X


def fit_once(path, solver, limit_threads, reference):
    """One fit in this process; returns its measurements."""
    import tracemalloc
    import warnings

    if reference:
        sys.path.insert(0, reference)
    from sklearn_gpca import PowerFactorization

    if not reference:
        from sklearn_gpca import _factorization

        _factorization.LIMIT_BLAS_THREADS = limit_threads
    X = np.load(path)
    pf = PowerFactorization(solver=solver, random_state=0)
    tracemalloc.start()
    wall, cpu = time.perf_counter(), time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pf.fit(X)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    peak = tracemalloc.get_traced_memory()[1]
    return {
        "seconds": wall,
        "cpu": cpu,
        "peak_mb": peak / 2**20,
        "rms": pf.reconstruction_err_,
        "starts": pf.n_init_,
    }


def measure(path, solver, *, one_thread=False, limit_threads=True, reference=""):
    """:func:`fit_once` in a fresh process."""
    env = dict(os.environ)
    if one_thread:
        env.update(OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="1")
    request = json.dumps([str(path), solver, limit_threads, reference])
    out = subprocess.run(
        [sys.executable, __file__, "--one", request],
        env=env,
        capture_output=True,
        text=True,
        check=True,
    )
    return json.loads(out.stdout.splitlines()[-1])


def determined_part(X, rank):
    """The rows and columns of ``X`` a rank-``rank`` fit can determine."""
    from sklearn_gpca._mask_graph import determinable

    rows, columns = determinable((~np.isnan(X)).astype(float), rank)
    return X[rows][:, columns]


def runs_of(name, args):
    """The (solver, one_thread) fits of one row of the table."""
    runs = [("varpro", False)]
    if args.one_thread_frames is None or (
        name != WIDE and int(name) in args.one_thread_frames
    ):
        runs.append(("varpro", True))
    if args.als_frames is None or name == WIDE or int(name) in args.als_frames:
        runs.append(("als", False))
        if args.als_one_thread:
            runs.append(("als", True))
    return runs


def skipped(rows):
    """The sentence on the fits not run (``--als-frames``), if any."""
    if not any("not run" in row for row in rows):
        return ""
    return (
        " 'not run': ALS was not timed at these frames in this run "
        "(`--als-frames`); its CPU seconds at F <= 100 are in the rows above."
    )


def shape_of(name):
    return WIDE if name == WIDE else f"1000 x {2 * int(name)}"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--one", help=argparse.SUPPRESS)
    parser.add_argument("--frames", type=int, nargs="+", default=list(FRAMES))
    parser.add_argument("--no-wide", action="store_true", help="skip 100 x 4000")
    parser.add_argument(
        "--als-frames",
        type=int,
        nargs="*",
        default=None,
        help="frames at which ALS is run too (default: all)",
    )
    parser.add_argument(
        "--als-one-thread",
        action="store_true",
        help="also time ALS under OMP_NUM_THREADS=1",
    )
    parser.add_argument(
        "--one-thread-frames",
        type=int,
        nargs="*",
        default=None,
        help="frames at which the default is also timed under OMP_NUM_THREADS=1 "
        "(default: all)",
    )
    parser.add_argument("--thread-frames", type=int, nargs="*", default=[30, 100])
    parser.add_argument("--reference", default="", help="earlier checkout")
    parser.add_argument("--reference-frames", type=int, nargs="*", default=[10, 30])
    parser.add_argument(
        "--data",
        choices=["tracks", "motions"],
        default="tracks",
        help="make_tracks (default) or make_motions(missing_pattern='occlusion')",
    )
    parser.add_argument("--output", type=Path, default=None)
    args = parser.parse_args()
    if args.output is None:
        args.output = RESULTS.with_stem(
            "frames" if args.data == "tracks" else "frames_motions"
        )
    if args.one:
        print(json.dumps(fit_once(*json.loads(args.one))))
        return

    args.load = os.getloadavg()[0]
    names = [str(f) for f in args.frames] + ([] if args.no_wide else [WIDE])
    folder = Path(tempfile.mkdtemp(prefix="bench_frames_"))
    paths = {}
    for name in names + [str(f) for f in args.thread_frames + args.reference_frames]:
        if name not in paths:
            paths[name] = folder / f"{name.replace(' ', '')}.npy"
            np.save(paths[name], make_data(name, args.data))
            print(f"data {name}: {np.isnan(np.load(paths[name])).mean():.0%} missing")

    rows = []
    for name in names:
        X = np.load(paths[name])
        cells = [shape_of(name), f"{np.isnan(X).mean():.0%}"]
        fits = {}
        for solver, one_thread in runs_of(name, args):
            fit = measure(paths[name], solver, one_thread=one_thread)
            fits[solver, one_thread] = fit
            print(name, solver, "OMP=1" if one_thread else "default", fit, flush=True)
        for solver in ("varpro", "als"):
            if (solver, False) not in fits:
                cells += ["not run"] + [""] * 4
                continue
            default, single = fits[solver, False], fits.get((solver, True))
            seconds = f"{default['seconds']:.2f}"
            if single is not None:
                seconds += f" ({single['seconds']:.2f})"
            cells += [
                seconds,
                f"{default['cpu']:.2f}",
                f"{default['peak_mb']:.0f}",
                f"{default['rms']:.6g}",
                str(default["starts"]),
            ]
        if ("als", False) in fits:
            ratio = fits["varpro", False]["cpu"] / fits["als", False]["cpu"]
            gap = fits["als", False]["rms"] / fits["varpro", False]["rms"] - 1
            cells += [f"{ratio:.2f}", f"{gap:.1e}"]
        else:
            cells += ["", ""]
        rows.append(cells)

    thread_rows = []
    for frames in args.thread_frames:
        path = paths[str(frames)]
        limited = measure(path, "varpro", limit_threads=True)
        pool = measure(path, "varpro", limit_threads=False)
        thread_rows.append(
            [
                shape_of(str(frames)),
                f"{limited['seconds']:.2f}",
                f"{pool['seconds']:.2f}",
                f"{pool['seconds'] / limited['seconds']:.1f}",
            ]
        )
        print("threads", frames, limited, pool)

    reference_rows = []
    if args.reference:
        for frames in args.reference_frames:
            # the previous version refuses tracks and frames observed in
            # fewer than 5 entries: both fit the rest
            path = folder / f"{frames}_determined.npy"
            np.save(path, determined_part(np.load(paths[str(frames)]), 5))
            new = measure(path, "varpro")
            old = measure(path, "varpro", reference=args.reference)
            reference_rows.append(
                [
                    "{} x {}".format(*np.load(path).shape),
                    f"{old['rms']:.9g}",
                    f"{new['rms']:.9g}",
                    f"{(new['rms'] ** 2 - old['rms'] ** 2) / old['rms'] ** 2:.1e}",
                    f"{old['seconds']:.2f}",
                    f"{new['seconds']:.2f}",
                ]
            )
            print("reference", frames, old, new)
    write(args, rows, thread_rows, reference_rows)


def write(args, rows, thread_rows, reference_rows):
    sys.path.insert(0, str(Path(__file__).parent))
    from _tables import markdown_table, write_markdown

    command = "python benchmarks/bench_frames.py " + " ".join(sys.argv[1:])
    header = ["X", "missing"]
    for solver in ("default (varpro)", "als"):
        header += [
            f"{solver} s (OMP=1)",
            f"{solver} CPU s",
            f"{solver} peak MB",
            f"{solver} RMS",
            f"{solver} starts",
        ]
    header += ["default / als CPU time", "als RMS excess"]
    if args.data == "tracks":
        data = (
            "`1000 x 2F`: 1,000 tracks of 3 motions from `make_tracks(3, "
            'scene="lab", missing=0.4, outlier_fraction=0)`, F frames (frame '
            "rate 30 F / 100 beyond 100 frames)"
        )
    else:
        data = (
            "`1000 x 2F`: 1,000 trajectories of 3 motions from `make_motions(3, "
            'n_points=1000, missing=0.4, missing_pattern="occlusion")`, F frames'
        )
    lines = [
        "# PowerFactorization as the sequence grows",
        "",
        f"Regenerate with `{command.strip()}`. One fit of "
        "`PowerFactorization(random_state=0)` per cell, each in a fresh "
        "process: wall seconds with the machine's default BLAS threads "
        "(in brackets with `OMP_NUM_THREADS=1`), CPU seconds, peak memory "
        "allocated during the fit (tracemalloc), RMS residual over the "
        f"observed entries, random starts run. {data}; `100 x 4000`: rank 5 "
        "plus noise, 10 % missing at random. 'als RMS excess': relative excess "
        "of ALS's RMS over the default's (0 where ALS reaches the same "
        "optimum); 'default / als CPU time' compares CPU seconds, steadier than "
        "wall seconds on a shared machine. Load average (1 min) when the run "
        f"started: {args.load:.1f} on {os.cpu_count()} cores.{skipped(rows)}",
        "",
        *markdown_table(header, rows),
        "",
    ]
    if thread_rows:
        lines += [
            "## One BLAS thread in the solvers, or the default pool",
            "",
            "Wall seconds of the default fit with the library's one-BLAS-thread "
            "limit (`LIMIT_BLAS_THREADS = True`, the default) and without it, "
            "under the machine's default BLAS threads.",
            "",
            *markdown_table(
                ["X", "one BLAS thread s", "default pool s", "pool / one thread"],
                thread_rows,
            ),
            "",
        ]
    if reference_rows:
        lines += [
            "## The previous default solver",
            "",
            f"The default of the checkout `{args.reference}` (dense variable "
            "projection) against this one, same data and seed, on the tracks and "
            "frames observed in at least 5 entries (the previous version refuses "
            "the others); 'relative cost difference': (new - old) / old squared "
            "residual.",
            "",
            *markdown_table(
                [
                    "X",
                    "previous RMS",
                    "new RMS",
                    "relative cost difference",
                    "previous s",
                    "new s",
                ],
                reference_rows,
            ),
            "",
        ]
    write_markdown(args.output, "\n".join(lines))
    print(f"written to {args.output}")


if __name__ == "__main__":
    main()
