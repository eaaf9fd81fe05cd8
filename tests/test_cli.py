"""Tests of the command line ``python -m sklearn_gpca``."""

# SPDX-License-Identifier: BSD-3-Clause

import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import scipy.io

from sklearn_gpca._cli import UsageError, build_parser, main, read_trajectories
from sklearn_gpca.datasets import make_missing, make_motions
from sklearn_gpca.metrics import misclassification_rate


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


def _distinct_motions(n, *, n_per=60, n_frames=10, seed=0):
    """Trajectories on ``n`` random 4-D subspaces of R^(2 n_frames): for
    ``n <= n_frames / 2`` their union is direct, so each is a motion of its
    own and ``n`` is the number to find."""
    rng = np.random.RandomState(seed)
    bases = [np.linalg.qr(rng.randn(2 * n_frames, 4))[0] for _ in range(n)]
    X = np.vstack([rng.randn(n_per, 4) @ B.T for B in bases])
    return X + 1e-3 * rng.randn(*X.shape), np.repeat(np.arange(n), n_per)


def test_segment_auto_and_plot(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    X, y = _distinct_motions(3)
    path = write_npz(tmp_path / "three.npz", X, y)
    plot = tmp_path / "seg.png"
    status = main(["segment", str(path), "--n-motions", "auto", "--plot", str(plot)])
    assert status == 0
    output = capsys.readouterr().out
    rows = summary(output)
    assert rows["motions"].startswith("3 (auto, coding length in bits: 1: ")
    assert (
        "make_pipeline(PowerFactorization(n_components=20, whiten=False), "
        "GPCAClustering(n_clusters=3, segmentation_dim=5))"
    ) in output
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
        "4 cells where line 1 has 6": _ragged(tmp_path / "ragged.csv"),
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
        "4 cells where line 1 has 6",
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


# --- the labels file: equal to the pipeline's labels, never lost -----------


def reference_labels(X, n_motions, rank=5, seed=0):
    """The segmentation the command line promises, through the public API."""
    from sklearn.pipeline import make_pipeline

    from sklearn_gpca import GPCAClustering, PowerFactorization

    return make_pipeline(
        PowerFactorization(rank, random_state=seed),
        GPCAClustering(n_motions, random_state=seed),
    ).fit_predict(X)


@pytest.mark.parametrize("fmt", ["npz", "csv"])
def test_segment_writes_and_scores_the_pipeline_labels(tmp_path, capsys, fmt):
    X, y = make_motions(
        3, n_points=[40, 50, 60], n_frames=8, noise=0.5, missing=0.1, random_state=5
    )
    if fmt == "npz":
        path = write_npz(tmp_path / "tracks.npz", X, y)
    else:
        header = [f"{c}{f}" for f in range(8) for c in "xy"] + ["label"]
        path = write_csv(tmp_path / "tracks.csv", np.column_stack([X, y]), header)
    out = tmp_path / "labels.txt"
    assert main(["segment", str(path), "--n-motions", "3", "--output", str(out)]) == 0
    expected = reference_labels(X, 3)
    written = np.loadtxt(out, dtype=int)
    np.testing.assert_array_equal(written, expected)
    error = misclassification_rate(y, expected)
    # three motions, 0.5 px noise: a draw the default pipeline segments well
    assert error <= 0.05
    rows = summary(capsys.readouterr().out)
    assert rows["misclassified"] == f"{100 * error:.2f} % (ground truth in file)"
    sizes = np.bincount(expected, minlength=3)
    assert rows["sizes"] == " ".join(str(n) for n in sizes)


def test_demo_reports_the_error_of_its_segmentation(capsys):
    from sklearn.pipeline import make_pipeline

    from sklearn_gpca import GPCAClustering, PowerFactorization

    assert (
        main(["demo", "--n-points", "30", "--n-frames", "6", "--n-motions", "2"]) == 0
    )
    X, y = make_motions(
        2,
        n_points=[30, 30],
        n_frames=6,
        noise=1.0,
        missing=0.2,
        missing_pattern="occlusion",
        random_state=0,
    )
    labels = make_pipeline(
        PowerFactorization(random_state=0), GPCAClustering(2, random_state=0)
    ).fit_predict(X)
    rows = summary(capsys.readouterr().out)
    assert rows["misclassified"] == f"{100 * misclassification_rate(y, labels):.2f} %"
    assert rows["missing entries"] == f"{100 * np.isnan(X).mean():.1f} % (occlusion)"


def test_output_equal_to_the_input_is_refused(tmp_path, capsys, motions):
    X, y = motions
    path = write_npz(tmp_path / "tracks.npz", X, y)
    before = path.read_bytes()
    for extra in ([], ["--force"]):
        argv = ["segment", str(path), "--n-motions", "2", "--output", str(path)]
        assert main([*argv, *extra]) == 2
        err = capsys.readouterr().err
        assert "is the input file" in err
        assert len(err.strip().splitlines()) == 1
        assert path.read_bytes() == before


def test_output_through_another_name_of_the_input_is_refused(tmp_path, capsys, motions):
    path = write_npz(tmp_path / "tracks.npz", *motions)
    link = tmp_path / "link.npz"
    link.symlink_to(path)
    argv = ["segment", str(path), "--n-motions", "2", "--output", str(link), "--force"]
    assert main(argv) == 2
    assert "is the input file" in capsys.readouterr().err
    assert np.load(path)["X"].shape == (80, 16)


@pytest.mark.parametrize("option", ["--output", "--plot"])
def test_existing_file_is_overwritten_only_with_force(tmp_path, capsys, option):
    if option == "--plot":
        pytest.importorskip("matplotlib")
    X, y = make_motions(2, n_points=[30, 30], n_frames=6, random_state=0)
    path = write_npz(tmp_path / "tracks.npz", X, y)
    target = tmp_path / ("labels.txt" if option == "--output" else "tracks.png")
    target.write_text("precious\n")
    argv = ["segment", str(path), "--n-motions", "2", option, str(target)]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "exists; add --force" in err
    assert target.read_text() == "precious\n"
    assert main([*argv, "--force"]) == 0
    if option == "--output":
        np.testing.assert_array_equal(
            np.loadtxt(target, dtype=int), reference_labels(X, 2)
        )
    else:
        assert target.read_bytes()[:4] == b"\x89PNG"


def test_labels_are_written_whole_or_not_at_all(tmp_path, capsys, monkeypatch):
    X, y = make_motions(2, n_points=[30, 30], n_frames=6, random_state=0)
    path = write_npz(tmp_path / "tracks.npz", X, y)
    target = tmp_path / "labels.txt"
    target.write_text("precious\n")
    real_savetxt = np.savetxt

    def savetxt_then_fail(fname, values, **kwargs):
        real_savetxt(fname, values[:5], **kwargs)
        raise OSError("No space left on device")

    monkeypatch.setattr(np, "savetxt", savetxt_then_fail)
    argv = ["segment", str(path), "--n-motions", "2", "--output", str(target)]
    assert main([*argv, "--force"]) == 2
    assert "No space left on device" in capsys.readouterr().err
    assert target.read_text() == "precious\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["labels.txt", "tracks.npz"]


def test_output_in_a_missing_folder_is_refused_before_fitting(tmp_path, capsys):
    X, y = make_motions(2, n_points=[30, 30], n_frames=6, random_state=0)
    path = write_npz(tmp_path / "tracks.npz", X, y)
    out = tmp_path / "no" / "labels.txt"
    assert main(["segment", str(path), "--n-motions", "2", "--output", str(out)]) == 2
    captured = capsys.readouterr()
    assert "no such directory" in captured.err
    assert captured.out == ""


# --- csv files: header, missing cells, label columns ------------------------


def csv_lines(X, labels=None, missing=""):
    lines = []
    for i, row in enumerate(X):
        cells = [missing if np.isnan(v) else repr(float(v)) for v in row]
        if labels is not None:
            cells.append(str(labels[i]))
        lines.append(",".join(cells))
    return lines


def test_csv_byte_order_mark_keeps_the_first_row(tmp_path, capsys, motions):
    X, _ = motions
    path = tmp_path / "bom.csv"
    path.write_text("\n".join(csv_lines(X)) + "\n", encoding="utf-8-sig")
    assert path.read_bytes()[:3] == b"\xef\xbb\xbf"
    X_read, y_read = read_trajectories(path)
    np.testing.assert_array_equal(np.isnan(X_read), np.isnan(X))
    np.testing.assert_allclose(X_read[~np.isnan(X)], X[~np.isnan(X)], rtol=1e-15)
    assert y_read is None
    out = tmp_path / "labels.txt"
    assert main(["segment", str(path), "--n-motions", "2", "--output", str(out)]) == 0
    assert len(out.read_text().splitlines()) == X.shape[0]


@pytest.mark.parametrize("missing", ["", "NA", "nan", "NaN", "N/A", " na "])
def test_csv_missing_cells_in_every_row_including_the_first(tmp_path, missing):
    X = make_motions(2, n_points=[10, 10], n_frames=5, random_state=0)[0]
    X[0, 3] = X[0, 6] = X[4, 0] = np.nan
    path = tmp_path / "t.csv"
    path.write_text("\n".join(csv_lines(X, missing=missing)) + "\n")
    X_read, _ = read_trajectories(path)
    assert X_read.shape == X.shape
    np.testing.assert_array_equal(np.isnan(X_read), np.isnan(X))


def test_csv_header_is_a_row_without_any_number(tmp_path):
    X = make_motions(2, n_points=[10, 10], n_frames=4, random_state=0)[0]
    body = "\n".join(csv_lines(X))
    # names: a header
    path = tmp_path / "named.csv"
    path.write_text(",".join(f"c{j}" for j in range(8)) + "\n" + body + "\n")
    assert read_trajectories(path)[0].shape == (20, 8)
    # numbers and a name in the first row: not a header, and not a number
    path = tmp_path / "mixed.csv"
    path.write_text("1.0,2.0,x,4.0,5.0,6.0,7.0,8.0\n" + body + "\n")
    with pytest.raises(UsageError, match=r"line 1: cell 3 \('x'\) is not a number"):
        read_trajectories(path)
    # a first row of missing cells only: an all-missing trajectory, not a header
    path = tmp_path / "empty_first.csv"
    path.write_text("NA,,nan,NA,,,NA,\n" + body + "\n")
    X_read, _ = read_trajectories(path)
    assert X_read.shape == (21, 8)
    assert np.isnan(X_read[0]).all()


@pytest.mark.parametrize("name", ["label", "labels", "s", "y_true", "Label", " LABEL"])
def test_csv_label_column_is_found_by_name(tmp_path, motions, name):
    X, y = motions
    header = ["x", "y"] * 8
    position = 5
    header.insert(position, name)
    lines = csv_lines(X, labels=y)
    # move the label cell to its column
    rows = []
    for line in lines:
        cells = line.split(",")
        cells.insert(position, cells.pop())
        rows.append(",".join(cells))
    path = tmp_path / "t.csv"
    path.write_text(",".join(header) + "\n" + "\n".join(rows) + "\n")
    X_read, y_read = read_trajectories(path)
    np.testing.assert_array_equal(y_read, y)
    np.testing.assert_array_equal(np.isnan(X_read), np.isnan(X))
    np.testing.assert_allclose(X_read[~np.isnan(X)], X[~np.isnan(X)], rtol=1e-15)


def test_csv_header_of_coordinates_has_no_label_column(tmp_path, motions):
    X, _ = motions
    path = tmp_path / "t.csv"
    path.write_text(",".join(["x", "y"] * 8) + "\n" + "\n".join(csv_lines(X)) + "\n")
    X_read, y_read = read_trajectories(path)
    assert X_read.shape == (80, 16)
    assert y_read is None


def test_csv_string_labels(tmp_path, capsys, motions):
    X, y = motions
    names = np.array(["car", "background"])[y]
    path = tmp_path / "t.csv"
    header = ",".join(["x", "y"] * 8 + ["motion"])
    path.write_text(header + "\n" + "\n".join(csv_lines(X, labels=names)) + "\n")
    _, y_read = read_trajectories(path)
    np.testing.assert_array_equal(y_read, names)
    assert main(["segment", str(path), "--n-motions", "2"]) == 0
    error = misclassification_rate(y, reference_labels(X, 2))
    rows = summary(capsys.readouterr().out)
    assert rows["misclassified"] == f"{100 * error:.2f} % (ground truth in file)"


@pytest.mark.parametrize(
    ("header", "labels", "message"),
    [
        # no header: every column is a coordinate, and 17 is odd
        (None, "0", r"odd number of columns \(17\).*name a label column"),
        (["x", "y"] * 8 + ["label"], "", r"label column 'label' is empty on line 2"),
        (["label"] + ["x", "y"] * 7 + ["x", "s"], "1", r"several label columns"),
        (["x", "y"] * 8, "1", r"line 2: 17 cells where the header has 16"),
    ],
)
def test_csv_label_column_errors(tmp_path, capsys, motions, header, labels, message):
    X, _ = motions
    lines = csv_lines(X, labels=[labels] * X.shape[0])
    if header is not None:
        lines.insert(0, ",".join(header))
    path = tmp_path / "t.csv"
    path.write_text("\n".join(lines) + "\n")
    assert main(["segment", str(path), "--n-motions", "2"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1
    assert re.search(message, err), err


@pytest.mark.parametrize(
    "text",
    [
        "\ufeffNA,2,3,4,5,6,7,8\n{body}\n",
        "x,y,x,y,x,y,x,y\n{body}\n\n\n",
        "{body}\n\n",
        "\n\n{body}",
        "{body}\r\n",
    ],
    ids=["bom-na", "header-trailing-blank", "trailing-blank", "leading-blank", "crlf"],
)
def test_one_label_line_per_input_row(tmp_path, text):
    X = make_motions(2, n_points=[15, 15], n_frames=4, random_state=0)[0]
    body = "\n".join(csv_lines(X))
    if text.startswith("\ufeffNA"):
        body = "\n".join(csv_lines(X)[1:])
        n_rows = X.shape[0]  # the NA row is a trajectory
    else:
        n_rows = X.shape[0]
    path = tmp_path / "t.csv"
    path.write_bytes(text.format(body=body).encode("utf-8"))
    out = tmp_path / "labels.txt"
    status = main(
        ["segment", str(path), "--n-motions", "2", "--rank", "4", "--output", str(out)]
    )
    assert status == 0
    assert len(out.read_text().splitlines()) == n_rows


# --- one-line errors, exit status, warnings, Ctrl-C -------------------------


def _zip_without_npy(path):
    import zipfile

    with zipfile.ZipFile(path, "w") as zf:
        zf.writestr("readme.txt", "not an array")
    return path


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda p: p.write_bytes(b"") and p, "the file is empty"),
        (lambda p: p.write_bytes(bytes(range(256)) * 4) and p, "not a .npz archive"),
        (lambda p: p.write_bytes(b"PK\x03\x04 truncated") and p, "cannot read as .npz"),
        (_zip_without_npy, "no array 'X'"),
    ],
    ids=["empty", "random-bytes", "truncated-zip", "zip-without-X"],
)
def test_bad_npz_files_get_one_line(tmp_path, capsys, make, message):
    path = tmp_path / "bad.npz"
    make(path)
    assert main(["segment", str(path), "--n-motions", "2"]) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1
    assert message in lines[0]
    assert "pickle" not in lines[0]


@pytest.mark.parametrize(
    ("scale", "message"),
    [
        (1e200, r"as large as 1e\+200 exceed 1e\+150"),
        (1e-200, r"largest coordinate is 1e-200, below 1e-150"),
        (0.0, r"largest coordinate is 0, below 1e-150"),
    ],
)
def test_out_of_range_coordinates_get_one_line(
    tmp_path, capsys, motions, scale, message
):
    X, y = motions
    X = X / np.nanmax(np.abs(X)) * scale
    path = write_npz(tmp_path / "scaled.npz", X, y)
    assert main(["segment", str(path), "--n-motions", "2"]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1
    assert re.search(message, lines[0]), lines[0]


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["demo", "--n-motions", "0"], "--n-motions: must be at least 1, got 0"),
        (["demo", "--n-points", "-3"], "--n-points: must be at least 1, got -3"),
        (["demo", "--n-frames", "1"], "--n-frames: must be at least 3, got 1"),
        (["demo", "--missing", "1.5"], r"--missing: must lie in \[0, 1\), got 1.5"),
        (["demo", "--missing", "1"], r"--missing: must lie in \[0, 1\), got 1"),
        (["demo", "--noise", "-1"], r"--noise: must lie in \[0, inf\), got -1"),
        (["demo", "--noise", "nan"], r"--noise: must lie in \[0, inf\), got nan"),
        (["segment", "x.npz", "--n-motions", "two"], "must be an integer, got 'two'"),
        (["segment", "x.npz"], "the following arguments are required: --n-motions"),
    ],
)
def test_bad_arguments_get_one_line_and_status_2(capsys, argv, message):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1
    assert re.search(message, lines[0]), lines[0]
    assert lines[0].startswith(f"python -m sklearn_gpca {argv[0]}: error: ")


def test_ctrl_c_exits_130_with_one_line(tmp_path, capsys, monkeypatch, motions):
    import sklearn_gpca._cli as cli

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(cli, "_fit", interrupted)
    path = write_npz(tmp_path / "tracks.npz", *motions)
    try:
        status = main(["segment", str(path), "--n-motions", "2"])
    except KeyboardInterrupt:  # caught here, or it would stop pytest itself
        pytest.fail("KeyboardInterrupt escaped the command line")
    assert status == 130
    lines = capsys.readouterr().err.strip().splitlines()
    assert lines == ["python -m sklearn_gpca: interrupted"]


def _reads_a_pipe(pid):
    """Whether process ``pid`` sleeps in a pipe read; None without /proc."""
    try:
        return "pipe" in Path(f"/proc/{pid}/wchan").read_text()  # pipe_read, ...
    except FileNotFoundError:
        return None if not Path("/proc/self/wchan").exists() else False


def test_subprocess_ctrl_c(tmp_path):
    """A real SIGINT while the command line waits on its input: status 130
    and one line, no traceback."""
    import errno
    import os
    import signal

    fifo = tmp_path / "tracks.npz"
    os.mkfifo(fifo)
    # A shell runs background jobs (CI scripts, nohup) with SIGINT ignored, and
    # the child would inherit it: give it Python's handler back before the
    # command line starts. (Not with ``preexec_fn``: between fork and exec in a
    # process with threads, as pytest's is, it can deadlock the child.)
    launcher = (
        "import runpy, signal, sys;"
        "signal.signal(signal.SIGINT, signal.default_int_handler);"
        "sys.argv = ['sklearn_gpca', *sys.argv[1:]];"
        "runpy.run_module('sklearn_gpca', run_name='__main__', alter_sys=True)"
    )
    process = subprocess.Popen(
        [sys.executable, "-c", launcher, "segment", str(fifo), "--n-motions", "2"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    # A writer can open the FIFO only once the command line has opened it to
    # read (inside its main loop, past the imports); it then blocks reading.
    deadline = time.monotonic() + 120
    while True:
        try:
            writer = os.open(fifo, os.O_WRONLY | os.O_NONBLOCK)
            break
        except OSError as exc:
            assert exc.errno == errno.ENXIO
            if process.poll() is not None or time.monotonic() > deadline:
                process.kill()
                pytest.fail(
                    "the command line never opened its input: "
                    f"status {process.poll()}, stderr {process.communicate()[1]!r}"
                )
            time.sleep(0.05)
    # CPython runs a signal's handler between bytecodes: a SIGINT that lands
    # after the open returned but before the read blocks waits for the read to
    # return, which it never does here. So send it once the command line is
    # blocked in the read, as the kernel's wait channel says (without /proc,
    # after 1 s), and again each 5 s while it still is, as a user would.
    deadline = time.monotonic() + 120
    while _reads_a_pipe(process.pid) is False and time.monotonic() < deadline:
        time.sleep(0.02)
    if _reads_a_pipe(process.pid) is None:
        time.sleep(1)
    try:
        while True:
            process.send_signal(signal.SIGINT)
            try:
                _, err = process.communicate(timeout=5)
                break
            except subprocess.TimeoutExpired:
                if time.monotonic() > deadline or not _reads_a_pipe(process.pid):
                    process.kill()
                    pytest.fail(f"no exit after SIGINT: {process.communicate()[1]!r}")
    finally:
        os.close(writer)
    assert process.returncode == 130, err
    assert err.strip().splitlines() == ["python -m sklearn_gpca: interrupted"]


def test_library_bug_is_not_a_usage_error(tmp_path, monkeypatch, motions):
    import sklearn_gpca._cli as cli

    def buggy_fit(*args, **kwargs):
        return np.ones(2) + np.ones(3)  # numpy's ValueError: a bug, not the input

    monkeypatch.setattr(cli, "_fit", buggy_fit)
    path = write_npz(tmp_path / "tracks.npz", *motions)
    with pytest.raises(ValueError, match="could not be broadcast"):
        main(["segment", str(path), "--n-motions", "2"])


def test_library_check_of_the_input_is_a_usage_error(tmp_path, capsys, motions):
    X, y = motions
    rows = [0, 1, -2, -1]  # four trajectories cannot determine a rank-5 fit
    path = write_npz(tmp_path / "tracks.npz", X[rows], y[rows])
    assert main(["segment", str(path), "--n-motions", "2"]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1
    # reported against the file
    assert lines[0].startswith(f"python -m sklearn_gpca segment: error: {path}: ")
    assert "n_components=5 must be at most n_samples=4" in lines[0]


def test_library_warnings_are_shown(tmp_path, capsys, monkeypatch, motions):
    import warnings

    from sklearn.exceptions import ConvergenceWarning

    import sklearn_gpca._cli as cli

    real_fit = cli._fit

    def warning_fit(*args, **kwargs):
        warnings.warn("cluster 2 is empty", UserWarning, stacklevel=1)
        warnings.warn("cluster 2 is empty", UserWarning, stacklevel=1)
        warnings.warn("did not converge", ConvergenceWarning, stacklevel=1)
        warnings.warn("internal detail", DeprecationWarning, stacklevel=1)
        return real_fit(*args, **kwargs)

    monkeypatch.setattr(cli, "_fit", warning_fit)
    path = write_npz(tmp_path / "tracks.npz", *motions)
    assert main(["segment", str(path), "--n-motions", "2"]) == 0
    lines = capsys.readouterr().err.strip().splitlines()
    assert lines == [
        "python -m sklearn_gpca: warning: cluster 2 is empty (UserWarning)",
        "python -m sklearn_gpca: warning: did not converge (ConvergenceWarning)",
    ]


def test_console_script_entry_point():
    from importlib.metadata import entry_points

    (script,) = entry_points(group="console_scripts", name="sklearn-gpca")
    assert script.load() is main


def test_sizes_count_empty_motions_and_outliers(tmp_path, capsys, monkeypatch):
    import sklearn_gpca._cli as cli

    X, y = make_motions(2, n_points=[10, 10], n_frames=4, random_state=0)
    path = write_npz(tmp_path / "tracks.npz", X, y)
    real_fit = cli._fit
    labels = np.r_[np.zeros(12, dtype=int), np.full(5, 2), np.full(3, -1)]

    def fit_with_outliers(*args, **kwargs):
        pipeline, _ = real_fit(*args, **kwargs)
        pipeline[-1].n_clusters_ = 3
        return pipeline, labels

    monkeypatch.setattr(cli, "_fit", fit_with_outliers)
    out = tmp_path / "labels.txt"
    argv = [
        "segment",
        str(path),
        "--n-motions",
        "2",
        "--rank",
        "4",
        "--output",
        str(out),
    ]
    assert main(argv) == 0
    rows = summary(capsys.readouterr().out)
    assert rows["sizes"] == "12 0 5 (+ 3 outliers, label -1)"
    np.testing.assert_array_equal(np.loadtxt(out, dtype=int), labels)


# --- behaviour pinned by the mutation run (benchmarks/results/mutation.md) --


def test_installed_script_names_itself(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(sys, "argv", ["/usr/local/bin/sklearn-gpca", "segment"])
    assert main(["segment", str(tmp_path / "absent.npz"), "--n-motions", "2"]) == 2
    err = capsys.readouterr().err
    assert (
        err == f"sklearn-gpca segment: error: {tmp_path / 'absent.npz'}: no such file\n"
    )
    assert build_parser().prog == "sklearn-gpca"
    monkeypatch.setattr(sys, "argv", ["/somewhere/sklearn_gpca/__main__.py"])
    assert build_parser().prog == "python -m sklearn_gpca"
    assert build_parser("gpca").prog == "gpca"


def test_checks_of_scikit_learn_count_as_input_errors():
    from sklearn.utils import check_array

    from sklearn_gpca._cli import _raised_by_a_check

    with pytest.raises(ValueError) as sklearn_check:
        check_array(np.zeros((0, 3)))
    assert _raised_by_a_check(sklearn_check.value)
    with pytest.raises(ValueError) as numpy_failure:
        np.ones(2) + np.ones(3)
    assert not _raised_by_a_check(numpy_failure.value)


def elapsed_and_output(capsys, argv):
    start = time.perf_counter()
    assert main(argv) == 0
    elapsed = time.perf_counter() - start
    return elapsed, capsys.readouterr().out


def reported_seconds(rows):
    match = re.fullmatch(r"(\d+\.\d{3}) s", rows["time"])
    assert match, rows["time"]
    return float(match.group(1))


def test_demo_reports_the_draw_it_was_asked_for(capsys, monkeypatch):
    """Every option reaches the draw and the pipeline: the printed error is
    the one of that draw, and it is far from zero, so that a different draw
    or a default pipeline would print another number."""
    import sklearn.pipeline
    from sklearn.pipeline import make_pipeline

    from sklearn_gpca import GPCAClustering, PowerFactorization

    built = []

    def spy_make_pipeline(*steps):
        built.append(make_pipeline(*steps))
        return built[-1]

    monkeypatch.setattr(sklearn.pipeline, "make_pipeline", spy_make_pipeline)
    argv = ["demo", "--n-motions", "3", "--n-points", "20", "--n-frames", "5"]
    argv += ["--noise", "5", "--missing", "0.3", "--missing-pattern", "occlusion"]
    argv += ["--random-state", "3"]
    elapsed, out = elapsed_and_output(capsys, argv)
    X, y = make_motions(
        3,
        n_points=[20, 20, 20],
        n_frames=5,
        noise=5.0,
        missing=0.3,
        missing_pattern="occlusion",
        random_state=3,
    )
    (pipeline,) = built
    params = pipeline.get_params()
    assert params["powerfactorization__random_state"] == 3
    assert params["gpcaclustering__random_state"] == 3
    assert params["gpcaclustering__n_clusters"] == 3
    labels = make_pipeline(
        PowerFactorization(random_state=3), GPCAClustering(3, random_state=3)
    ).fit_predict(X)
    error = misclassification_rate(y, labels)
    assert error > 0.05  # 5 px of noise on 5 frames: a hard draw
    assert out.splitlines()[:3] == [
        "Segmenting synthetic rigid motions under an affine camera",
        "  make_pipeline(PowerFactorization(), GPCAClustering(n_clusters=3))",
        "",
    ]
    rows = summary(out)
    assert rows == {
        "trajectories": "60",
        "frames": "5",
        "motions": "3",
        "noise": "5 px",
        "missing entries": f"{100 * np.isnan(X).mean():.1f} % (occlusion)",
        "misclassified": f"{100 * error:.2f} %",
        "time": rows["time"],
    }
    assert reported_seconds(rows) <= elapsed + 5e-4


def test_segment_builds_and_prints_the_pipeline_of_its_options(
    tmp_path, capsys, monkeypatch
):
    import sklearn_gpca._cli as cli

    X, y = make_motions(2, n_points=[30, 30], n_frames=6, missing=0.1, random_state=2)
    path = write_npz(tmp_path / "tracks.npz", X, y)
    out = tmp_path / "labels.txt"
    fitted = []
    real_fit = cli._fit

    def spy_fit(*args, **kwargs):
        pipeline, labels = real_fit(*args, **kwargs)
        fitted.append(pipeline)
        return pipeline, labels

    monkeypatch.setattr(cli, "_fit", spy_fit)
    argv = ["segment", str(path), "--n-motions", "2", "--rank", "4", "--seed", "3"]
    elapsed, text = elapsed_and_output(capsys, [*argv, "--output", str(out)])
    (pipeline,) = fitted
    params = pipeline.get_params()
    assert params["powerfactorization__n_components"] == 4
    assert params["powerfactorization__random_state"] == 3
    assert params["gpcaclustering__n_clusters"] == 2
    assert params["gpcaclustering__random_state"] == 3
    assert text.splitlines()[:3] == [
        f"Segmenting {path}",
        "  make_pipeline(PowerFactorization(n_components=4), "
        "GPCAClustering(n_clusters=2))",
        "",
    ]
    expected = reference_labels(X, 2, rank=4, seed=3)
    np.testing.assert_array_equal(np.loadtxt(out, dtype=int), expected)
    rows = summary(text)
    assert list(rows) == [
        "trajectories",
        "frames",
        "missing entries",
        "motions",
        "sizes",
        "misclassified",
        "time",
        "labels",
    ]
    assert rows["missing entries"] == f"{100 * np.isnan(X).mean():.1f} %"
    assert rows["labels"] == str(out)
    assert reported_seconds(rows) <= elapsed + 5e-4
    # without --output (and a file without labels): no labels row
    write_npz(path, X)
    rows = summary(elapsed_and_output(capsys, argv)[1])
    assert list(rows) == [
        "trajectories",
        "frames",
        "missing entries",
        "motions",
        "sizes",
        "time",
    ]


def test_rank_may_reach_twice_the_frames(tmp_path, capsys):
    X, y = make_motions(2, n_points=[30, 30], n_frames=3, random_state=0)
    path = write_npz(tmp_path / "tracks.npz", X, y)
    assert main(["segment", str(path), "--n-motions", "2", "--rank", "6"]) == 0
    capsys.readouterr()
    assert main(["segment", str(path), "--n-motions", "2", "--rank", "7"]) == 2
    assert capsys.readouterr().err == (
        "python -m sklearn_gpca segment: error: "
        f"--rank 7 exceeds 2 * frames = 6 for {path}\n"
    )


@pytest.mark.parametrize("option", ["--output", "--plot"])
def test_destinations_are_named_in_their_errors(tmp_path, capsys, option):
    X, y = make_motions(2, n_points=[10, 10], n_frames=4, random_state=0)
    path = write_npz(tmp_path / "tracks.npz", X, y)
    prefix = "python -m sklearn_gpca segment: error: "
    folder = tmp_path / "folder"
    folder.mkdir()
    existing = tmp_path / "existing.png"
    existing.write_text("precious\n")
    for target, problem in [
        (folder, "is a directory"),
        (existing, "exists; add --force to overwrite it"),
    ]:
        argv = ["segment", str(path), "--n-motions", "2", option, str(target)]
        assert main(argv) == 2
        assert capsys.readouterr().err == f"{prefix}{option} {target} {problem}\n"


def test_output_and_plot_on_one_file_are_refused(tmp_path, capsys):
    X, y = make_motions(2, n_points=[10, 10], n_frames=4, random_state=0)
    path = write_npz(tmp_path / "tracks.npz", X, y)
    same = str(tmp_path / "out.png")
    argv = ["segment", str(path), "--n-motions", "2", "--output", same, "--plot", same]
    assert main(argv) == 2
    captured = capsys.readouterr()
    assert captured.err == (
        "python -m sklearn_gpca segment: error: --output and --plot name the same "
        "file\n"
    )
    assert captured.out == ""


def test_plot_marks_errors_against_the_file_labels(tmp_path, capsys, monkeypatch):
    pytest.importorskip("matplotlib")
    from sklearn_gpca.plotting import TrajectoryDisplay

    X, y = make_motions(2, n_points=[20, 20], n_frames=5, random_state=0)
    path = write_npz(tmp_path / "tracks.npz", X, y)
    calls = []
    real = TrajectoryDisplay.from_predictions

    def spy(*args, **kwargs):
        calls.append(kwargs)
        return real(*args, **kwargs)

    monkeypatch.setattr(TrajectoryDisplay, "from_predictions", spy)
    plot = tmp_path / "tracks.png"
    argv = ["segment", str(path), "--n-motions", "2", "--plot", str(plot)]
    rows = summary(elapsed_and_output(capsys, argv)[1])
    (kwargs,) = calls
    np.testing.assert_array_equal(kwargs["y_true"], y)
    assert rows["plot"] == str(plot)
    assert "labels" not in rows


def test_plot_errors_get_one_line(tmp_path, capsys, monkeypatch):
    pytest.importorskip("matplotlib")
    X, y = make_motions(2, n_points=[20, 20], n_frames=5, random_state=0)
    path = write_npz(tmp_path / "tracks.npz", X, y)
    bad = tmp_path / "tracks.xyz"
    assert main(["segment", str(path), "--n-motions", "2", "--plot", str(bad)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(
        f"python -m sklearn_gpca segment: error: cannot write {bad}: "
    )
    assert "xyz" in err[len("python -m sklearn_gpca segment: error: cannot write") :]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["tracks.npz"]
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    plot = tmp_path / "tracks.png"
    assert main(["segment", str(path), "--n-motions", "2", "--plot", str(plot)]) == 2
    assert capsys.readouterr().err == (
        "python -m sklearn_gpca segment: error: --plot requires matplotlib: "
        "pip install 'sklearn_gpca[plot]'\n"
    )


def test_auto_prints_the_coding_length_of_each_count(tmp_path, capsys):
    from sklearn.pipeline import make_pipeline

    from sklearn_gpca import GPCAClustering, PowerFactorization

    X, y = make_motions(3, n_points=[30, 30, 30], n_frames=6, random_state=0)
    path = write_npz(tmp_path / "three.npz", X, y)
    argv = ["segment", str(path), "--n-motions", "auto"]
    rows = summary(elapsed_and_output(capsys, argv)[1])
    # the counting pipeline: unwhitened rank min(20, 2F, P) = 12, segmented
    # in its leading 5 directions
    reference = make_pipeline(
        PowerFactorization(12, whiten=False, random_state=0),
        GPCAClustering("auto", segmentation_dim=5, max_clusters=5, random_state=0),
    ).fit(X)[-1]
    bits = reference.n_clusters_costs_
    chosen = ", ".join(f"{n}: {b:.0f}" for n, b in enumerate(bits, 1) if np.isfinite(b))
    assert rows["motions"] == (
        f"{reference.n_clusters_} (auto, coding length in bits: {chosen})"
    )


def test_sizes_count_trailing_empty_motions(tmp_path, capsys, monkeypatch):
    import sklearn_gpca._cli as cli

    X, y = make_motions(2, n_points=[10, 10], n_frames=4, random_state=0)
    path = write_npz(tmp_path / "tracks.npz", X, y)
    real_fit = cli._fit
    labels = np.r_[np.zeros(12, dtype=int), np.ones(8, dtype=int)]

    def fit_with_empty_third(*args, **kwargs):
        pipeline, _ = real_fit(*args, **kwargs)
        pipeline[-1].n_clusters_ = 3
        return pipeline, labels

    monkeypatch.setattr(cli, "_fit", fit_with_empty_third)
    argv = ["segment", str(path), "--n-motions", "2", "--rank", "4"]
    assert summary(elapsed_and_output(capsys, argv)[1])["sizes"] == "12 8 0"


def test_parser_defaults_and_choices(capsys):
    parser = build_parser("prog")
    demo = parser.parse_args(["demo"])
    # three motions, a fifth of the entries occluded (docs/command_line.rst)
    assert (demo.n_motions, demo.missing, demo.missing_pattern) == (3, 0.2, "occlusion")
    assert (demo.n_points, demo.n_frames, demo.noise, demo.random_state) == (
        100,
        10,
        1.0,
        0,
    )
    segment = parser.parse_args(["segment", "f.npz", "--n-motions", "2"])
    # --rank unset reads as 5 (the paper's) with --method pipeline, the default
    assert (segment.rank, segment.method, segment.seed, segment.force) == (
        None,
        "pipeline",
        0,
        False,
    )
    assert segment.outlier_threshold is None
    assert (segment.output, segment.plot) == (None, None)
    given = parser.parse_args(
        ["demo", "--noise", "0", "--missing", "0", "--random-state", "7"]
    )
    assert (given.noise, given.missing, given.random_state) == (0.0, 0.0, 7)
    smallest = parser.parse_args(["demo", "--n-points", "1", "--n-frames", "3"])
    assert (smallest.n_points, smallest.n_frames) == (1, 3)
    for pattern in ["random", "occlusion"]:
        args = parser.parse_args(["demo", "--missing-pattern", pattern])
        assert args.missing_pattern == pattern


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        ([], "the following arguments are required: command"),
        (["demo", "--missing-pattern", "bursts"], "invalid choice: 'bursts'"),
        (["demo", "--noise", "loud"], "--noise: must be a number, got 'loud'"),
        (["demo", "--n-points", "1.5"], "--n-points: must be an integer, got '1.5'"),
    ],
)
def test_more_bad_arguments_get_one_line(capsys, argv, message):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1
    assert message in lines[0], lines[0]


def test_main_reads_sys_argv_by_default(tmp_path, capsys, monkeypatch):
    absent = tmp_path / "absent.npz"
    argv = ["/usr/bin/sklearn-gpca", "segment", str(absent), "--n-motions", "2"]
    monkeypatch.setattr(sys, "argv", argv)
    assert main() == 2
    assert (
        capsys.readouterr().err
        == f"sklearn-gpca segment: error: {absent}: no such file\n"
    )


@pytest.mark.parametrize(
    "missing, method, noted",
    [(0.5, "pipeline", True), (0.5, "tracks", False), (0.0, "pipeline", False)],
)
def test_segment_suggests_tracks_method_for_tracker_output(
    tmp_path, capsys, missing, method, noted
):
    X, y = make_motions(2, n_points=[60, 40], n_frames=8, random_state=0)
    if missing:
        X = make_missing(X, missing, random_state=0)
    path = write_npz(tmp_path / "tracks.npz", X, y)
    status = main(["segment", str(path), "--n-motions", "2", "--method", method])
    assert status == 0
    err = capsys.readouterr().err
    assert ("--method tracks segments better" in err) == noted
    if noted:
        assert "note: 50 % of the entries are missing" in err
