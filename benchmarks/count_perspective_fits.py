"""Every perspective fit of one ``segment_motions`` call: how many, and their time.

Run from the project root, for the installed package or another revision's
(``PYTHONPATH`` puts a copy first), with the default BLAS threads as users
run it, and with ``OMP_NUM_THREADS=1`` for the figure beside it (the fits'
share is clearer without the threads' noise)::

    python benchmarks/count_perspective_fits.py
    OMP_NUM_THREADS=1 python benchmarks/count_perspective_fits.py
    mkdir /tmp/old && git archive REV sklearn_gpca | tar -x -C /tmp/old
    PYTHONPATH=/tmp/old python benchmarks/count_perspective_fits.py

Wraps ``fit_projective_motion`` where the refinement, the consensus cameras
and the selection call it, and prints, per caller and per kind (*scratch*:
no start, the sequential fit; *warm*: from given cameras), the number of
fits and their seconds, then the call's wall time, on one draw of a setting
of ``bench_segment_speed.py`` (``--setting``, by default its 200-frame
hand-held draw of 800 tracks, 776 once the outlier tracks are removed; seed
``--seed``). Prints a table; writes nothing.
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import collections
import time
import traceback
import warnings

import numpy as np
from bench_segment_speed import _draw

import sklearn_gpca._model_consistency as consistency_module
import sklearn_gpca._projective_motion as projective_module
import sklearn_gpca._refine_observed as refine_module
import sklearn_gpca._segment as segment_module


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--setting", default="handheld, 3 motions, 200 frames, 800 tracks"
    )
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    fit = projective_module.fit_projective_motion
    fits = collections.defaultdict(lambda: [0, 0.0])

    def timed(X0, mask, *, cameras=None):
        clock = time.perf_counter()
        result = fit(X0, mask, cameras=cameras)
        # the function that called the fit (not a comprehension inside it)
        stack = traceback.extract_stack(limit=4)[:-1]
        caller = [frame.name for frame in stack if not frame.name.startswith("<")][-1]
        entry = fits[(caller, "scratch" if cameras is None else "warm")]
        entry[0] += 1
        entry[1] += time.perf_counter() - clock
        return result

    for module in (refine_module, segment_module, consistency_module):
        module.fit_projective_motion = timed
    X, y = _draw(args.setting, args.seed)
    clock = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        segment_module.segment_motions(X, np.unique(y).size, random_state=0)
    wall = time.perf_counter() - clock
    print(f"package: {projective_module.__file__}")
    print(f"{args.setting}, seed {args.seed}: {X.shape[0]} tracks")
    print("| caller | kind | fits | seconds |\n|---|---|---|---|")
    for (caller, kind), (count, seconds) in sorted(fits.items()):
        print(f"| {caller} | {kind} | {count} | {seconds:.1f} |")
    print(f"| segment_motions (wall) | | | {wall:.1f} |")


if __name__ == "__main__":
    main()
