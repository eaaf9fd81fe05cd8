"""Statistics of the data make_tracks draws, scene by scene.

Run from the project root::

    python benchmarks/describe_tracks.py [--seeds 10]

For each setting (the three scene presets, then longer sequences) and each
seed, draws ``make_tracks(..., random_state=seed)`` and reports, averaged over
the seeds: tracks, frames, motions, missing fraction, observed track lengths
(10th, 50th, 90th percentiles and mean, frames), the share of tracks seen in
1-2 frames, the background's share of the inlier tracks, the outliers' share,
how tracks end, and the perspective deviation of the noise-free tracks
from the affine model (one rank-4 subspace per motion), in pixels:

- on a complete block: for every motion, the best rank-4 fit of the frames
  where at least 90% of its tracks are in front of the camera and the tracks
  in front in all of them (projections need not be in the image there), as
  the relative Frobenius residual ``||W - W_4|| / ||W||`` and the RMS
  residual; median over motions, and the background's alone;
- on the observed entries, as an oracle sees them: the RMS residual over the
  observed entries of a rank-4 PowerFactorization (ALS, 3 starts) of each
  motion's tracks seen in 3 frames or more (shorter ones fit any rank-4
  subspace); median over motions, and the background's alone.

A line for Hopkins155 (the real data in ``../shared/data``, when present)
gives the complete-block residual of its tracks in pixels (with their noise),
for comparison with the "lab" scene. Writes
``benchmarks/results/tracks.md``.
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import time
import warnings
from pathlib import Path

import numpy as np
from _tables import write_markdown

from sklearn_gpca import PowerFactorization
from sklearn_gpca.datasets import load_hopkins155, make_tracks

SETTINGS = [
    ("driving (KT3DMoSeg)", {"scene": "driving"}),
    ("handheld (FBMS-59)", {"scene": "handheld"}),
    ("lab (Hopkins155)", {"scene": "lab"}),
    ("driving, 50 frames", {"scene": "driving", "n_frames": 50}),
    (
        "handheld, 20 frames, 40% missing",
        {"scene": "handheld", "n_frames": 20, "missing": 0.4},
    ),
    (
        "handheld, 200 frames, 4 motions, mean lifetime 100",
        {"scene": "handheld", "n_frames": 200, "n_motions": 4, "mean_lifetime": 100},
    ),
    ("lab, 50 frames, 40% missing", {"scene": "lab", "n_frames": 50, "missing": 0.4}),
    (
        "driving, 100 frames at 30 Hz",
        {"scene": "driving", "n_frames": 100, "frame_rate": 30},
    ),
]


def rank4_deviation(W):
    """Relative and RMS residual (units of W) of the best rank-4 fit of W."""
    singular = np.linalg.svd(W, compute_uv=False)
    residual = np.sqrt(np.sum(singular[4:] ** 2))
    relative = residual / np.sqrt(np.sum(singular**2))
    return relative, residual / np.sqrt(W.size)


def observed_rank4_rms(W):
    """RMS residual over the observed entries of a rank-4 fit to them."""
    # Tracks of 1-2 frames fit any rank-4 subspace; the solver needs 4
    # observed entries per row and per column.
    W = W[np.sum(~np.isnan(W), axis=1) >= 6]
    W = W[:, np.sum(~np.isnan(W), axis=0) >= 4]
    W = W[np.sum(~np.isnan(W), axis=1) >= 4]
    if W.shape[0] < 8 or W.shape[1] < 8:
        return np.nan
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            model = PowerFactorization(
                4, whiten=False, solver="als", n_init=3, random_state=0
            ).fit(W)
        except ValueError:
            return np.nan
    return model.reconstruction_err_


def complete_block(W):
    """Frames where >= 90% of the tracks are defined, tracks defined in all."""
    defined = np.isfinite(W[:, 0::2])
    frames = defined.mean(axis=0) >= 0.9
    rows = defined[:, frames].all(axis=1)
    cols = np.repeat(frames, 2)
    return W[np.ix_(rows, cols)]


def describe(kwargs, seeds):
    rows = []
    for seed in range(seeds):
        start = time.perf_counter()
        X, y, info = make_tracks(
            random_state=seed, units="pixels", return_info=True, **kwargs
        )
        seconds = time.perf_counter() - start
        lengths = info.end - info.birth
        inliers = y >= 0
        deviations, observed_rms = [], []
        for k in np.unique(y[inliers]):
            W = complete_block(info.X_complete[y == k])
            if W.shape[0] >= 8 and W.shape[1] >= 8:
                deviations.append(rank4_deviation(W))
            observed_rms.append(observed_rank4_rms(info.X_clean[y == k]))
        reasons = {
            r: np.mean(info.end_reason == r)
            for r in ("lifetime", "left_view", "occluded", "sequence_end")
        }
        rows.append(
            {
                "tracks": X.shape[0],
                "frames": X.shape[1] // 2,
                "motions": int(y.max()) + 1,
                "missing": np.isnan(X).mean(),
                "p10": np.percentile(lengths, 10),
                "p50": np.percentile(lengths, 50),
                "p90": np.percentile(lengths, 90),
                "mean": lengths.mean(),
                "short": np.mean(lengths <= 2),
                "background": np.mean(y[inliers] == 0),
                "outliers": np.mean(~inliers),
                **reasons,
                "relative": np.median([d[0] for d in deviations]),
                "rms_px": np.median([d[1] for d in deviations]),
                "background_px": deviations[0][1] if deviations else np.nan,
                "observed_px": np.nanmedian(observed_rms),
                "background_observed_px": observed_rms[0],
                "seconds": seconds,
            }
        )
    return {key: float(np.nanmean([r[key] for r in rows])) for key in rows[0]}


def hopkins_deviation(data_home):
    try:
        sequences = load_hopkins155(data_home)
    except (FileNotFoundError, ValueError):
        return None
    relative, rms, background = [], [], []
    for seq in sequences:
        labels = np.asarray(seq.y)
        counts = np.bincount(labels)
        background.append(counts.max() / counts.sum())
        for k in np.unique(labels):
            W = np.asarray(seq.X_pixels)[labels == k]
            if W.shape[0] >= 8:
                r, p = rank4_deviation(W)
                relative.append(r)
                rms.append(p)
    return {
        "sequences": len(sequences),
        "relative": float(np.median(relative)),
        "rms_px": float(np.median(rms)),
        "background": float(np.median(background)),
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=10)
    parser.add_argument(
        "--output", type=Path, default=Path("benchmarks/results/tracks.md")
    )
    parser.add_argument("--data-home", default="../shared/data")
    args = parser.parse_args()

    lines = [
        "# What `make_tracks` draws",
        "",
        f"`python benchmarks/describe_tracks.py --seeds {args.seeds}`: every "
        f"figure is the mean over seeds 0-{args.seeds - 1} of one draw per seed, "
        "with the other parameters at the scene's defaults. Lengths are the "
        "observed frames of a track (end - birth); 'short' is the share of "
        "tracks seen in 1-2 frames; 'background' is the background's share of "
        "the inlier tracks. The rank-4 deviation columns measure the noise-free "
        "tracks' departure from one rank-4 subspace per motion, in pixels (see "
        "the script's docstring): on a complete block (relative Frobenius "
        "residual, RMS over motions (median), RMS of the background) and on the "
        "observed entries (RMS over motions (median), background).",
        "",
        "| setting | tracks | frames | motions | missing | length p10 / p50 / p90"
        " / mean | short | background | outliers | ends: lifetime / view /"
        " occluded / end | rank-4, complete block: rel. / px / background px |"
        " rank-4, observed: px / background px | s per draw |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for name, kwargs in SETTINGS:
        s = describe(kwargs, args.seeds)
        lines.append(
            f"| {name} | {s['tracks']:.0f} | {s['frames']:.0f} | "
            f"{s['motions']:.0f} | {s['missing']:.3f} | {s['p10']:.1f} / "
            f"{s['p50']:.1f} / {s['p90']:.1f} / {s['mean']:.1f} | "
            f"{s['short']:.3f} | {s['background']:.3f} | {s['outliers']:.3f} | "
            f"{s['lifetime']:.2f} / {s['left_view']:.2f} / {s['occluded']:.2f} /"
            f" {s['sequence_end']:.2f} | {s['relative']:.1e} / {s['rms_px']:.2f}"
            f" / {s['background_px']:.2f} | {s['observed_px']:.2f} / "
            f"{s['background_observed_px']:.2f} | {s['seconds']:.2f} |"
        )
        print(lines[-1], flush=True)
    hopkins = hopkins_deviation(args.data_home)
    if hopkins is not None:
        lines += [
            "",
            f"Hopkins155, measured on the {hopkins['sequences']} sequences of "
            "`../shared/data` (real tracks, with their noise): rank-4 deviation "
            f"per motion (median) {hopkins['relative']:.1e} relative, "
            f"{hopkins['rms_px']:.2f} px RMS; the largest group's share of the "
            f"tracks (median) {hopkins['background']:.3f}.",
        ]
        print(lines[-1])
    write_markdown(args.output, "\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
