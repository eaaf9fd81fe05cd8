"""Tests of the command line ``python -m sklearn_gpca``."""

# SPDX-License-Identifier: BSD-3-Clause

import re
import subprocess
import sys

import numpy as np
import pytest
import scipy.io

from sklearn_gpca._cli import main, read_trajectories
from sklearn_gpca.datasets import make_motions


@pytest.fixture(scope="module")
def motions():
    """Two motions, 40 points each, 8 frames, 10 % of entries missing."""
    return make_motions(2, n_points=[40, 40], n_frames=8, missing=0.1, random_state=0)


def write_npz(path, X, y=None):
    if y is None:
        np.savez(path, X=X)
    else:
        np.savez(path, X=X, y=y)
    return path


def write_csv(path, X, header=None):
    lines = [] if header is None else [",".join(header)]
    lines += [",".join("" if np.isnan(v) else repr(float(v)) for v in row) for row in X]
    path.write_text("\n".join(lines) + "\n")
    return path


def write_mat(path, X, y=None, key="x"):
    n_points, n_frames = X.shape[0], X.shape[1] // 2
    points = X.reshape(n_points, n_frames, 2).transpose(2, 0, 1)
    points = np.concatenate([points, np.ones((1, n_points, n_frames))])
    data = {key: points}
    if y is not None:
        data["s"] = (np.asarray(y) + 1).reshape(-1, 1)
    scipy.io.savemat(path, data)
    return path


def summary(output):
    """``{name: value}`` of the indented two-column summary lines."""
    rows = re.findall(r"^  (\S[\w ]*?)  +(.+)$", output, flags=re.MULTILINE)
    return dict(rows)


def test_demo_output_format(capsys):
    assert main(["demo", "--n-points", "30", "--n-frames", "6"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("Segmenting synthetic rigid motions")
    rows = summary(out)
    assert list(rows) == [
        "trajectories",
        "frames",
        "motions",
        "noise",
        "missing entries",
        "misclassified",
        "time",
    ]
    assert rows["trajectories"] == "90"


@pytest.mark.parametrize("fmt", ["npz", "csv", "mat"])
def test_segment_each_format(tmp_path, capsys, motions, fmt):
    X, y = motions
    if fmt == "npz":
        path = write_npz(tmp_path / "tracks.npz", X, y)
    elif fmt == "csv":
        path = write_csv(tmp_path / "tracks.csv", X)
    else:
        # Hopkins155 files hold complete trajectories.
        X, y = make_motions(2, n_points=[40, 40], n_frames=8, random_state=0)
        path = write_mat(tmp_path / "tracks.mat", X, y)
    labels_path = tmp_path / "labels.csv"
    status = main(
        ["segment", str(path), "--n-motions", "2", "--output", str(labels_path)]
    )
    assert status == 0
    rows = summary(capsys.readouterr().out)
    assert rows["trajectories"] == "80"
    assert rows["frames"] == "8"
    assert rows["motions"] == "2"
    assert ("misclassified" in rows) == (fmt != "csv")
    labels = np.loadtxt(labels_path, dtype=int)
    assert labels.shape == (80,)
    assert set(labels) <= {0, 1}


def test_read_csv_missing_cells_and_label_column(tmp_path, motions):
    X, y = motions
    header = [f"c{j}" for j in range(X.shape[1])] + ["label"]
    path = write_csv(tmp_path / "t.csv", np.column_stack([X, y]), header=header)
    X_read, y_read = read_trajectories(path)
    np.testing.assert_array_equal(np.isnan(X_read), np.isnan(X))
    np.testing.assert_allclose(X_read[~np.isnan(X)], X[~np.isnan(X)], rtol=1e-15)
    np.testing.assert_array_equal(y_read, y)


def test_read_mat_uses_y_without_x(tmp_path, motions):
    X = make_motions(2, n_points=[10, 10], n_frames=4, random_state=0)[0]
    path = write_mat(tmp_path / "t.mat", X, key="y")
    X_read, y_read = read_trajectories(path)
    np.testing.assert_allclose(X_read, X)
    assert y_read is None


def test_segment_auto_and_plot(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    X, y = make_motions(3, n_points=[60, 60, 60], n_frames=8, random_state=0)
    path = write_npz(tmp_path / "three.npz", X, y)
    plot = tmp_path / "seg.png"
    status = main(["segment", str(path), "--n-motions", "auto", "--plot", str(plot)])
    assert status == 0
    rows = summary(capsys.readouterr().out)
    assert rows["motions"].startswith("3 (auto, coding length in bits: 1: ")
    assert plot.stat().st_size > 0
    assert plot.read_bytes()[:4] == b"\x89PNG"


def _error_cases(tmp_path):
    X = make_motions(2, n_points=[10, 10], n_frames=4, random_state=0)[0]
    unknown = tmp_path / "tracks.txt"
    unknown.write_text("1,2\n")
    no_x = tmp_path / "no_x.npz"
    np.savez(no_x, Z=X)
    return {
        "no such file": tmp_path / "absent.npz",
        "unknown format": unknown,
        "odd number of columns": write_npz(tmp_path / "odd.npz", X[:, :-1]),
        "must be 2-D": write_npz(tmp_path / "flat.npz", X[0]),
        "at least 3 are needed": write_csv(tmp_path / "short.csv", X[:, :4]),
        "no array 'X'": no_x,
        "no field 'x' or 'y'": _mat_without_points(tmp_path / "bad.mat", X),
        "different numbers of cells": _ragged(tmp_path / "ragged.csv"),
    }


def _mat_without_points(path, X):
    scipy.io.savemat(path, {"z": X})
    return path


def _ragged(path):
    path.write_text("1,2,3,4,5,6\n1,2,3,4\n")
    return path


@pytest.mark.parametrize(
    "message",
    [
        "no such file",
        "unknown format",
        "odd number of columns",
        "must be 2-D",
        "at least 3 are needed",
        "no array 'X'",
        "no field 'x' or 'y'",
        "different numbers of cells",
    ],
)
def test_segment_user_errors(tmp_path, capsys, message):
    path = _error_cases(tmp_path)[message]
    status = main(["segment", str(path), "--n-motions", "2"])
    assert status == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1
    assert lines[0].startswith("python -m sklearn_gpca segment: error: ")
    assert message in lines[0]
    assert "Traceback" not in captured.err


def test_segment_too_few_points_for_n_motions(tmp_path, capsys):
    X = make_motions(2, n_points=[5, 5], n_frames=4, random_state=0)[0]
    path = write_npz(tmp_path / "few.npz", X)
    assert main(["segment", str(path), "--n-motions", "4"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1
    assert "too few" in err


@pytest.mark.parametrize("value", ["0", "two"])
def test_segment_bad_n_motions_is_a_usage_error(tmp_path, capsys, value):
    with pytest.raises(SystemExit) as exc:
        main(["segment", "x.npz", "--n-motions", value])
    assert exc.value.code == 2
    assert "--n-motions" in capsys.readouterr().err


def test_subprocess_segment_and_error(tmp_path, motions):
    X, y = motions
    path = write_npz(tmp_path / "tracks.npz", X, y)
    command = [sys.executable, "-m", "sklearn_gpca", "segment"]
    ok = subprocess.run(
        [*command, str(path), "--n-motions", "2"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert ok.returncode == 0, ok.stderr
    assert "misclassified" in ok.stdout
    bad = subprocess.run(
        [*command, str(tmp_path / "no.csv"), "--n-motions", "2"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert bad.returncode == 2
    assert bad.stderr.count("\n") == 1
    assert "no such file" in bad.stderr
