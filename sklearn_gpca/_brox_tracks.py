"""Track files of Brox & Malik's point tracker (``.dat``).

The tracker of "Object Segmentation by Long Term Analysis of Point
Trajectories" (Brox & Malik, ECCV 2010), also used for the FBMS-59 benchmark
(Ochs, Malik & Brox, PAMI 2014), writes its tracks as whitespace-separated
numbers: the number of frames, the number of tracks, then for each track its
label and its length ``m`` followed by ``m`` triples ``x y frame`` (frames
counted from 0). Its tracks are born and lost all along the video: every
frame a track is not seen in is missing.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._trajectory_files import UsageError

#: Most point-frames (tracks times frames) a file may announce: 2^31 of them
#: take 32 GiB as float64 coordinates. A header beyond it is taken for a
#: malformed file rather than allocated.
MAX_POINT_FRAMES = 2**31


def read_brox_tracks(path):
    """Read a Brox & Malik ``.dat`` track file.

    Parameters
    ----------
    path : pathlib.Path

    Returns
    -------
    X : ndarray of shape (n_tracks, 2 * n_frames)
        ``[x_1, y_1, ..., x_F, y_F]`` per track, NaN in the frames it is not
        seen in.
    y : ndarray of shape (n_tracks,) or None
        The tracks' labels; None when every track has the same label (the
        tracker's own output labels every track 0: no segmentation to compare
        with).

    Raises
    ------
    UsageError
        For a file that is not one: a token that is not a number, a count
        that is not a whole number, a file that ends inside a track or goes
        on after the last, a frame outside the video, a frame seen twice in
        one track, a coordinate that is not finite.
    """
    try:
        tokens = path.read_text(encoding="ascii").split()
    except UnicodeDecodeError as exc:
        raise UsageError(
            f"{path}: not a Brox & Malik track file (not plain text)"
        ) from exc
    except OSError as exc:
        raise UsageError(f"{path}: cannot read ({exc.strerror or exc})") from exc
    if not tokens:
        raise UsageError(f"{path}: the file is empty")
    try:
        numbers = np.array(tokens, dtype=np.float64)
    except ValueError as exc:
        bad = next(token for token in tokens if not _is_number(token))
        raise UsageError(
            f"{path}: not a Brox & Malik track file: {bad!r} is not a number"
        ) from exc
    if numbers.size < 2:
        raise UsageError(
            f"{path}: the file ends before its header (number of frames, "
            "number of tracks)"
        )
    n_frames = _count(path, numbers[0], "the number of frames", minimum=1)
    n_tracks = _count(path, numbers[1], "the number of tracks", minimum=1)
    if n_tracks * n_frames > MAX_POINT_FRAMES:
        raise UsageError(
            f"{path}: its header announces {n_tracks} tracks over {n_frames} "
            f"frames, more than {MAX_POINT_FRAMES} point-frames: not a track file "
            "this reader can hold in memory"
        )
    starts, lengths = _track_offsets(path, numbers, n_tracks)
    # the position of every triple (x, y, frame), in file order
    track = np.repeat(np.arange(n_tracks), lengths)
    within = np.arange(track.size) - np.repeat(np.cumsum(lengths) - lengths, lengths)
    first = starts[track] + 2 + 3 * within
    x, y_coord, frame = (numbers[first + k] for k in range(3))
    if not np.all(np.isfinite(x) & np.isfinite(y_coord)):
        first = int(track[~(np.isfinite(x) & np.isfinite(y_coord))][0])
        raise UsageError(f"{path}: track {first} has a coordinate that is not finite")
    whole = (frame == np.round(frame)) & (frame >= 0) & (frame < n_frames)
    if not whole.all():
        k = int(np.flatnonzero(~whole)[0])
        raise UsageError(
            f"{path}: track {track[k]} is seen in frame {frame[k]:g}, not a frame "
            f"of the video (0 to {n_frames - 1})"
        )
    frame = frame.astype(np.intp)
    seen = np.zeros((n_tracks, n_frames), dtype=np.intp)
    np.add.at(seen, (track, frame), 1)
    if seen.max() > 1:
        k, f = np.argwhere(seen > 1)[0]
        raise UsageError(f"{path}: track {k} is seen twice in frame {f}")
    X = np.full((n_tracks, n_frames, 2), np.nan)
    X[track, frame, 0] = x
    X[track, frame, 1] = y_coord
    labels = numbers[starts]
    y = None
    if np.unique(labels).size > 1:
        y = labels.astype(np.intp) if np.all(labels == np.round(labels)) else labels
    return X.reshape(n_tracks, 2 * n_frames), y


def _is_number(token):
    try:
        float(token)
    except ValueError:
        return False
    return True


def _count(path, value, name, *, minimum):
    if not (np.isfinite(value) and value == np.round(value) and value >= minimum):
        raise UsageError(
            f"{path}: {name} is {value:g}, not a whole number of at least {minimum}"
        )
    return int(value)


def _track_offsets(path, numbers, n_tracks):
    """Position of every track's header (label, length) and its length.

    Sequential by nature: a track's header follows the previous track's
    triples.
    """
    starts = np.empty(n_tracks, dtype=np.intp)
    lengths = np.empty(n_tracks, dtype=np.intp)
    position = 2
    for k in range(n_tracks):
        if position + 2 > numbers.size:
            raise UsageError(
                f"{path}: the file ends before track {k} of the {n_tracks} its "
                "header announces"
            )
        lengths[k] = _count(
            path, numbers[position + 1], f"the length of track {k}", minimum=1
        )
        starts[k] = position
        position += 2 + 3 * lengths[k]
        if position > numbers.size:
            raise UsageError(
                f"{path}: the file ends inside track {k} ({lengths[k]} points "
                "announced)"
            )
    if position != numbers.size:
        raise UsageError(
            f"{path}: {numbers.size - position} numbers after the last of the "
            f"{n_tracks} tracks its header announces"
        )
    return starts, lengths
