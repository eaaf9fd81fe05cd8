"""CPU time and peak traced memory of the fragment stages and the subspace votes.

On one ``make_tracks`` draw (default: 3000 tracks, 100 frames, scene "lab",
``random_state=0``) prepared as :func:`sklearn_gpca.segment_motions` prepares
it (tracks scaled to unit RMS, 20 co-observed neighbours, the local noise
level, the motion affinity), times

- the leading eigenvectors of the over-segmentation (``n_tracks // 40``
  fragments) and :func:`~sklearn_gpca._fragments.over_segment`;
- :func:`~sklearn_gpca._fragments.merge_fragments` down to 3 motions;
- :func:`~sklearn_gpca._view_hypotheses.preference_votes` of the subspace
  model (100 hypotheses per 4-frame window) and the residuals of 1000 subspace
  hypotheses on a 30-frame window.

Each stage is run once for ``time.process_time`` (CPU seconds, all threads)
and once under ``tracemalloc`` for the peak of the memory numpy allocates.
Prints a Markdown table.

Usage::

    python benchmarks/bench_fragment_stages.py --n-tracks 3000 --n-frames 100
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import time
import tracemalloc

import numpy as np
from sklearn.utils import check_random_state

from sklearn_gpca._fragments import (
    absorb_small_fragments,
    merge_fragments,
    over_segment,
)
from sklearn_gpca._hypotheses import local_noise_level
from sklearn_gpca._motion_graph import motion_affinity
from sklearn_gpca._observed_subspaces import observed_entries
from sklearn_gpca._segment import (
    GRAPH_NEIGHBORS,
    MIN_FRAGMENT_SIZE,
    TRACKS_PER_FRAGMENT,
)
from sklearn_gpca._spectral import leading_eigenvectors
from sklearn_gpca._track_neighbors import track_neighbors
from sklearn_gpca._view_hypotheses import (
    _subspace_residuals,
    local_samples,
    observed_frames,
    preference_votes,
)
from sklearn_gpca.datasets import make_tracks


def measure(stage):
    """CPU seconds of one run, and the peak traced MB of another."""
    start = time.process_time()
    stage()
    cpu = time.process_time() - start
    tracemalloc.start()
    stage()
    peak = tracemalloc.get_traced_memory()[1] / 2**20
    tracemalloc.stop()
    return cpu, peak


def main(n_tracks, n_frames, scene):
    X, _ = make_tracks(
        3, scene=scene, n_tracks=n_tracks, n_frames=n_frames, random_state=0
    )
    X0, mask = observed_entries(X)
    X0 = X0 / np.sqrt(np.mean(X0[mask] ** 2))
    neighbors = track_neighbors(X0, mask, min(GRAPH_NEIGHBORS, n_tracks - 1))
    noise = local_noise_level(X0, mask, neighbors, random_state=check_random_state(0))
    affinity = motion_affinity(X0, mask, neighbors)
    n_fragments = min(max(12, n_tracks // TRACKS_PER_FRAGMENT), n_tracks - 1)
    fragments = over_segment(
        affinity, n_fragments, random_state=np.random.RandomState(0)
    )
    fragments = absorb_small_fragments(affinity, fragments, MIN_FRAGMENT_SIZE)
    window = np.arange(min(30, n_frames))
    seen = np.flatnonzero(observed_frames(X)[:, window].all(axis=1))
    coords = X[np.ix_(seen, np.c_[2 * window, 2 * window + 1].ravel())]
    samples = local_samples(coords[:, :2], 4, 1000, 10, np.random.RandomState(0))
    stages = {
        f"leading eigenvectors ({n_fragments})": lambda: leading_eigenvectors(
            affinity, n_fragments, np.random.RandomState(0)
        ),
        "over_segment": lambda: over_segment(
            affinity, n_fragments, random_state=np.random.RandomState(0)
        ),
        f"merge_fragments ({fragments.max() + 1} to 3)": lambda: merge_fragments(
            X0, mask, fragments, 3, noise
        ),
        "preference_votes (subspace)": lambda: preference_votes(
            X,
            "subspace",
            n_hypotheses=100,
            top=0.05,
            gaps=(1,),
            window=4,
            n_neighbors=10,
            random_state=np.random.RandomState(0),
        ),
        f"subspace residuals ({seen.size} tracks, {window.size} frames, 1000 "
        "hypotheses)": lambda: _subspace_residuals(coords, samples),
    }
    print(
        f"make_tracks(3, scene={scene!r}, n_tracks={n_tracks}, "
        f"n_frames={n_frames}, random_state=0): {np.isnan(X).mean():.0%} missing\n"
    )
    print("| stage | CPU s | peak MB |\n| --- | ---: | ---: |")
    for name, stage in stages.items():
        cpu, peak = measure(stage)
        print(f"| {name} | {cpu:.2f} | {peak:.1f} |", flush=True)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-tracks", type=int, default=3000)
    parser.add_argument("--n-frames", type=int, default=100)
    parser.add_argument("--scene", default="lab")
    args = parser.parse_args()
    main(args.n_tracks, args.n_frames, args.scene)
