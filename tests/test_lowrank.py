"""Tests for the low-rank matrix benchmark loader."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
import scipy.io
import scipy.sparse
from numpy.testing import assert_array_equal

from sklearn_gpca.datasets import load_lowrank


def write_mat(path, **arrays):
    path.parent.mkdir(parents=True, exist_ok=True)
    scipy.io.savemat(path, arrays)
    return path


def test_tracks_layout(tmp_path):
    # 2 frames x 3 points, point 1 missing in frame 2.
    M = np.arange(12, dtype=float).reshape(4, 3)
    W = np.ones((4, 3), dtype=np.uint8)
    W[2:, 1] = 0
    M[2:, 1] = -999.0
    write_mat(tmp_path / "lowrank" / "Toy" / "toy.mat", M=M, W=W)
    data = load_lowrank("toy", data_home=tmp_path)
    assert data.layout == "tracks"
    assert (data.name, data.n_frames) == ("toy", 2)
    assert data.X.shape == (3, 4)
    assert_array_equal(data.mask, W.T.astype(bool))
    assert_array_equal(data.X[0], M[:, 0])
    assert_array_equal(np.isnan(data.X), ~data.mask)
    assert np.isnan(data.X[1, 2:]).all()


def test_sparse_arrays_and_direct_path(tmp_path):
    M = np.arange(1.0, 13.0).reshape(4, 3)
    W = np.ones((4, 3))
    path = write_mat(
        tmp_path / "s.mat", M=scipy.sparse.csc_matrix(M), W=scipy.sparse.csc_matrix(W)
    )
    data = load_lowrank(path)
    assert_array_equal(data.X, M.T)
    assert data.mask.all()
    assert load_lowrank(str(path)).name == "s"


def test_nonfinite_observed_entries_are_missing(tmp_path):
    M = np.ones((4, 3))
    M[0, 0] = M[1, 0] = np.nan
    path = write_mat(tmp_path / "n.mat", M=M, W=np.ones((4, 3)))
    data = load_lowrank(path)
    assert not data.mask[0, 0] and not data.mask[0, 1]
    assert data.mask.sum() == 10


def test_transposed_and_matrix_layouts(tmp_path):
    # Points as rows [x_1, y_1, x_2, y_2, x_3, y_3], one point unseen in frame 1.
    M = np.arange(30.0).reshape(5, 6)
    W = np.ones((5, 6))
    W[0, :2] = 0
    data = load_lowrank(write_mat(tmp_path / "t.mat", M=M, W=W))
    assert data.layout == "tracks_transposed"
    assert data.n_frames == 3
    assert_array_equal(data.X[1:], M[1:])
    assert np.isnan(data.X[0, :2]).all()
    # No x/y pairing in the mask: a generic matrix, one column per row of M.
    W = np.ones((5, 6))
    W[0, 0] = W[1, 3] = 0
    data = load_lowrank(write_mat(tmp_path / "m.mat", M=M, W=W))
    assert data.layout == "matrix"
    assert data.n_frames is None
    assert data.X.shape == (6, 5)


@pytest.mark.parametrize(
    ("arrays", "match"),
    [
        (dict(M=np.ones((4, 3))), "missing variable 'W'"),
        (dict(W=np.ones((4, 3))), "missing variable 'M'"),
        (dict(M=np.ones((4, 3)), W=np.ones((4, 2))), "same shape"),
    ],
)
def test_malformed_file(tmp_path, arrays, match):
    path = write_mat(tmp_path / "bad.mat", **arrays)
    with pytest.raises(ValueError, match=match) as excinfo:
        load_lowrank(path)
    assert "bad.mat" in str(excinfo.value)


def test_wrong_names_and_paths(tmp_path):
    with pytest.raises(FileNotFoundError, match=r"No such \.mat file"):
        load_lowrank(tmp_path / "missing.mat")
    with pytest.raises(FileNotFoundError, match="No low-rank datasets"):
        load_lowrank("Dino", data_home=tmp_path / "nowhere")
    write_mat(tmp_path / "Toy" / "toy.mat", M=np.ones((2, 2)), W=np.ones((2, 2)))
    with pytest.raises(ValueError, match=r"Unknown low-rank dataset 'Dino'.*'Toy'"):
        load_lowrank("Dino", data_home=tmp_path)


# --- the real matrices (skipped when ../shared/data is absent) -----------


@pytest.mark.parametrize(
    ("name", "shape", "layout", "n_frames", "observed"),
    [
        ("Dino_trimmed", (319, 72), "tracks", 36, 0.2308),
        ("dino_trimmed", (319, 72), "tracks", 36, 0.2308),
        ("Um_boy", (1760, 110), "tracks", 55, 0.1441),
        ("Giraffe", (166, 240), "tracks_transposed", 120, 0.6976),
        ("Face", (2944, 20), "matrix", None, 0.5828),
    ],
)
def test_real_matrices(shared_data_dir, name, shape, layout, n_frames, observed):
    data = load_lowrank(name, data_home=shared_data_dir)
    assert data.X.shape == shape
    assert (data.layout, data.n_frames) == (layout, n_frames)
    assert data.mask.mean() == pytest.approx(observed, abs=1e-4)
    assert_array_equal(np.isnan(data.X), ~data.mask)
    if layout != "matrix":
        # Both coordinates of a point go missing together.
        assert_array_equal(data.mask[:, 0::2], data.mask[:, 1::2])
        # Tracks are smooth: consecutive frames move by a few pixels.
        steps = np.abs(data.X[:, 2:] - data.X[:, :-2])
        assert np.nanmedian(steps) < 10


def test_real_dino_from_lowrank_dir(lowrank_dir):
    data = load_lowrank(lowrank_dir / "Dino_trimmed" / "dino_trimmed.mat")
    assert data.name == "dino_trimmed"
    assert data.X.shape == (319, 72)
    assert load_lowrank("Dino_trimmed", data_home=lowrank_dir).X.shape == (319, 72)


def test_folder_without_a_mat_file_says_so(tmp_path):
    (tmp_path / "Toy").mkdir()
    (tmp_path / "Toy" / "readme.txt").write_text("no data here")
    with pytest.raises(FileNotFoundError, match=r"Toy holds no \.mat file"):
        load_lowrank("Toy", data_home=tmp_path)


def test_folder_with_several_mat_files_says_so(tmp_path):
    write_mat(tmp_path / "Toy" / "a.mat", M=np.ones((2, 2)), W=np.ones((2, 2)))
    write_mat(tmp_path / "Toy" / "b.mat", M=np.ones((2, 2)), W=np.ones((2, 2)))
    with pytest.raises(ValueError, match=r"several \.mat files.*a\.mat.*b\.mat"):
        load_lowrank("toy", data_home=tmp_path)


def test_upper_case_mat_path_is_a_path(tmp_path):
    M = np.arange(1.0, 13.0).reshape(4, 3)
    path = write_mat(tmp_path / "UPPER.MAT", M=M, W=np.ones((4, 3)))
    data = load_lowrank(path)
    assert_array_equal(data.X, M.T)
    assert data.name == "UPPER"
    with pytest.raises(FileNotFoundError, match=r"No such \.mat file"):
        load_lowrank(tmp_path / "ABSENT.MAT")


def test_failed_load_creates_no_data_home(tmp_path, monkeypatch):
    home = tmp_path / "home"
    monkeypatch.delenv("SKLEARN_GPCA_DATA", raising=False)
    monkeypatch.delenv("SCIKIT_LEARN_DATA", raising=False)
    monkeypatch.setenv("HOME", str(home))
    with pytest.raises(FileNotFoundError, match="scikit_learn_data"):
        load_lowrank("Dino")
    assert not home.exists()
