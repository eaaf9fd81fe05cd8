"""Command line: ``python -m sklearn_gpca`` (or ``sklearn-gpca``)
``{demo,segment}``.

``demo`` segments synthetic trajectories; ``segment`` reads trajectories from a
``.npz``, ``.csv``, Hopkins155-style ``.mat`` or Brox & Malik ``.dat`` file,
segments them and writes
the labels. The Hopkins155 benchmark is ``benchmarks/bench_hopkins155.py``,
outside the package.

Exit status: 0 on success; 2, with a one-line message on stderr, for a mistake
in the user's input (a bad file or argument, a value the library's checks
reject); 130, with one line, on Ctrl-C. Any other exception is a bug of the
library: it is not disguised as a usage error but ends with its traceback
(status 1). Warnings of the library (``UserWarning`` and its subclasses, such
as ``ConvergenceWarning``) are shown on stderr, one line each.
"""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import contextlib
import linecache
import sys
import time
import warnings
from pathlib import Path

import numpy as np

from sklearn_gpca._trajectory_files import (
    CSV_RULES,
    UsageError,
    read_trajectories,
    same_file,
    write_atomically,
)

__all__ = ["UsageError", "build_parser", "main", "read_trajectories"]

#: Largest number of motions tried by ``--n-motions auto``.
AUTO_MAX_MOTIONS = 5

#: Exit status after Ctrl-C (128 + SIGINT), as shells report it.
INTERRUPTED = 130

#: Share of missing entries from which ``segment`` with the default
#: ``--method pipeline`` suggests ``--method tracks``: the low end of the
#: tracker output ``MotionSegmentation`` is built for (30-70 % missing), where
#: the pipeline errs several times more (``benchmarks/results/segment_tracks.md``).
TRACKS_HINT_MISSING = 0.3


def _prog():
    """``sklearn-gpca`` when run as the installed script, else ``python -m``."""
    if Path(sys.argv[0]).name.startswith("sklearn-gpca"):
        return "sklearn-gpca"
    return "python -m sklearn_gpca"


def _print_rows(rows):
    width = max(len(name) for name, _ in rows)
    for name, value in rows:
        print(f"  {name:<{width}}  {value}")


# ---------------------------------------------------------------------------
# Errors and warnings of the library


def _raised_by_a_check(exc):
    """Whether ``exc`` comes from a ``raise`` statement of this library or of
    scikit-learn, i.e. a check of the input, rather than from numpy or scipy
    failing inside a computation (a bug)."""
    tb = exc.__traceback__
    if tb is None:
        return False
    while tb.tb_next is not None:
        tb = tb.tb_next
    module = tb.tb_frame.f_globals.get("__name__", "")
    if module.split(".")[0] not in ("sklearn_gpca", "sklearn"):
        return False
    line = linecache.getline(tb.tb_frame.f_code.co_filename, tb.tb_lineno)
    return line.lstrip().startswith("raise")


@contextlib.contextmanager
def _input_errors(prefix=""):
    """Turn the ``ValueError`` of a check of the input into a UsageError."""
    try:
        yield
    except UsageError:
        raise
    except ValueError as exc:
        if not _raised_by_a_check(exc):
            raise
        message = " ".join(str(exc).split())  # one line
        raise UsageError(f"{prefix}{message}") from exc


@contextlib.contextmanager
def _shown_warnings(prog):
    """Show each distinct ``UserWarning`` (and subclass) on one stderr line."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            yield
        finally:
            seen = set()
            for w in caught:
                if not issubclass(w.category, UserWarning):
                    continue
                message = " ".join(str(w.message).split())
                if (w.category, message) in seen:
                    continue
                seen.add((w.category, message))
                print(
                    f"{prog}: warning: {message} ({w.category.__name__})",
                    file=sys.stderr,
                )


# ---------------------------------------------------------------------------
# demo


def _demo(args):
    from sklearn.pipeline import make_pipeline

    from sklearn_gpca import GPCAClustering, PowerFactorization
    from sklearn_gpca.datasets import make_motions
    from sklearn_gpca.metrics import misclassification_rate

    with _input_errors():
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
# segment


def _pipeline(n_motions, rank, random_state, shape):
    """``PowerFactorization(rank)`` then ``GPCAClustering(n_motions)``; with
    ``n_motions="auto"`` the counting pipeline of ``GPCAClustering``: the
    unwhitened projection of rank ``4 * AUTO_MAX_MOTIONS`` (at most the number
    of trajectories and of coordinates), segmented in its leading ``rank``
    directions, where the trajectory coding length chooses among ``1 ..
    AUTO_MAX_MOTIONS`` motions."""
    from sklearn.pipeline import make_pipeline

    from sklearn_gpca import GPCAClustering, PowerFactorization

    if n_motions != "auto":
        return make_pipeline(
            PowerFactorization(rank, random_state=random_state),
            GPCAClustering(n_motions, random_state=random_state),
        )
    wide = max(min(4 * AUTO_MAX_MOTIONS, *shape), rank)
    return make_pipeline(
        PowerFactorization(wide, whiten=False, random_state=random_state),
        GPCAClustering(
            "auto",
            segmentation_dim=rank,
            max_clusters=AUTO_MAX_MOTIONS,
            random_state=random_state,
        ),
    )


def _estimator(args, shape):
    """The estimator ``--method`` names, with the options given."""
    from sklearn_gpca import MotionSegmentation, PerspectiveClustering

    if args.method == "pipeline":
        return _pipeline(args.n_motions, args.rank, args.seed, shape)
    if args.method == "tracks":
        return MotionSegmentation(
            args.n_motions,
            outlier_threshold=args.outlier_threshold,
            n_init=1 if args.n_init is None else args.n_init,
            random_state=args.seed,
            n_jobs=args.jobs,
        )
    return PerspectiveClustering(args.n_motions, random_state=args.seed)


def _check_method_options(args):
    """Refuse options that the chosen ``--method`` does not use."""
    if args.jobs is not None and args.method != "tracks":
        raise UsageError("--jobs needs --method tracks")
    if args.n_init is not None and args.method != "tracks":
        raise UsageError("--n-init needs --method tracks")
    if args.method == "pipeline":
        if args.outlier_threshold is not None:
            raise UsageError("--outlier-threshold needs --method tracks")
        return
    if args.rank is not None:
        raise UsageError(f"--rank applies to --method pipeline, not {args.method}")
    if args.n_motions == "auto":
        raise UsageError(
            f"--n-motions auto needs --method pipeline; give N with {args.method}"
        )
    if args.method == "perspective" and args.outlier_threshold is not None:
        raise UsageError("--outlier-threshold needs --method tracks")


def _fit(X, args):
    """Fitted estimator (pipeline, or one estimator) and labels."""
    estimator = _estimator(args, X.shape)
    return estimator, estimator.fit_predict(X)


def _described(estimator, n_motions):
    """The estimator as fitted, as Python code."""
    if not hasattr(estimator, "steps"):
        threshold = getattr(estimator, "outlier_threshold", None)
        options = f"n_clusters={n_motions}"
        if threshold is not None:
            options += f", outlier_threshold={threshold:g}"
        return f"{type(estimator).__name__}({options})"
    projection, clustering = estimator[0], estimator[-1]
    rank = f"n_components={projection.n_components}"
    if not projection.whiten:
        rank += ", whiten=False"
    segmented = f"n_clusters={n_motions}"
    if clustering.segmentation_dim is not None:
        segmented += f", segmentation_dim={clustering.segmentation_dim}"
    return f"make_pipeline(PowerFactorization({rank}), GPCAClustering({segmented}))"


def _check_destination(path, option, source, force):
    """Refuse to write over the input, or over a file without ``--force``."""
    path = Path(path)
    if same_file(path, source):
        raise UsageError(f"{option} {path} is the input file; it is never overwritten")
    if path.is_dir():
        raise UsageError(f"{option} {path} is a directory")
    if not path.parent.is_dir():
        raise UsageError(f"{option} {path}: no such directory {path.parent}")
    if path.exists() and not force:
        raise UsageError(f"{option} {path} exists; add --force to overwrite it")


def _sizes(labels, n_motions):
    """``"26 35 19 0"``: the size of every motion, empty ones included."""
    inliers = labels[labels >= 0]
    text = " ".join(str(c) for c in np.bincount(inliers, minlength=n_motions))
    n_noise = int(np.sum(labels < 0))
    return text + (f" (+ {n_noise} outliers, label -1)" if n_noise else "")


def _segment(args):
    from sklearn_gpca.metrics import misclassification_rate

    _check_method_options(args)
    X, y = read_trajectories(args.file)
    n_points, n_frames = X.shape[0], X.shape[1] // 2
    if args.rank is None:
        args.rank = 5
    elif args.rank > X.shape[1]:
        raise UsageError(
            f"--rank {args.rank} exceeds 2 * frames = {X.shape[1]} for {args.file}"
        )
    destinations = [("--output", args.output), ("--plot", args.plot)]
    destinations = [(option, path) for option, path in destinations if path]
    for option, path in destinations:
        _check_destination(path, option, args.file, args.force)
    if args.output and args.plot and Path(args.output) == Path(args.plot):
        raise UsageError("--output and --plot name the same file")

    start = time.perf_counter()
    with _shown_warnings(args.prog), _input_errors(f"{args.file}: "):
        estimator, labels = _fit(X, args)
    seconds = time.perf_counter() - start
    n_motions = (
        estimator[-1].n_clusters_ if args.method == "pipeline" else args.n_motions
    )

    if args.output is not None:
        try:
            write_atomically(args.output, lambda tmp: np.savetxt(tmp, labels, fmt="%d"))
        except OSError as exc:
            raise UsageError(f"cannot write {args.output}: {exc}") from exc
    if args.plot is not None:
        _plot_segmentation(X, labels, y, args.plot)

    print(f"Segmenting {args.file}\n  {_described(estimator, n_motions)}\n")
    motions = f"{n_motions}"
    if args.n_motions == "auto":
        bits = estimator[-1].n_clusters_costs_
        chosen = ", ".join(
            f"{n}: {b:.0f}" for n, b in enumerate(bits, start=1) if np.isfinite(b)
        )
        motions += f" (auto, coding length in bits: {chosen})"
    missing = float(np.isnan(X).mean())
    rows = [
        ("trajectories", f"{n_points}"),
        ("frames", f"{n_frames}"),
        ("missing entries", f"{100 * missing:.1f} %"),
        ("motions", motions),
        ("sizes", _sizes(labels, n_motions)),
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
    if args.method == "pipeline" and missing >= TRACKS_HINT_MISSING:
        print(
            f"{args.prog}: note: {100 * missing:.0f} % of the entries are missing; "
            "for a tracker's output (tracks born and lost) --method tracks "
            "segments better (benchmarks/results/segment_tracks.md)",
            file=sys.stderr,
        )
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
        write_atomically(
            path, lambda tmp: display.figure_.savefig(tmp, dpi=120, bbox_inches="tight")
        )
    except (OSError, ValueError) as exc:
        raise UsageError(f"cannot write {path}: {exc}") from exc
    finally:
        plt.close(display.figure_)


# ---------------------------------------------------------------------------
# Arguments


class _Parser(argparse.ArgumentParser):
    """An ArgumentParser whose errors take one line (and exit status 2)."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message} (see --help)\n")


def _n_jobs(value):
    """A joblib ``n_jobs``: a non-zero integer (-1: every core)."""
    try:
        n = int(value)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be an integer, got {value!r}") from None
    if n == 0:
        raise argparse.ArgumentTypeError("must not be 0 (-1 runs on every core)")
    return n


def _int_at_least(least):
    def parse(value):
        try:
            n = int(value)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"must be an integer, got {value!r}"
            ) from None
        if n < least:
            raise argparse.ArgumentTypeError(f"must be at least {least}, got {n}")
        return n

    parse.__name__ = f"integer >= {least}"
    return parse


_positive_int = _int_at_least(1)


def _n_motions(value):
    return value if value == "auto" else _positive_int(value)


def _float_in(low, high=None, *, closed_high=False):
    if high is None:
        interval = f"[{low:g}, inf)"
    else:
        interval = f"[{low:g}, {high:g}{']' if closed_high else ')'}"

    def parse(value):
        try:
            x = float(value)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"must be a number, got {value!r}"
            ) from None
        too_high = high is not None and (x > high if closed_high else x >= high)
        if not x >= low or too_high:
            raise argparse.ArgumentTypeError(f"must lie in {interval}, got {value}")
        return x

    parse.__name__ = f"number in {interval}"
    return parse


def build_parser(prog=None):
    """The argument parser of the command line."""
    prog = _prog() if prog is None else prog
    parser = _Parser(
        prog=prog,
        description="Motion segmentation with PowerFactorization and GPCA.",
    )
    commands = parser.add_subparsers(dest="command", required=True)
    demo = commands.add_parser(
        "demo", help="segment synthetic trajectories with missing entries"
    )
    demo.add_argument("--n-motions", type=_positive_int, default=3)
    demo.add_argument("--n-points", type=_positive_int, default=100, help="per motion")
    demo.add_argument("--n-frames", type=_int_at_least(3), default=10)
    demo.add_argument("--noise", type=_float_in(0.0), default=1.0, help="pixels")
    demo.add_argument(
        "--missing", type=_float_in(0.0, 1.0), default=0.2, help="fraction in [0, 1)"
    )
    demo.add_argument(
        "--missing-pattern", choices=["random", "occlusion"], default="occlusion"
    )
    demo.add_argument("--random-state", type=int, default=0)
    demo.set_defaults(run=_demo)

    segment = commands.add_parser(
        "segment",
        help="segment the trajectories of a .npz, .csv, .mat or .dat file",
        description=(
            "Segment trajectories into rigid motions with make_pipeline("
            "PowerFactorization(R), GPCAClustering(N)), or the estimator "
            "--method names. FILE is a .npz (array X "
            "of shape (points, 2 * frames), optional labels y), a .csv, a "
            "Hopkins155-style .mat (field x, else y, of shape 3 x points x "
            "frames; optional labels s) or a track file of Brox & Malik's "
            "tracker (.dat: frames, tracks, then per track its label, its "
            "length and one 'x y frame' per point, frames from 0; labels "
            f"count as ground truth when they differ). {CSV_RULES} The labels "
            "file has one "
            "line per trajectory, in the order of FILE. Files are written "
            "whole or not at all (a temporary file, then a rename); FILE is "
            "never overwritten, and another existing file only with --force."
        ),
    )
    segment.add_argument("file", metavar="FILE", help="trajectory file")
    segment.add_argument(
        "--n-motions",
        type=_n_motions,
        required=True,
        metavar="N",
        help="number of motions, or 'auto' to choose among 1..5 by "
        "GPCAClustering(n_clusters='auto') (shortest coding length of the "
        "trajectories in an unwhitened projection of rank 20, segmented in its "
        "leading R directions)",
    )
    segment.add_argument(
        "--method",
        choices=("pipeline", "tracks", "perspective"),
        default="pipeline",
        help="pipeline (default): make_pipeline(PowerFactorization(R), "
        "GPCAClustering(N)), for trajectories with few missing entries; "
        "tracks: MotionSegmentation(N), for a tracker's output (tracks born "
        "and lost, 30-70%% missing, tracks of 1-2 frames); perspective: "
        "PerspectiveClustering(N), for scenes with strong perspective",
    )
    segment.add_argument(
        "--rank",
        type=_positive_int,
        default=None,
        metavar="R",
        help="dimension of the projection of --method pipeline (default: 5, as "
        "in the paper)",
    )
    segment.add_argument(
        "--outlier-threshold",
        type=_float_in(0.0, 1.0),
        default=None,
        metavar="P",
        help="with --method tracks: label -1 the tracks that fit no motion, at "
        "false-alarm probability P per track (e.g. 0.001)",
    )
    segment.add_argument(
        "--n-init",
        type=_positive_int,
        default=None,
        metavar="K",
        help="with --method tracks: run the segmentation with K random states "
        "and keep the run its consistency rule judges best (K times the time; "
        "default 1)",
    )
    segment.add_argument(
        "--jobs",
        type=_n_jobs,
        default=None,
        metavar="J",
        help="with --method tracks: processes that refine and judge the "
        "candidate segmentations (-1: every core); the labels do not depend "
        "on it",
    )
    segment.add_argument(
        "--output", metavar="LABELS", help="write one label per line to this file"
    )
    segment.add_argument(
        "--plot", metavar="PNG", help="draw the segmented trajectories to this image"
    )
    segment.add_argument(
        "--force",
        action="store_true",
        help="overwrite an existing --output or --plot file (never FILE itself)",
    )
    segment.add_argument("--seed", type=int, default=0, help="random_state")
    segment.set_defaults(run=_segment)

    return parser


def main(argv=None):
    """Run the command line; return the exit status."""
    prog = _prog()
    argv = sys.argv[1:] if argv is None else list(argv)
    try:
        args = build_parser(prog).parse_args(argv)
        args.prog = prog
        try:
            return args.run(args)
        except UsageError as exc:
            print(f"{prog} {args.command}: error: {exc}", file=sys.stderr)
            return 2
    except KeyboardInterrupt:
        print(f"\n{prog}: interrupted", file=sys.stderr)
        return INTERRUPTED
