"""Command line: ``python -m sklearn_gpca {demo,segment}``.

``demo`` segments synthetic trajectories; ``segment`` reads trajectories from a
``.npz``, ``.csv`` or Hopkins155-style ``.mat`` file, segments them and writes
the labels. Mistakes in the input (missing file, unknown format, wrong shape)
end with a one-line message on stderr and exit status 2. The Hopkins155
benchmark is ``benchmarks/bench_hopkins155.py``, outside the package.
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import csv
import sys
import time
import warnings
from pathlib import Path

import numpy as np

#: Largest number of motions tried by ``--n-motions auto``.
AUTO_MAX_MOTIONS = 5

#: Least number of frames for a trajectory file.
MIN_FRAMES = 3

FORMATS = (".npz", ".csv", ".mat")


class UsageError(Exception):
    """A mistake in the user's input: reported on one line, exit status 2."""


def _print_rows(rows):
    width = max(len(name) for name, _ in rows)
    for name, value in rows:
        print(f"  {name:<{width}}  {value}")


def _demo(args):
    from sklearn.pipeline import make_pipeline

    from sklearn_gpca import GPCAClustering, PowerFactorization
    from sklearn_gpca.datasets import make_motions
    from sklearn_gpca.metrics import misclassification_rate

    X, y = make_motions(
        n_motions=args.n_motions,
        n_points=[args.n_points] * args.n_motions,
        n_frames=args.n_frames,
        noise=args.noise,
        missing=args.missing,
        missing_pattern=args.missing_pattern,
        random_state=args.random_state,
    )
    pipeline = make_pipeline(
        PowerFactorization(random_state=args.random_state),
        GPCAClustering(args.n_motions, random_state=args.random_state),
    )
    start = time.perf_counter()
    labels = pipeline.fit_predict(X)
    seconds = time.perf_counter() - start
    error = misclassification_rate(y, labels)
    print(
        "Segmenting synthetic rigid motions under an affine camera\n"
        "  make_pipeline(PowerFactorization(), "
        f"GPCAClustering(n_clusters={args.n_motions}))\n"
    )
    _print_rows(
        [
            ("trajectories", f"{X.shape[0]}"),
            ("frames", f"{X.shape[1] // 2}"),
            ("motions", f"{args.n_motions}"),
            ("noise", f"{args.noise:g} px"),
            (
                "missing entries",
                f"{100 * np.isnan(X).mean():.1f} % ({args.missing_pattern})",
            ),
            ("misclassified", f"{100 * error:.2f} %"),
            ("time", f"{seconds:.3f} s"),
        ]
    )
    return 0


# ---------------------------------------------------------------------------
# Reading trajectory files


def _read_npz(path):
    try:
        with np.load(path, allow_pickle=False) as data:
            if "X" not in data:
                raise UsageError(
                    f"{path}: no array 'X' in the .npz file (found "
                    f"{', '.join(sorted(data.files)) or 'nothing'})"
                )
            X = data["X"]
            y = data.get("y", None)
    except (OSError, ValueError) as exc:
        raise UsageError(f"{path}: cannot read as .npz ({exc})") from exc
    return X, y


def _is_number(cell):
    cell = cell.strip()
    if not cell:
        return True
    try:
        float(cell)
    except ValueError:
        return False
    return True


def _read_csv(path):
    """One trajectory per row; empty cells or NaN are missing.

    An optional header row (any non-numeric cell) names the columns; a column
    named ``y`` or ``label`` then holds the ground truth.
    """
    try:
        with open(path, newline="") as f:
            rows = [row for row in csv.reader(f) if any(c.strip() for c in row)]
    except (OSError, UnicodeDecodeError) as exc:
        raise UsageError(f"{path}: cannot read as .csv ({exc})") from exc
    if not rows:
        raise UsageError(f"{path}: the file holds no trajectories")
    header = None
    if not all(_is_number(cell) for cell in rows[0]):
        header, rows = [c.strip() for c in rows[0]], rows[1:]
    widths = {len(row) for row in rows}
    if len(widths) > 1:
        raise UsageError(
            f"{path}: rows have different numbers of cells ({sorted(widths)})"
        )
    values = []
    for i, row in enumerate(rows, start=2 if header else 1):
        try:
            values.append([float(c) if c.strip() else np.nan for c in row])
        except ValueError as exc:
            raise UsageError(f"{path}, line {i}: {exc}") from exc
    X = np.array(values, dtype=np.float64).reshape(len(rows), -1)
    y = None
    if header is not None:
        names = [h.lower() for h in header]
        label = next((names.index(n) for n in ("y", "label") if n in names), None)
        if label is not None:
            y = X[:, label]
            if np.isnan(y).any():
                raise UsageError(f"{path}: column {header[label]!r} has empty cells")
            X = np.delete(X, label, axis=1)
    return X, y


def _read_mat(path):
    """Hopkins155 layout: ``x`` (else ``y``) of shape (3, P, F); ``s`` optional."""
    import scipy.io

    try:
        data = scipy.io.loadmat(path)
    except Exception as exc:  # scipy raises several types on bad files
        raise UsageError(f"{path}: cannot read as .mat ({exc})") from exc
    key = "x" if "x" in data else "y" if "y" in data else None
    if key is None:
        found = sorted(k for k in data if not k.startswith("__"))
        raise UsageError(
            f"{path}: no field 'x' or 'y' (3 x points x frames) in the .mat file "
            f"(found {', '.join(found) or 'nothing'})"
        )
    points = np.asarray(data[key], dtype=np.float64)
    if points.ndim != 3 or points.shape[0] not in (2, 3):
        raise UsageError(
            f"{path}: field {key!r} must have shape (3, points, frames), got "
            f"{points.shape}"
        )
    _, n_points, n_frames = points.shape
    X = points[:2].transpose(1, 2, 0).reshape(n_points, 2 * n_frames)
    y = None
    if "s" in data:
        y = np.asarray(data["s"]).ravel()
        if y.shape[0] != n_points:
            raise UsageError(
                f"{path}: field 's' holds {y.shape[0]} labels for {n_points} points"
            )
    return X, y


def read_trajectories(path):
    """Read ``X`` of shape (n_points, 2 * n_frames) and optional labels ``y``.

    Raises
    ------
    UsageError
        For a missing file, an unknown format or a wrong shape.
    """
    path = Path(path)
    if not path.exists():
        raise UsageError(f"{path}: no such file")
    if path.is_dir():
        raise UsageError(f"{path}: is a directory, not a trajectory file")
    suffix = path.suffix.lower()
    readers = {".npz": _read_npz, ".csv": _read_csv, ".mat": _read_mat}
    if suffix not in readers:
        raise UsageError(
            f"{path}: unknown format {suffix or '(no extension)'!r}; "
            f"expected one of {', '.join(FORMATS)}"
        )
    X, y = readers[suffix](path)
    X = np.asarray(X)
    if X.dtype.kind not in "biuf":
        raise UsageError(f"{path}: X must be numeric, got dtype {X.dtype}")
    X = X.astype(np.float64)
    if X.ndim != 2:
        raise UsageError(
            f"{path}: X must be 2-D (points x 2 * frames), got shape {X.shape}"
        )
    n_points, n_columns = X.shape
    if n_columns % 2:
        raise UsageError(
            f"{path}: X has an odd number of columns ({n_columns}); rows must be "
            "[x_1, y_1, ..., x_F, y_F]"
        )
    if n_columns // 2 < MIN_FRAMES:
        raise UsageError(
            f"{path}: {n_columns // 2} frames; at least {MIN_FRAMES} are needed"
        )
    if n_points < 2:
        raise UsageError(f"{path}: {n_points} trajectories; at least 2 are needed")
    if np.isinf(X).any():
        raise UsageError(f"{path}: X holds infinite values")
    if y is not None:
        y = np.asarray(y).ravel()
        if y.shape[0] != n_points:
            raise UsageError(
                f"{path}: y holds {y.shape[0]} labels for {n_points} points"
            )
    return X, y


# ---------------------------------------------------------------------------
# segment


def _n_motions(value):
    return value if value == "auto" else _positive_int(value)


def _positive_int(value):
    try:
        n = int(value)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"must be a positive integer, got {value!r}"
        ) from None
    if n < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {n}")
    return n


def _pipeline(n_motions, rank, random_state):
    from sklearn.pipeline import make_pipeline

    from sklearn_gpca import GPCAClustering, PowerFactorization

    return make_pipeline(
        PowerFactorization(rank, random_state=random_state),
        GPCAClustering(n_motions, random_state=random_state),
    )


def _fit(X, n_motions, rank, random_state):
    """Fitted pipeline and labels; ``n_motions="auto"`` lets GPCAClustering
    choose ``1 .. AUTO_MAX_MOTIONS`` by coding length."""
    pipeline = _pipeline(n_motions, rank, random_state)
    if n_motions == "auto":
        pipeline[-1].set_params(max_clusters=AUTO_MAX_MOTIONS)
    return pipeline, pipeline.fit_predict(X)


def _segment(args):
    from sklearn_gpca.metrics import misclassification_rate

    X, y = read_trajectories(args.file)
    n_points, n_frames = X.shape[0], X.shape[1] // 2
    if args.rank > X.shape[1]:
        raise UsageError(
            f"--rank {args.rank} exceeds 2 * frames = {X.shape[1]} for {args.file}"
        )
    start = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            pipeline, labels = _fit(X, args.n_motions, args.rank, args.seed)
    except ValueError as exc:
        raise UsageError(f"{args.file}: {exc}") from exc
    seconds = time.perf_counter() - start
    n_motions = pipeline[-1].n_clusters_

    if args.output is not None:
        try:
            np.savetxt(args.output, labels, fmt="%d")
        except OSError as exc:
            raise UsageError(f"cannot write {args.output}: {exc}") from exc
    if args.plot is not None:
        _plot_segmentation(X, labels, y, args.plot)

    print(
        f"Segmenting {args.file}\n"
        f"  make_pipeline(PowerFactorization(n_components={args.rank}), "
        f"GPCAClustering(n_clusters={n_motions}))\n"
    )
    motions = f"{n_motions}"
    if args.n_motions == "auto":
        bits = pipeline[-1].n_clusters_costs_
        chosen = ", ".join(
            f"{n}: {b:.0f}" for n, b in enumerate(bits, start=1) if np.isfinite(b)
        )
        motions += f" (auto, coding length in bits: {chosen})"
    rows = [
        ("trajectories", f"{n_points}"),
        ("frames", f"{n_frames}"),
        ("missing entries", f"{100 * np.isnan(X).mean():.1f} %"),
        ("motions", motions),
        ("sizes", " ".join(str(c) for c in np.bincount(labels, minlength=n_motions))),
    ]
    if y is not None:
        error = misclassification_rate(y, labels)
        rows.append(("misclassified", f"{100 * error:.2f} % (ground truth in file)"))
    rows.append(("time", f"{seconds:.3f} s"))
    if args.output is not None:
        rows.append(("labels", f"{args.output}"))
    if args.plot is not None:
        rows.append(("plot", f"{args.plot}"))
    _print_rows(rows)
    return 0


def _plot_segmentation(X, labels, y, path):
    try:
        import matplotlib

        matplotlib.use("Agg")
    except ImportError as exc:
        raise UsageError(
            "--plot requires matplotlib: pip install 'sklearn_gpca[plot]'"
        ) from exc
    import matplotlib.pyplot as plt

    from sklearn_gpca.plotting import TrajectoryDisplay

    display = TrajectoryDisplay.from_predictions(X, labels, y_true=y)
    try:
        display.figure_.savefig(path, dpi=120, bbox_inches="tight")
    except (OSError, ValueError) as exc:
        raise UsageError(f"cannot write {path}: {exc}") from exc
    finally:
        plt.close(display.figure_)


# ---------------------------------------------------------------------------


def build_parser():
    parser = argparse.ArgumentParser(
        prog="python -m sklearn_gpca",
        description="Motion segmentation with PowerFactorization and GPCA.",
    )
    commands = parser.add_subparsers(dest="command", required=True)
    demo = commands.add_parser(
        "demo", help="segment synthetic trajectories with missing entries"
    )
    demo.add_argument("--n-motions", type=int, default=3)
    demo.add_argument("--n-points", type=int, default=100, help="per motion")
    demo.add_argument("--n-frames", type=int, default=10)
    demo.add_argument("--noise", type=float, default=1.0, help="pixels")
    demo.add_argument("--missing", type=float, default=0.2, help="fraction")
    demo.add_argument(
        "--missing-pattern", choices=["random", "occlusion"], default="occlusion"
    )
    demo.add_argument("--random-state", type=int, default=0)
    demo.set_defaults(run=_demo)

    segment = commands.add_parser(
        "segment",
        help="segment the trajectories of a .npz, .csv or .mat file",
        description=(
            "Segment trajectories into rigid motions with make_pipeline("
            "PowerFactorization(R), GPCAClustering(N)). FILE is a .npz (array X "
            "of shape (points, 2 * frames), optional labels y), a .csv (one "
            "trajectory x_1, y_1, ..., x_F, y_F per row; empty cells or NaN for "
            "missing; an optional header row may name a label column y) or a "
            "Hopkins155-style .mat (field x, else y, of shape 3 x points x "
            "frames; optional labels s)."
        ),
    )
    segment.add_argument("file", metavar="FILE", help="trajectory file")
    segment.add_argument(
        "--n-motions",
        type=_n_motions,
        required=True,
        metavar="N",
        help="number of motions, or 'auto' to choose among 1..5 by "
        "GPCAClustering(n_clusters='auto') (shortest coding length)",
    )
    segment.add_argument(
        "--rank",
        type=_positive_int,
        default=5,
        metavar="R",
        help="dimension of the projection (default: 5, as in the paper)",
    )
    segment.add_argument(
        "--output", metavar="LABELS", help="write one label per line to this file"
    )
    segment.add_argument(
        "--plot", metavar="PNG", help="draw the segmented trajectories to this image"
    )
    segment.add_argument("--seed", type=int, default=0, help="random_state")
    segment.set_defaults(run=_segment)

    return parser


def main(argv=None):
    """Run the command line; return the exit status."""
    argv = sys.argv[1:] if argv is None else list(argv)
    args = build_parser().parse_args(argv)
    try:
        return args.run(args)
    except UsageError as exc:
        print(f"python -m sklearn_gpca {args.command}: error: {exc}", file=sys.stderr)
        return 2
