"""Wall time of segment_motions: parallel jobs, and against another revision.

Run from the project root (about 10 minutes for one seed)::

    python benchmarks/bench_segment_speed.py --seeds 0 \
        --against /tmp/previous --out benchmarks/results/segment_speed.md

where ``/tmp/previous`` is a checkout of the revision to compare with, e.g.
``git worktree add /tmp/previous 942d4af``. For each draw of the seven
``make_tracks`` settings of ``bench_segment.py`` (or, with ``--dense``, of
the dense settings below: more tracks of two of them, above the density
where ``segment_motions`` also segments subsamples; with ``--long``, of the
200-frame hand-held settings below; outlier tracks removed, as there), times
``segment_motions(X, n, random_state=0)``:

- with ``n_jobs=1`` (the default) and with ``--jobs`` processes, in this
  process, one after the other, and checks that the labels are the same (the
  process pool is started once, by a small call before the first draw, as it
  is once per session for a user);
- with ``--against``: the same call of the other revision, in a child
  process started just before (the two versions of the package cannot share
  one process), with whether its labels are the same.

Ratios divide by the time measured beside them on the same draw, so that a
busy machine slows both. The BLAS threads are the machine's default unless
``OMP_NUM_THREADS`` is set; the page records it.
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import datetime
import os
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
from _tables import write_markdown
from bench_segment import TRACK_SETTINGS

from sklearn_gpca import segment_motions
from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.metrics import misclassification_rate

#: The child process of ``--against``: times one call, saves its labels.
_CHILD = """
import sys, time, warnings
import numpy as np
from sklearn_gpca import segment_motions
warnings.simplefilter("ignore")
data = np.load(sys.argv[1])
start = time.perf_counter()
labels = segment_motions(data["X"], int(data["n"]), random_state=0)
seconds = time.perf_counter() - start
np.savez(sys.argv[2], labels=labels, seconds=seconds)
"""


#: Dense tracks (more than 600 seen per frame on average): 4 and 2 times the
#: tracks of two ``TRACK_SETTINGS`` (``benchmarks/check_track_count.py``).
DENSE_SETTINGS = {
    "driving, 3 motions, 4 times the tracks": {"scene": "driving", "n_tracks": 2000},
    "handheld, 3 motions, 40 frames, 2 times the tracks": {
        **TRACK_SETTINGS["handheld, 3 motions, 40 frames"],
        "n_tracks": 1600,
    },
}

#: Long sequences: 200 frames of the hand-held scene (half the entries
#: missing: tracks seen in 100 frames on average), at 400 and 1,000 tracks
#: seen per frame (the second above the density of ``DENSE_SETTINGS``).
LONG_SETTINGS = {
    f"handheld, 3 motions, 200 frames, {n_tracks} tracks": {
        "scene": "handheld",
        "n_frames": 200,
        "n_tracks": n_tracks,
    }
    for n_tracks in (800, 2000)
}


def _draw(setting, seed):
    settings = {**TRACK_SETTINGS, **DENSE_SETTINGS, **LONG_SETTINGS}
    X, y = make_tracks(random_state=seed, **settings[setting])[:2]
    keep = y >= 0
    return X[keep], y[keep]


def _timed(X, n, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        start = time.perf_counter()
        labels = segment_motions(X, n, random_state=0, **kwargs)
        return labels, time.perf_counter() - start


def _against(root, X, n):
    """Labels and seconds of the other revision's call, in a child process."""
    with tempfile.TemporaryDirectory() as folder:
        data, result = Path(folder) / "draw.npz", Path(folder) / "result.npz"
        np.savez(data, X=X, n=n)
        env = dict(os.environ, PYTHONPATH=str(root))
        subprocess.run(
            [sys.executable, "-c", _CHILD, str(data), str(result)],
            env=env,
            check=True,
            cwd=folder,
        )
        out = np.load(result)
        return out["labels"], float(out["seconds"])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[0])
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--against", default=None, help="checkout of a revision")
    which = parser.add_mutually_exclusive_group()
    which.add_argument("--dense", action="store_true", help="the dense settings")
    which.add_argument("--long", action="store_true", help="the 200-frame settings")
    parser.add_argument("--out", default=None, help="also write the page here")
    args = parser.parse_args(argv)
    against = None if args.against is None else Path(args.against).resolve()
    if against is not None and not (against / "sklearn_gpca").is_dir():
        parser.error(f"--against {args.against} holds no sklearn_gpca package")
    # the process pool, started once
    X, y = _draw("lab, 2 motions, 30 frames, 40% missing", 0)
    _timed(X[:60], 2, n_jobs=args.jobs)
    header = ["setting", "seed", "tracks", "frames", "error %", "1 job s"]
    header += [f"{args.jobs} jobs s", "1 job / jobs", "same labels"]
    if against is not None:
        header += ["other revision s", "other / this (1 job)", "same as other"]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    print(*lines, sep="\n", flush=True)
    serial, parallel, other = [], [], []
    settings = TRACK_SETTINGS
    settings = DENSE_SETTINGS if args.dense else settings
    settings = LONG_SETTINGS if args.long else settings
    for setting in settings:
        for seed in args.seeds:
            X, y = _draw(setting, seed)
            n = np.unique(y).size
            cells = [setting, str(seed), str(X.shape[0]), str(X.shape[1] // 2)]
            if against is not None:
                other_labels, other_s = _against(against, X, n)
            one, one_s = _timed(X, n)
            many, many_s = _timed(X, n, n_jobs=args.jobs)
            serial.append(one_s)
            parallel.append(many_s)
            cells += [f"{100 * misclassification_rate(y, one):.2f}", f"{one_s:.1f}"]
            cells += [f"{many_s:.1f}", f"{one_s / many_s:.2f}"]
            cells += ["yes" if np.array_equal(one, many) else "**no**"]
            if against is not None:
                other.append(other_s)
                cells += [f"{other_s:.1f}", f"{other_s / one_s:.2f}"]
                cells += ["yes" if np.array_equal(one, other_labels) else "no"]
            lines.append("| " + " | ".join(cells) + " |")
            print(lines[-1], flush=True)
    total = ["all draws (sum of seconds)", "", "", "", "", f"{sum(serial):.1f}"]
    total += [f"{sum(parallel):.1f}", f"{sum(serial) / sum(parallel):.2f}", ""]
    if against is not None:
        total += [f"{sum(other):.1f}", f"{sum(other) / sum(serial):.2f}", ""]
    lines.append("| " + " | ".join(total) + " |")
    print(lines[-1])
    threads = os.environ.get("OMP_NUM_THREADS", "the default")
    stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%d %b %Y %H:%M")
    command = "python benchmarks/bench_segment_speed.py --seeds " + " ".join(
        str(s) for s in args.seeds
    )
    command += f" --jobs {args.jobs}" if args.jobs != 2 else ""
    command += " --dense" if args.dense else ""
    command += " --long" if args.long else ""
    command += f" --against {args.against}" if args.against else ""
    command += f" --out {args.out}" if args.out else ""
    page = (
        "# segment_motions: wall time with parallel jobs and against another "
        "revision\n\n"
        f"`{command}`, {stamp} UTC, {os.cpu_count()} cores, BLAS threads: "
        f"{threads}. Wall seconds of `segment_motions(X, n, random_state=0)` "
        "on one draw of each `make_tracks` setting (outlier tracks removed); "
        "the ratios divide by the time measured beside them on the same draw "
        "(see the script's docstring).\n\n" + "\n".join(lines) + "\n"
    )
    if args.out:
        write_markdown(args.out, page)


if __name__ == "__main__":
    main()
