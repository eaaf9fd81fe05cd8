"""Tests of the reader of Brox & Malik's track files (``.dat``)."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_trajectory_files import message_of

from sklearn_gpca._brox_tracks import read_brox_tracks
from sklearn_gpca._cli import main
from sklearn_gpca._trajectory_files import read_trajectories
from sklearn_gpca.datasets import load_trajectories, make_tracks
from sklearn_gpca.metrics import misclassification_rate


def brox_text(X, labels):
    """The ``.dat`` text of tracks ``X`` (NaN where unseen), as the tracker
    writes it: every track's seen frames, in order."""
    n_tracks, n_frames = X.shape[0], X.shape[1] // 2
    points = X.reshape(n_tracks, n_frames, 2)
    lines = [str(n_frames), str(n_tracks)]
    for k in range(n_tracks):
        frames = np.flatnonzero(~np.isnan(points[k, :, 0]))
        lines.append(f"{labels[k]} {frames.size}")
        lines += [
            f"{float(points[k, f, 0])!r} {float(points[k, f, 1])!r} {f}" for f in frames
        ]
    return "\n".join(lines) + "\n"


def test_tracks_born_and_lost_are_read_back_exactly(tmp_path):
    X, y = make_tracks(scene="driving", n_tracks=60, random_state=0)
    X, y = X[y >= 0], y[y >= 0]
    X = X[np.count_nonzero(~np.isnan(X), axis=1) > 0]
    path = tmp_path / "Tracks20.dat"
    path.write_text(brox_text(X, y[: X.shape[0]]))
    read, labels = read_trajectories(path)
    np.testing.assert_array_equal(read, X)
    np.testing.assert_array_equal(labels, y[: X.shape[0]])
    assert labels.dtype.kind == "i"


def test_one_label_for_every_track_is_no_ground_truth(tmp_path):
    path = tmp_path / "t.dat"
    path.write_text("3\n2\n0 3\n1 2 0\n3 4 1\n5 6 2\n0 2\n7 8 2\n9 10 0\n")
    X, labels = read_trajectories(path)
    assert labels is None
    # the points of a track may come in any frame order
    np.testing.assert_array_equal(
        X, [[1, 2, 3, 4, 5, 6], [9, 10, np.nan, np.nan, 7, 8]]
    )


@pytest.mark.parametrize(
    "text, message",
    [
        ("", "the file is empty"),
        ("3\n", "the file ends before its header"),
        ("3\n1\n0 1\n1 2 x\n", "'x' is not a number"),
        ("0\n1\n0 1\n1 2 0\n", "the number of frames is 0, not a whole number"),
        ("3.5\n1\n0 1\n1 2 0\n", "the number of frames is 3.5"),
        ("3\n0\n", "the number of tracks is 0"),
        ("3\n2\n0 1\n1 2 0\n", "ends before track 1 of the 2"),
        ("3\n1\n0 2\n1 2 0\n", "ends inside track 0 (2 points announced)"),
        ("3\n1\n0 0\n", "the length of track 0 is 0"),
        ("3\n1\n0 1\n1 2 0\n7\n", "1 numbers after the last of the 1 tracks"),
        ("3\n1\n0 1\n1 2 3\n", "track 0 is seen in frame 3, not a frame"),
        ("3\n1\n0 1\n1 2 0.5\n", "track 0 is seen in frame 0.5"),
        ("3\n1\n0 2\n1 2 1\n3 4 1\n", "track 0 is seen twice in frame 1"),
        ("3\n1\n0 1\n1 inf 1\n", "track 0 has a coordinate that is not finite"),
        ("3000000000\n1\n0 1\n1 2 0\n", "more than 2147483648 point-frames"),
    ],
)
def test_bad_files_are_named(tmp_path, text, message):
    path = tmp_path / "t.dat"
    path.write_text(text)
    assert message in message_of(path)
    assert message_of(path).startswith(f"{path}: ")


def test_binary_file_is_not_plain_text(tmp_path):
    path = tmp_path / "t.dat"
    path.write_bytes(b"\x89PNG\r\n\x1a\n\xff\xfe")
    assert message_of(path) == (
        f"{path}: not a Brox & Malik track file (not plain text)"
    )


def test_command_line_segments_a_track_file(tmp_path, capsys):
    X, y = make_tracks(scene="lab", n_tracks=120, missing=0.3, random_state=1)
    path = tmp_path / "Tracks30.dat"
    path.write_text(brox_text(X, y))
    labels = tmp_path / "labels.txt"
    status = main(["segment", str(path), "--n-motions", "2", "--output", str(labels)])
    assert status == 0
    found = np.loadtxt(labels, dtype=int)
    assert found.shape == y.shape
    assert misclassification_rate(y, found) < 0.1
    assert "misclassified" in capsys.readouterr().out


def test_python_loader_raises_value_error_naming_the_file(tmp_path):
    path = tmp_path / "t.dat"
    path.write_text("3\n1\n0 2\n1 2 1\n3 4 1\n")
    with pytest.raises(ValueError, match=r"t\.dat: track 0 is seen twice in frame 1"):
        load_trajectories(path)
    path.write_text("3\n2\n1 2\n1 2 0\n3 4 2\n2 3\n5 6 0\n7 8 1\n9 9 2\n")
    X, y = load_trajectories(path)
    np.testing.assert_array_equal(y, [1, 2])
    assert X.shape == (2, 6)


@settings(max_examples=40, deadline=None)
@given(
    n_frames=st.integers(1, 6),
    seen=st.lists(st.integers(1, 63), min_size=1, max_size=8),
    seed=st.integers(0, 2**16),
)
def test_any_tracks_in_any_point_order_are_read_back(
    tmp_path_factory, n_frames, seen, seed
):
    rng = np.random.default_rng(seed)
    # each track seen in the frames of a bit mask (at least one frame)
    masks = np.array(
        [[(bits >> f) & 1 for f in range(n_frames)] for bits in seen], dtype=bool
    )
    masks[~masks.any(axis=1), 0] = True
    X = np.where(
        np.repeat(masks, 2, axis=1),
        rng.normal(0, 300, (len(seen), 2 * n_frames)),
        np.nan,
    )
    labels = rng.integers(0, 3, len(seen))
    lines = [str(n_frames), str(len(seen))]
    for k, row in enumerate(X.reshape(len(seen), n_frames, 2)):
        frames = rng.permutation(np.flatnonzero(masks[k]))
        lines.append(f"{labels[k]} {frames.size}")
        lines += [f"{float(row[f, 0])!r} {float(row[f, 1])!r} {f}" for f in frames]
    path = tmp_path_factory.mktemp("dat") / "t.dat"
    path.write_text(" ".join(lines))
    read, y = read_brox_tracks(path)
    np.testing.assert_array_equal(read, X)
    if np.unique(labels).size > 1:
        np.testing.assert_array_equal(y, labels)
    else:
        assert y is None
