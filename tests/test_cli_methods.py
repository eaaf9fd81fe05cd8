"""``python -m sklearn_gpca segment --method``: the estimators for tracker output."""

# SPDX-License-Identifier: BSD-3-Clause

import re

import numpy as np
import pytest

from sklearn_gpca import MotionSegmentation, PerspectiveClustering
from sklearn_gpca._cli import _estimator, build_parser, main
from sklearn_gpca.datasets import make_motions, make_tracks


def _summary(output):
    return dict(re.findall(r"^  (\S[\w ]*?)  +(.+)$", output, flags=re.MULTILINE))


@pytest.fixture(scope="module")
def tracks_file(tmp_path_factory):
    """A small tracker-like draw with outlier tracks, and its truth."""
    X, y = make_tracks(
        scene="lab", n_tracks=150, n_frames=12, outlier_fraction=0.1, random_state=0
    )[:2]
    path = tmp_path_factory.mktemp("tracks") / "tracks.npz"
    np.savez(path, X=X, y=y)
    return path, X, y


@pytest.mark.parametrize(
    "method, options, estimator",
    [
        ("tracks", [], MotionSegmentation(2, random_state=3)),
        (
            "tracks",
            ["--outlier-threshold", "0.001"],
            MotionSegmentation(2, outlier_threshold=0.001, random_state=3),
        ),
        ("perspective", [], PerspectiveClustering(2, random_state=3)),
        ("tracks", ["--jobs", "2"], MotionSegmentation(2, random_state=3)),
        (
            "tracks",
            ["--n-init", "2"],
            MotionSegmentation(2, n_init=2, random_state=3),
        ),
    ],
)
def test_method_writes_the_labels_of_its_estimator(
    tmp_path, capsys, tracks_file, method, options, estimator
):
    path, X, _ = tracks_file
    out = tmp_path / "labels.txt"
    argv = ["segment", str(path), "--n-motions", "2", "--method", method]
    argv += [*options, "--seed", "3", "--output", str(out)]
    assert main(argv) == 0
    written = np.loadtxt(out, dtype=int)
    np.testing.assert_array_equal(written, estimator.fit_predict(X))
    text = capsys.readouterr().out
    assert f"  {type(estimator).__name__}(n_clusters=2" in text
    n_outliers = int(np.sum(written == -1))
    sizes = _summary(text)["sizes"]
    assert sizes.endswith(f"(+ {n_outliers} outliers, label -1)") == bool(n_outliers)
    if "--outlier-threshold" in options:
        assert n_outliers > 0


@pytest.mark.parametrize(
    "options, message",
    [
        (["--method", "tracks", "--rank", "4"], "--rank applies to --method pipeline"),
        (["--method", "perspective", "--rank", "4"], "not perspective"),
        (["--outlier-threshold", "0.01"], "--outlier-threshold needs --method tracks"),
        (
            ["--method", "perspective", "--outlier-threshold", "0.01"],
            "--outlier-threshold needs --method tracks",
        ),
        (["--jobs", "2"], "--jobs needs --method tracks"),
        (["--method", "perspective", "--jobs", "2"], "--jobs needs --method tracks"),
        (["--n-init", "2"], "--n-init needs --method tracks"),
        (
            ["--method", "perspective", "--n-init", "2"],
            "--n-init needs --method tracks",
        ),
    ],
)
def test_options_the_method_does_not_use_are_refused(
    tmp_path, capsys, options, message
):
    X = make_motions(2, n_points=20, n_frames=5, random_state=0)[0]
    path = tmp_path / "m.npz"
    np.savez(path, X=X)
    assert main(["segment", str(path), "--n-motions", "2", *options]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1
    assert message in err


def test_auto_needs_the_pipeline(tmp_path, capsys):
    path = tmp_path / "m.npz"
    np.savez(path, X=make_motions(2, n_points=20, n_frames=5, random_state=0)[0])
    argv = ["segment", str(path), "--n-motions", "auto", "--method", "tracks"]
    assert main(argv) == 2
    assert "--n-motions auto needs --method pipeline" in capsys.readouterr().err


def test_unknown_method_is_a_usage_error(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["segment", "x.npz", "--n-motions", "2", "--method", "ssc"])
    assert exc.value.code == 2
    assert "--method" in capsys.readouterr().err


@pytest.mark.parametrize(
    "jobs, message", [("0", "must not be 0"), ("two", "must be an integer")]
)
def test_bad_jobs_is_a_usage_error(capsys, jobs, message):
    argv = ["segment", "x.npz", "--n-motions", "2", "--method", "tracks"]
    with pytest.raises(SystemExit) as exc:
        main([*argv, "--jobs", jobs])
    assert exc.value.code == 2
    assert f"--jobs: {message}" in capsys.readouterr().err


def test_jobs_reach_the_estimator():
    argv = ["segment", "x.npz", "--n-motions", "2", "--method", "tracks"]
    args = build_parser().parse_args([*argv, "--jobs", "-1"])
    assert _estimator(args, (150, 24)).n_jobs == -1
    assert _estimator(build_parser().parse_args(argv), (150, 24)).n_jobs is None


def test_n_init_reaches_the_estimator():
    argv = ["segment", "x.npz", "--n-motions", "2", "--method", "tracks"]
    args = build_parser().parse_args([*argv, "--n-init", "3"])
    assert _estimator(args, (150, 24)).n_init == 3
    assert _estimator(build_parser().parse_args(argv), (150, 24)).n_init == 1


@pytest.mark.parametrize("value", ["0", "-2", "two"])
def test_bad_n_init_is_a_usage_error(capsys, value):
    argv = ["segment", "x.npz", "--n-motions", "2", "--method", "tracks"]
    with pytest.raises(SystemExit) as exc:
        main([*argv, "--n-init", value])
    assert exc.value.code == 2
    assert "--n-init" in capsys.readouterr().err
