"""Tests for the Hopkins155 loader and fetcher."""

# SPDX-License-Identifier: BSD-3-Clause

import collections
import types
import zipfile

import numpy as np
import pytest
import scipy.io
from numpy.testing import assert_allclose, assert_array_equal

import sklearn_gpca.datasets._hopkins155 as hopkins_module
from sklearn_gpca.datasets import (
    fetch_hopkins155,
    hopkins155_category,
    load_hopkins155,
)

FEW = ["1R2RC", "cars2B_g12", "kanatani3", "three-cars"]


def write_sequence(folder, name, n_points=6, n_frames=4, labels=None, **overrides):
    """Write a tiny Hopkins155-style ``<name>/<name>_truth.mat``."""
    rng = np.random.RandomState(0)
    y = np.ones((3, n_points, n_frames))
    y[:2] = rng.uniform(0, 640, size=(2, n_points, n_frames))
    x = y.copy()
    x[:2] = (y[:2] - 320) / 320
    if labels is None:
        labels = np.arange(n_points) % 2 + 1
    data = dict(
        x=x,
        y=y,
        s=np.asarray(labels, dtype=np.uint8).reshape(-1, 1),
        points=n_points,
        frames=n_frames,
        K=np.eye(3),
    )
    data.update(overrides)
    data = {k: v for k, v in data.items() if v is not None}
    (folder / name).mkdir(parents=True)
    scipy.io.savemat(folder / name / f"{name}_truth.mat", data)
    return x, y


@pytest.fixture
def fake_home(tmp_path):
    """A data home ``tmp_path`` with ``hopkins155/`` holding two sequences."""
    root = tmp_path / "hopkins155"
    write_sequence(root, "1R2RC")
    write_sequence(root, "cars1", labels=[1, 2, 3, 1, 2, 3])
    write_sequence(root, "dancing", labels=[1, 2, 3, 4, 5, 5])
    (root / "README.txt").write_text("not a sequence")
    (root / "cars1" / "cars1_other.mat").write_bytes(b"ignored")
    return tmp_path


@pytest.mark.parametrize(
    ("name", "category"),
    [
        ("1R2RC", "checkerboard"),
        ("2T3RTCR_g23", "checkerboard"),
        ("three-cars_g12", "checkerboard"),
        ("cars2_06_g13", "traffic"),
        ("truck2", "traffic"),
        ("kanatani1", "traffic"),
        ("kanatani2", "traffic"),
        ("kanatani3", "articulated"),
        ("people1", "articulated"),
        ("two_cranes_g12", "articulated"),
        ("arm", "articulated"),
        ("head", "articulated"),
        ("dancing", "articulated"),
        ("unrelated", None),
    ],
)
def test_category_rules(name, category):
    assert hopkins155_category(name) == category


def test_layout_and_labels_on_fake_data(fake_home):
    data = load_hopkins155(fake_home)
    assert [b.name for b in data] == ["1R2RC", "cars1"]
    x, y = write_sequence(fake_home / "other", "1R2RC")
    seq = data[0]
    assert seq.X.shape == (6, 8)
    assert seq.X.dtype == np.float64
    # Row p is [x_1, y_1, ..., x_F, y_F] from x[:2]; X_pixels from y[:2].
    assert_allclose(seq.X[2, 0::2], x[0, 2])
    assert_allclose(seq.X[2, 1::2], x[1, 2])
    assert_allclose(seq.X_pixels[3, 0::2], y[0, 3])
    assert_array_equal(seq.y, [0, 1, 0, 1, 0, 1])
    assert (seq.n_motions, seq.n_points, seq.n_frames) == (2, 6, 4)
    assert seq.category == "checkerboard"
    assert data[1].n_motions == 3
    assert data[1].category == "traffic"


def test_extra_sequence_and_filters(fake_home):
    names = [b.name for b in load_hopkins155(fake_home, include_extra=True)]
    assert names == ["1R2RC", "cars1", "dancing"]
    assert load_hopkins155(fake_home, sequences="dancing")[0].n_motions == 5
    assert [b.name for b in load_hopkins155(fake_home, n_motions=3)] == ["cars1"]
    assert [b.name for b in load_hopkins155(fake_home, n_motions=[2, 5])] == ["1R2RC"]
    assert [b.name for b in load_hopkins155(fake_home, category="traffic")] == ["cars1"]
    it = load_hopkins155(fake_home / "hopkins155", return_iterator=True)
    assert isinstance(it, types.GeneratorType)
    assert [b.name for b in it] == ["1R2RC", "cars1"]


def test_data_home_from_environment(fake_home, monkeypatch):
    monkeypatch.setenv("SKLEARN_GPCA_DATA", str(fake_home))
    assert len(load_hopkins155()) == 2


def test_wrong_path(tmp_path):
    with pytest.raises(FileNotFoundError, match="fetch_hopkins155") as excinfo:
        load_hopkins155(tmp_path / "nowhere")
    assert "nowhere" in str(excinfo.value)


def test_unknown_sequences(fake_home):
    with pytest.raises(ValueError, match=r"Unknown Hopkins155 sequences \['bogus'"):
        load_hopkins155(fake_home, sequences=["1R2RC", "bogus"])


def test_unknown_category(fake_home):
    with pytest.raises(ValueError, match="category"):
        load_hopkins155(fake_home, category="indoor")
    with pytest.raises(ValueError, match=r"Unknown categories \['indoor'\]"):
        load_hopkins155(fake_home, category=["traffic", "indoor"])


@pytest.mark.parametrize(
    ("overrides", "match"),
    [
        (dict(s=None), "missing variable 's'"),
        (dict(x=None), "missing variable 'x'"),
        (dict(x=np.zeros((3, 6))), "'x' must have 3 dimensions"),
        (dict(y=np.zeros((3, 5, 4))), r"shape \(3, n_points, n_frames\)"),
        (dict(s=np.zeros((6, 1))), "numbered from 1"),
        (dict(s=np.ones((4, 1))), "must hold 6 labels"),
    ],
)
def test_malformed_file(tmp_path, overrides, match):
    write_sequence(tmp_path, "bad", **overrides)
    with pytest.raises(ValueError, match=match) as excinfo:
        load_hopkins155(tmp_path)
    assert "bad_truth.mat" in str(excinfo.value)


def test_unreadable_file(tmp_path):
    (tmp_path / "junk").mkdir()
    (tmp_path / "junk" / "junk_truth.mat").write_bytes(b"not a mat file")
    with pytest.raises(ValueError, match="Could not read Hopkins155 file"):
        load_hopkins155(tmp_path)


def test_fetch_without_download(tmp_path, monkeypatch):
    def no_download(url, path):
        raise AssertionError("tests must never download")

    monkeypatch.setattr(hopkins_module, "_download", no_download)
    with pytest.raises(OSError, match="download_if_missing=False"):
        fetch_hopkins155(tmp_path, download_if_missing=False)


def test_fetch_present_data(fake_home, monkeypatch):
    def no_download(url, path):
        raise AssertionError("tests must never download")

    monkeypatch.setattr(hopkins_module, "_download", no_download)
    data = fetch_hopkins155(fake_home, download_if_missing=False)
    assert [b.name for b in data] == ["1R2RC", "cars1"]


def test_fetch_extracts_archive(tmp_path, monkeypatch):
    # A local stand-in for the archive: a top folder "Hopkins155/" holding
    # the sequence folders, like the official zip.
    source = tmp_path / "source"
    write_sequence(source / "Hopkins155", "2RT3RC")
    write_sequence(source / "Hopkins155", "truck1")
    calls = []

    def fake_download(url, path):
        calls.append(url)
        with zipfile.ZipFile(path, "w") as zf:
            for file in sorted(source.rglob("*")):
                zf.write(file, file.relative_to(source))

    monkeypatch.setattr(hopkins_module, "_download", fake_download)
    home = tmp_path / "home"
    data = fetch_hopkins155(home)
    assert calls == [hopkins_module.HOPKINS155_URL]
    assert [b.name for b in data] == ["2RT3RC", "truck1"]
    assert (home / "hopkins155" / "truck1" / "truck1_truth.mat").is_file()
    assert sorted(p.name for p in home.iterdir()) == ["hopkins155"]
    # Second call finds the data and does not download again.
    assert len(fetch_hopkins155(home)) == 2
    assert len(calls) == 1


# --- the real benchmark (skipped when ../shared/data is absent) ----------


def test_real_sequences(hopkins155_dir):
    data = load_hopkins155(hopkins155_dir, sequences=FEW)
    assert [b.name for b in data] == sorted(FEW)
    by_name = {b.name: b for b in data}
    seq = by_name["1R2RC"]
    assert seq.X.shape == (459, 58)
    assert (seq.n_points, seq.n_frames, seq.n_motions) == (459, 29, 3)
    assert seq.category == "checkerboard"
    for b in data:
        assert b.X.shape == (b.n_points, 2 * b.n_frames)
        assert b.X_pixels.shape == b.X.shape
        assert np.all(np.isfinite(b.X))
        assert_array_equal(np.unique(b.y), np.arange(b.n_motions))
        # Normalised coordinates lie in [-1, 1] (up to rounding), pixels not.
        assert np.abs(b.X).max() < 1.5
        assert np.abs(b.X_pixels).max() > 10
    assert by_name["cars2B_g12"].n_motions == 2
    assert by_name["kanatani3"].category == "articulated"


def test_real_labels_are_zero_based(hopkins155_dir):
    seq = load_hopkins155(hopkins155_dir, sequences="arm")[0]
    s = scipy.io.loadmat(hopkins155_dir / "arm" / "arm_truth.mat")["s"].ravel()
    assert_array_equal(seq.y, s.astype(int) - 1)
    x = scipy.io.loadmat(hopkins155_dir / "arm" / "arm_truth.mat")["x"]
    assert_array_equal(seq.X[:, 0], x[0, :, 0])
    assert_array_equal(seq.X[:, 3], x[1, :, 1])


def test_real_category_counts(shared_data_dir):
    """The README's table: (2 motions, 3 motions) sequences per category."""
    # Loads all 155 benchmark files: about 0.5 s.
    data = load_hopkins155(shared_data_dir, n_motions=[2, 3], include_extra=True)
    counts = collections.Counter((b.category, b.n_motions) for b in data)
    assert counts == {
        ("checkerboard", 2): 78,
        ("checkerboard", 3): 26,
        ("traffic", 2): 31,
        ("traffic", 3): 7,
        ("articulated", 2): 11,
        ("articulated", 3): 2,
    }
    assert len(data) == 155
    extra = load_hopkins155(shared_data_dir, sequences="dancing")[0]
    assert extra.n_motions == 5
    assert extra.category == "articulated"


# --- bad values are rejected, not loaded (issue: silent wrong data) -------


def _points(n_points=6, n_frames=4, bad=None):
    x = np.ones((3, n_points, n_frames))
    x[:2] = np.random.RandomState(0).uniform(-1, 1, size=(2, n_points, n_frames))
    if bad is not None:
        x[0, 2, 1] = bad
    return x


@pytest.mark.parametrize(
    ("overrides", "match"),
    [
        (dict(x=_points(bad=np.nan)), r"'x' holds 1 NaN or infinite value"),
        (dict(x=_points(bad=np.inf)), r"'x' holds 1 NaN or infinite value"),
        (dict(y=_points(bad=np.nan)), r"'y' holds 1 NaN or infinite value"),
        (dict(s=np.array([[1.0], [2], [1.5], [2], [1], [2]])), r"'s' holds 1.5"),
        (
            dict(x=np.ones((3, 6, 0)), y=np.ones((3, 6, 0))),
            r"no frames",
        ),
        (
            dict(x=np.ones((3, 0, 4)), y=np.ones((3, 0, 4)), s=np.ones((0, 1))),
            r"no points",
        ),
    ],
    ids=["nan-x", "inf-x", "nan-y", "float-s", "zero-frames", "zero-points"],
)
def test_bad_values_are_rejected(tmp_path, overrides, match):
    write_sequence(tmp_path, "bad", **overrides)
    with pytest.raises(ValueError, match=match) as excinfo:
        load_hopkins155(tmp_path)
    assert "bad_truth.mat" in str(excinfo.value)


def test_integral_float_labels_are_accepted(tmp_path):
    write_sequence(tmp_path, "ok", s=np.array([[1.0], [2], [1], [2], [1], [2]]))
    assert_array_equal(load_hopkins155(tmp_path)[0].y, [0, 1, 0, 1, 0, 1])


def test_failed_load_creates_no_data_home(tmp_path, monkeypatch):
    home = tmp_path / "home"
    monkeypatch.delenv("SKLEARN_GPCA_DATA", raising=False)
    monkeypatch.setenv("HOME", str(home))
    monkeypatch.delenv("SCIKIT_LEARN_DATA", raising=False)
    with pytest.raises(FileNotFoundError, match="scikit_learn_data"):
        load_hopkins155()
    with pytest.raises(OSError, match="download_if_missing=False"):
        fetch_hopkins155(download_if_missing=False)
    assert not home.exists()
    monkeypatch.setenv("SCIKIT_LEARN_DATA", str(tmp_path / "sk"))
    with pytest.raises(FileNotFoundError, match="sk"):
        load_hopkins155()
    assert sorted(p.name for p in tmp_path.iterdir()) == []
