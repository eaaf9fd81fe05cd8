"""Command line: ``python -m sklearn_gpca demo``."""

# SPDX-License-Identifier: BSD-3-Clause

import argparse
import time

import numpy as np


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
    rows = [
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
    width = max(len(name) for name, _ in rows)
    for name, value in rows:
        print(f"  {name:<{width}}  {value}")
    return 0


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
    return parser


def main(argv=None):
    """Run the command line; return the exit status."""
    args = build_parser().parse_args(argv)
    return args.run(args)
