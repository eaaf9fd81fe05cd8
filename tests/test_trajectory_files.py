"""Tests of the command line's trajectory files: readers and atomic writes.

Each test pins a behaviour that a mutation run of ``_trajectory_files.py``
found unchecked (benchmarks/results/mutation.md).
"""

# SPDX-License-Identifier: BSD-3-Clause

import os
import re
import zipfile
from pathlib import Path

import numpy as np
import pytest
import scipy.io

from sklearn_gpca._trajectory_files import (
    UsageError,
    read_trajectories,
    same_file,
    write_atomically,
)
from sklearn_gpca.datasets import make_motions


@pytest.fixture(scope="module")
def complete():
    """Two motions, 10 points each, 4 frames, no entry missing."""
    return make_motions(2, n_points=[10, 10], n_frames=4, random_state=0)


def points_of(X):
    """Hopkins155 layout (3, P, F) of ``X``: x, y and a homogeneous 1."""
    n_points, n_frames = X.shape[0], X.shape[1] // 2
    points = X.reshape(n_points, n_frames, 2).transpose(2, 0, 1)
    return np.concatenate([points, np.ones((1, n_points, n_frames))])


def csv_text(X, labels=None, header=None):
    lines = [] if header is None else [",".join(header)]
    for i, row in enumerate(X):
        cells = ["" if np.isnan(v) else repr(float(v)) for v in row]
        if labels is not None:
            cells.append(str(labels[i]))
        lines.append(",".join(cells))
    return "\n".join(lines) + "\n"


def message_of(path):
    with pytest.raises(UsageError) as exc:
        read_trajectories(path)
    return str(exc.value)


# --- write_atomically -------------------------------------------------------


def test_temporary_file_is_a_hidden_sibling_renamed_onto_the_target(tmp_path):
    target = tmp_path / "labels.txt"
    seen = []

    def write(tmp):
        seen.append(Path(tmp))
        Path(tmp).write_text("1\n2\n")

    write_atomically(target, write)
    (tmp,) = seen
    # same folder, hence the same file system: os.replace is a rename
    assert tmp.parent == target.parent
    assert tmp.name.startswith(".labels.") and tmp.suffix == ".txt"
    assert not tmp.exists()
    assert target.read_text() == "1\n2\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["labels.txt"]


@pytest.mark.parametrize("umask", [0o022, 0o027, 0o077, 0o002])
def test_written_file_mode_follows_the_umask(tmp_path, umask):
    old = os.umask(umask)
    try:
        write_atomically(tmp_path / "out.txt", lambda tmp: Path(tmp).write_text("0\n"))
        # what open() would have given: 0o666 without the umask's bits
        reference = tmp_path / "reference.txt"
        reference.write_text("0\n")
    finally:
        os.umask(old)
    mode = (tmp_path / "out.txt").stat().st_mode & 0o777
    assert mode == 0o666 & ~umask
    assert mode == reference.stat().st_mode & 0o777


def test_failed_write_leaves_the_target_and_raises_its_own_error(tmp_path):
    target = tmp_path / "labels.txt"
    target.write_text("precious\n")

    def write_then_fail(tmp):
        Path(tmp).write_text("half")
        raise OSError("No space left on device")

    with pytest.raises(OSError, match="No space left on device"):
        write_atomically(target, write_then_fail)
    assert target.read_text() == "precious\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["labels.txt"]


def test_writer_that_removed_its_file_still_reports_its_own_error(tmp_path):
    """A writer may delete its partial output before failing: its error, not
    a FileNotFoundError of the clean-up, reaches the caller."""

    def remove_then_fail(tmp):
        Path(tmp).unlink()
        raise ValueError("unsupported format")

    with pytest.raises(ValueError, match="unsupported format"):
        write_atomically(tmp_path / "plot.png", remove_then_fail)
    assert list(tmp_path.iterdir()) == []


def test_same_file_is_false_when_the_files_cannot_be_compared(tmp_path, monkeypatch):
    a = tmp_path / "a.txt"
    a.write_text("a")
    assert same_file(a, a)

    def unreadable(*args):
        raise PermissionError("permission denied")

    monkeypatch.setattr(os.path, "samefile", unreadable)
    assert not same_file(a, a)


# --- .npz -------------------------------------------------------------------


def test_npz_listing_names_the_arrays_found(tmp_path):
    path = tmp_path / "t.npz"
    with zipfile.ZipFile(path, "w") as zf:
        zf.writestr("b.npy", b"")
        zf.writestr("a.npy", b"")
    assert message_of(path) == f"{path}: no array 'X' in the .npz file (found a, b)"


def test_npz_of_other_bytes_says_what_an_npz_is(tmp_path):
    path = tmp_path / "t.npz"
    path.write_bytes(b"not a zip file")
    assert message_of(path) == (
        f"{path}: not a .npz archive (a zip of .npy arrays, as written by numpy.savez)"
    )


def test_npz_object_array_is_never_unpickled(tmp_path):
    X = np.empty((4, 6), dtype=object)
    X[:] = 1.0
    path = tmp_path / "t.npz"
    np.savez(path, X=X)
    message = message_of(path)
    assert message.startswith(f"{path}: cannot read as .npz (")
    assert "allow_pickle=False" in message


# --- .mat -------------------------------------------------------------------


def test_mat_listing_names_the_fields_found(tmp_path, complete):
    path = tmp_path / "t.mat"
    scipy.io.savemat(path, {"z": complete[0], "w": complete[1]})
    assert message_of(path) == (
        f"{path}: no field 'x' or 'y' (3 x points x frames) in the .mat file "
        "(found w, z)"
    )


def test_mat_without_any_field_says_so(tmp_path):
    path = tmp_path / "t.mat"
    scipy.io.savemat(path, {})
    assert message_of(path).endswith("in the .mat file (found nothing)")


def test_mat_prefers_x_over_y(tmp_path, complete):
    X, _ = complete
    path = tmp_path / "t.mat"
    scipy.io.savemat(path, {"x": points_of(X), "y": points_of(2 * X)})
    np.testing.assert_array_equal(read_trajectories(path)[0], X)


def test_mat_of_two_coordinate_rows_is_read(tmp_path, complete):
    X, y = complete
    path = tmp_path / "t.mat"
    scipy.io.savemat(path, {"x": points_of(X)[:2], "s": y + 1})
    X_read, y_read = read_trajectories(path)
    np.testing.assert_array_equal(X_read, X)
    np.testing.assert_array_equal(y_read, y + 1)


@pytest.mark.parametrize(
    ("field", "message"),
    [
        (
            np.zeros((3, 10)),
            "field 'x' must have shape (3, points, frames), got (3, 10)",
        ),
        (np.zeros((4, 5, 3)), "field 'x' must have shape (3, points, frames), got "),
        (np.array(["ab", "cd"]), "field 'x' must be numeric, got <U2"),
    ],
    ids=["2-d", "4-rows", "strings"],
)
def test_mat_bad_point_field_is_named(tmp_path, field, message):
    path = tmp_path / "t.mat"
    scipy.io.savemat(path, {"x": field})
    assert message_of(path).startswith(f"{path}: {message}")


def test_mat_label_count_is_checked(tmp_path, complete):
    X, y = complete
    path = tmp_path / "t.mat"
    scipy.io.savemat(path, {"x": points_of(X), "s": y[:-1]})
    assert message_of(path) == f"{path}: field 's' holds 19 labels for 20 points"


def test_unreadable_mat_is_named(tmp_path):
    path = tmp_path / "t.mat"
    path.write_bytes(b"MATLAB 5.0 MAT-file" + bytes(200))
    assert message_of(path).startswith(f"{path}: cannot read as .mat (")


# --- .csv -------------------------------------------------------------------


def test_csv_lines_of_spaces_are_blank(tmp_path, complete):
    X, _ = complete
    path = tmp_path / "t.csv"
    body = csv_text(X).splitlines()
    body.insert(3, "   ")
    path.write_text("  \n" + "\n".join(body) + "\n \t \n")
    np.testing.assert_array_equal(read_trajectories(path)[0], X)


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (b"", "the file holds no trajectories"),
        (b"\n  \n", "the file holds no trajectories"),
        (b"x,y,x,y,x,y\n", "the file holds a header and no trajectories"),
        ("1,2,3,4,5,é\n".encode("latin-1"), "not UTF-8 text (invalid"),
        (b'"' + b"1" * 200_000 + b'",2\n', "cannot read as .csv (field larger"),
    ],
    ids=["empty", "blank", "header-only", "latin-1", "huge-field"],
)
def test_csv_unreadable_files_are_named(tmp_path, content, message):
    path = tmp_path / "t.csv"
    path.write_bytes(content)
    assert message_of(path).startswith(f"{path}: {message}")


def test_csv_several_label_columns_are_named(tmp_path, complete):
    X, y = complete
    header = ["Label"] + ["x", "y"] * 3 + [" s "]
    path = tmp_path / "t.csv"
    path.write_text(csv_text(np.column_stack([y, X[:, 1:]]), header=header))
    assert message_of(path) == f"{path}: several label columns ('Label', 's'); keep one"


@pytest.mark.parametrize(
    ("empty_rows", "suffix"),
    [([1], ""), ([1, 4], " and 1 more"), ([1, 4, 5], " and 2 more")],
)
def test_csv_empty_labels_are_counted(tmp_path, complete, empty_rows, suffix):
    X, y = complete
    labels = [str(v) for v in y]
    for i in empty_rows:
        labels[i] = "NA"
    path = tmp_path / "t.csv"
    path.write_text(csv_text(X, labels=labels, header=["x", "y"] * 4 + ["label"]))
    # row i is on line i + 2, after the header
    first = empty_rows[0] + 2
    assert message_of(path) == (
        f"{path}: label column 'label' is empty on line {first}{suffix}"
    )


@pytest.mark.parametrize(
    ("cells", "expected"),
    [
        (["1", "2"], np.array([1, 2])),
        (["1.0", "2.0"], np.array([1, 2])),
        (["0.5", "2"], np.array(["0.5", "2"])),
        (["car", "2"], np.array(["car", "2"])),
    ],
    ids=["integers", "integral-floats", "fractions", "names"],
)
def test_csv_labels_are_integers_when_integral_else_names(
    tmp_path, complete, cells, expected
):
    X, _ = complete
    labels = [cells[i % 2] for i in range(X.shape[0])]
    path = tmp_path / "t.csv"
    path.write_text(csv_text(X, labels=labels, header=["x", "y"] * 4 + ["truth"]))
    _, y_read = read_trajectories(path)
    assert y_read.dtype.kind == expected.dtype.kind
    np.testing.assert_array_equal(y_read, expected[np.arange(X.shape[0]) % 2])


@pytest.mark.parametrize(
    ("lines", "message"),
    [
        # a first row that is neither numbers only nor names only
        (
            ["1,2,x,4,5,6"],
            "line 1: cell 3 ('x') is not a number; a header row must hold names only",
        ),
        # the same cell further down: no word about headers
        (
            ["1,2,3,4,5,6", "1,2,3,4,5,6", "1,2,x,4,5,6"],
            "line 3: cell 3 ('x') is not a number",
        ),
        # a header, then a bad cell on the first data line
        (["a,b,c,d,e,f", "1,2,x,4,5,6"], "line 2: cell 3 ('x') is not a number"),
    ],
    ids=["first-row", "third-row", "after-header"],
)
def test_csv_bad_cell_hint_only_for_a_first_row(tmp_path, lines, message):
    path = tmp_path / "t.csv"
    path.write_text("\n".join([*lines, "1,2,3,4,5,6"]) + "\n")
    assert message_of(path) == f"{path}, {message}"


# --- checks common to every format ------------------------------------------


def test_directory_and_unknown_formats_are_named(tmp_path):
    folder = tmp_path / "tracks.npz"
    folder.mkdir()
    assert message_of(folder) == f"{folder}: is a directory, not a trajectory file"
    expected = "expected one of .npz, .csv, .mat, .dat"
    for name, shown in [("t.txt", "'.txt'"), ("tracks", "'(no extension)'")]:
        path = tmp_path / name
        path.write_text("1,2\n")
        assert message_of(path) == f"{path}: unknown format {shown}; {expected}"


def write_npz(path, **arrays):
    np.savez(path, **arrays)
    return path


def test_non_numeric_x_is_named(tmp_path):
    path = write_npz(tmp_path / "t.npz", X=np.full((4, 6), "a"))
    assert message_of(path) == f"{path}: X must be numeric, got dtype <U1"


def test_odd_columns_hint_at_a_label_column_only_for_csv(tmp_path, complete):
    X, _ = complete
    path = write_npz(tmp_path / "t.npz", X=X[:, :-1])
    assert message_of(path) == (
        f"{path}: X has an odd number of columns (7); rows must be "
        "[x_1, y_1, ..., x_F, y_F]"
    )


def test_odd_csv_columns_suggest_a_label_column(tmp_path, complete):
    X, _ = complete
    path = tmp_path / "t.csv"
    path.write_text(csv_text(X[:, :-1]))
    assert message_of(path) == (
        f"{path}: X has an odd number of columns (7); rows must be "
        "[x_1, y_1, ..., x_F, y_F]; name a label column in a header row (label, "
        "labels, s, y_true, ...)"
    )


def test_frame_and_trajectory_counts_at_the_limits(tmp_path, complete):
    X, _ = complete
    # three frames and two trajectories are enough
    path = write_npz(tmp_path / "three.npz", X=X[:2, :6])
    assert read_trajectories(path)[0].shape == (2, 6)
    path = write_npz(tmp_path / "two_frames.npz", X=X[:, :4])
    assert message_of(path) == f"{path}: 2 frames; at least 3 are needed"
    path = write_npz(tmp_path / "one.npz", X=X[:1])
    assert message_of(path) == f"{path}: 1 trajectories; at least 2 are needed"


@pytest.mark.parametrize(
    ("value", "message"),
    [
        (np.inf, "X holds infinite values"),
        (np.nan, "every entry is missing"),
        (
            1e151,
            "coordinates as large as 1e+151 exceed 1e+150 and overflow float64 "
            "arithmetic; rescale them (the segmentation does not depend on the unit)",
        ),
    ],
)
def test_unusable_values_are_named(tmp_path, value, message):
    path = write_npz(tmp_path / "t.npz", X=np.full((4, 6), value))
    assert message_of(path).startswith(f"{path}: {message}")


@pytest.mark.parametrize("largest", [1e150, 1e-150])
def test_magnitude_limits_are_inclusive(tmp_path, largest):
    X = np.full((4, 6), largest)
    X[0, 0] = -largest
    X[1, :] = largest / 2
    path = write_npz(tmp_path / "t.npz", X=X)
    np.testing.assert_array_equal(read_trajectories(path)[0], X)


def test_column_of_labels_is_flattened(tmp_path, complete):
    X, y = complete
    path = write_npz(tmp_path / "t.npz", X=X, y=y.reshape(-1, 1))
    y_read = read_trajectories(path)[1]
    assert y_read.shape == (20,)
    np.testing.assert_array_equal(y_read, y)


@pytest.mark.parametrize(
    ("shape", "message"),
    [((19,), r"y of shape \(19,\)"), ((2, 20), r"y of shape \(2, 20\)")],
)
def test_labels_of_the_wrong_shape_are_refused(tmp_path, complete, shape, message):
    X, _ = complete
    path = write_npz(tmp_path / "t.npz", X=X, y=np.zeros(shape, dtype=int))
    assert re.fullmatch(
        rf"{re.escape(str(path))}: {message} does not hold one label for each of "
        r"the 20 points",
        message_of(path),
    )


def test_missing_labels_are_refused(tmp_path, complete):
    X, y = complete
    labels = y.astype(float)
    labels[3] = np.nan
    path = write_npz(tmp_path / "t.npz", X=X, y=labels)
    assert message_of(path) == f"{path}: y holds missing labels (NaN)"
