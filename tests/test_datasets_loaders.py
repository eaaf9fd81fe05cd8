"""Messages and fall-backs of the real-data loaders, to the letter."""

# SPDX-License-Identifier: BSD-3-Clause

import re
from pathlib import Path

import numpy as np
import pytest
import scipy.io
from numpy.testing import assert_array_equal

from sklearn_gpca.datasets import load_hopkins155, load_lowrank
from sklearn_gpca.datasets._home import default_data_home
from sklearn_gpca.datasets._hopkins155 import HOPKINS155_URL


def write_mat(path, **arrays):
    path.parent.mkdir(parents=True, exist_ok=True)
    scipy.io.savemat(path, arrays)
    return path


def test_data_home_falls_back_to_scikit_learn_s(tmp_path, monkeypatch):
    """``$SKLEARN_GPCA_DATA``, else ``$SCIKIT_LEARN_DATA``, else
    ``~/scikit_learn_data`` (as :func:`sklearn.datasets.get_data_home`)."""
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    monkeypatch.delenv("SKLEARN_GPCA_DATA", raising=False)
    monkeypatch.delenv("SCIKIT_LEARN_DATA", raising=False)
    assert default_data_home() == tmp_path / "home" / "scikit_learn_data"
    monkeypatch.setenv("SCIKIT_LEARN_DATA", str(tmp_path / "sk"))
    assert default_data_home() == tmp_path / "sk"
    monkeypatch.setenv("SKLEARN_GPCA_DATA", str(tmp_path / "ours"))
    assert default_data_home() == tmp_path / "ours"
    assert not any(tmp_path.iterdir())  # nothing created


def test_hopkins155_not_found_message(tmp_path):
    base = tmp_path / "nowhere"
    message = (
        f"No Hopkins155 sequences (<name>/<name>_truth.mat) found in {base} or "
        f"{base / 'hopkins155'}. Download them with "
        "sklearn_gpca.datasets.fetch_hopkins155(data_home=...), or get "
        f"{HOPKINS155_URL} and extract it there."
    )
    with pytest.raises(FileNotFoundError, match=f"^{re.escape(message)}$"):
        load_hopkins155(base)


def test_lowrank_folder_file_named_after_the_folder_wins(tmp_path):
    """``<Name>/<name>.mat`` is read even beside other .mat files."""
    M = np.arange(1.0, 13.0).reshape(4, 3)
    write_mat(tmp_path / "Toy" / "toy.mat", M=M, W=np.ones((4, 3)))
    write_mat(tmp_path / "Toy" / "other.mat", M=2 * M, W=np.ones((4, 3)))
    assert_array_equal(load_lowrank("Toy", data_home=tmp_path).X, M.T)


def test_lowrank_folder_with_one_mat_file_of_another_name(tmp_path):
    M = np.arange(1.0, 13.0).reshape(4, 3)
    write_mat(tmp_path / "Toy" / "data.mat", M=M, W=np.ones((4, 3)))
    assert_array_equal(load_lowrank("toy", data_home=tmp_path).X, M.T)


def test_lowrank_messages(tmp_path):
    home = tmp_path / "nowhere"
    message = (
        f"No low-rank datasets (<Name>/<name>.mat) found in {home}; "
        "pass data_home or set SKLEARN_GPCA_DATA."
    )
    with pytest.raises(FileNotFoundError, match=f"^{re.escape(message)}$"):
        load_lowrank("Dino", data_home=home)
    write_mat(tmp_path / "Toy" / "a.mat", M=np.ones((2, 2)), W=np.ones((2, 2)))
    write_mat(tmp_path / "Toy" / "b.mat", M=np.ones((2, 2)), W=np.ones((2, 2)))
    message = (
        f"{tmp_path / 'Toy'} holds several .mat files (a.mat, b.mat); "
        "pass the path of one of them."
    )
    with pytest.raises(ValueError, match=f"^{re.escape(message)}$"):
        load_lowrank("toy", data_home=tmp_path)


def test_lowrank_malformed_file_messages(tmp_path):
    path = write_mat(tmp_path / "bad.mat", M=np.ones((4, 3)), X=np.ones(2))
    message = (
        f"Malformed low-rank file {path}: missing variable 'W' (found ['M', 'X'])."
    )
    with pytest.raises(ValueError, match=f"^{re.escape(message)}$"):
        load_lowrank(path)
    path = write_mat(tmp_path / "cube.mat", M=np.ones((2, 2, 2)), W=np.ones((4, 3)))
    message = (
        f"Malformed low-rank file {path}: 'M' must be a matrix, got shape (2, 2, 2)."
    )
    with pytest.raises(ValueError, match=f"^{re.escape(message)}$"):
        load_lowrank(path)


def test_lowrank_transposed_layout_on_two_frames(tmp_path):
    """Points as rows ``[x_1, y_1, x_2, y_2]`` (4 columns, an odd number of
    rows): the mask pairs the columns, so the layout is ``tracks_transposed``."""
    M = np.arange(20.0).reshape(5, 4)
    W = np.ones((5, 4))
    W[0, 2:] = 0
    data = load_lowrank(write_mat(tmp_path / "t.mat", M=M, W=W))
    assert data.layout == "tracks_transposed"
    assert data.n_frames == 2
    assert np.isnan(data.X[0, 2:]).all()
    assert_array_equal(data.X[1:], M[1:])


def test_failed_lowrank_load_names_scikit_learn_s_home(tmp_path, monkeypatch):
    monkeypatch.delenv("SKLEARN_GPCA_DATA", raising=False)
    monkeypatch.delenv("SCIKIT_LEARN_DATA", raising=False)
    monkeypatch.setenv("HOME", str(tmp_path))
    with pytest.raises(FileNotFoundError) as excinfo:
        load_lowrank("Dino")
    assert str(Path(tmp_path) / "scikit_learn_data") in str(excinfo.value)


def write_sequence(folder, name, **overrides):
    """A tiny Hopkins155-style ``<name>/<name>_truth.mat`` (6 points, 4
    frames, 2 motions); an override of None leaves the variable out."""
    y = np.ones((3, 6, 4))
    y[:2] = np.random.RandomState(0).uniform(0, 640, size=(2, 6, 4))
    data = dict(x=y.copy(), y=y, s=np.array([[1], [2]] * 3, dtype=np.uint8))
    data.update(overrides)
    data = {k: v for k, v in data.items() if v is not None}
    return write_mat(folder / name / f"{name}_truth.mat", **data)


def test_hopkins155_messages_name_the_file(tmp_path):
    path = write_sequence(tmp_path, "seq1", y=None)
    message = (
        f"Malformed Hopkins155 file {path}: missing variable 'y' (found ['s', 'x'])."
    )
    with pytest.raises(ValueError, match=f"^{re.escape(message)}$"):
        load_hopkins155(tmp_path)
    # filtering by the number of motions reads ``s`` first
    path = write_sequence(tmp_path / "b", "seq2", s=None)
    message = f"Malformed Hopkins155 file {path}: missing variable 's'."
    with pytest.raises(ValueError, match=f"^{re.escape(message)}$"):
        load_hopkins155(tmp_path / "b", n_motions=2)
    path = tmp_path / "c" / "seq3" / "seq3_truth.mat"
    path.parent.mkdir(parents=True)
    path.write_bytes(b"not a mat file")
    message = f"Could not read Hopkins155 file {path}: "
    with pytest.raises(ValueError, match=f"^{re.escape(message)}.+"):
        load_hopkins155(tmp_path / "c", n_motions=2)


def test_hopkins155_capitalised_folder_is_found(tmp_path):
    write_sequence(tmp_path / "Hopkins155", "seq1")
    (data,) = load_hopkins155(tmp_path)
    assert data.name == "seq1"


@pytest.mark.parametrize(
    ("overrides", "problem"),
    [
        (dict(bad_x=1), "'x' holds 1 NaN or infinite value; Hopkins155 trajectories"),
        (dict(bad_y=2), "'y' holds 2 NaN or infinite values; Hopkins155 trajectories"),
        (
            dict(s=np.array([[1.0], [1.5]] * 3)),
            "'s' holds 1.5; labels must be integers.",
        ),
        (
            dict(s=np.array([[0], [1]] * 3)),
            "'s' must hold 6 labels numbered from 1, got shape (6, 1) and minimum 0.",
        ),
        (
            dict(s=np.array([[2], [3], [2], [3], [2]])),
            "'s' must hold 6 labels numbered from 1, got shape (5, 1) and minimum 2.",
        ),
    ],
)
def test_hopkins155_bad_values_are_named(tmp_path, overrides, problem):
    y = np.ones((3, 6, 4))
    y[:2] = np.random.RandomState(0).uniform(0, 640, size=(2, 6, 4))
    x = y.copy()
    x[0, 0, : overrides.pop("bad_x", 0)] = np.nan
    y[1, 1, : overrides.pop("bad_y", 0)] = np.inf
    path = write_sequence(tmp_path, "seq1", x=x, y=y, **overrides)
    if "trajectories" in problem:
        problem += " are complete."
    message = f"Malformed Hopkins155 file {path}: {problem}"
    with pytest.raises(ValueError, match=f"^{re.escape(message)}$"):
        load_hopkins155(tmp_path)


def test_hopkins155_types_and_the_homogeneous_row(tmp_path):
    """Integer coordinates are read as float64, labels as integers; the third
    (homogeneous) row of ``x`` and ``y`` is not read, so NaN there is fine."""
    y = np.ones((3, 6, 4))
    y[:2] = np.arange(48).reshape(2, 6, 4)
    y[2, 0, 0] = np.nan
    write_sequence(tmp_path, "seq1", x=np.ones((3, 6, 4), dtype=np.int64), y=y)
    (data,) = load_hopkins155(tmp_path)
    assert data.X.dtype == np.float64 and data.X_pixels.dtype == np.float64
    assert data.y.dtype.kind == "i"
    assert_array_equal(data.y, [0, 1] * 3)
    assert np.isfinite(data.X_pixels).all()


def test_hopkins155_unknown_sequence_lists_three_examples(tmp_path):
    for name in ("a1", "b2", "c3", "d4"):
        write_sequence(tmp_path, name)
    message = (
        f"Unknown Hopkins155 sequences ['zz'] (not in {tmp_path}); there are 4 "
        "sequences, e.g. ['a1', 'b2', 'c3']."
    )
    with pytest.raises(ValueError, match=f"^{re.escape(message)}$"):
        load_hopkins155(tmp_path, sequences=["zz"])
