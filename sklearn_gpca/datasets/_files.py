"""Trajectories from a file: the formats of the command line, in Python."""

# SPDX-License-Identifier: BSD-3-Clause

from sklearn_gpca._trajectory_files import UsageError, read_trajectories


def load_trajectories(path):
    """Load trajectories, and their labels if the file holds them.

    The files ``python -m sklearn_gpca segment`` reads (see
    :doc:`/command_line`):

    - ``.npz``: array ``X`` of shape ``(points, 2 * frames)``, optional
      labels ``y``;
    - ``.csv``: one trajectory ``x_1, y_1, ..., x_F, y_F`` per row, empty
      cells or ``NaN`` where missing, an optional header naming a label
      column;
    - ``.mat`` in the Hopkins155 layout (field ``x``, else ``y``, of shape
      ``3 x points x frames``; optional labels ``s``);
    - ``.dat``, the track files of Brox & Malik's tracker (FBMS-59): a track
      is missing in the frames it is not seen in; its labels are returned
      only when they differ (the tracker's own output labels every track 0).

    Parameters
    ----------
    path : str or path-like

    Returns
    -------
    X : ndarray of shape (n_samples, 2 * n_frames)
        One trajectory per row ``[x_1, y_1, ..., x_F, y_F]``, float64, NaN
        where missing.
    y : ndarray of shape (n_samples,) or None
        The labels the file holds, if any.

    Raises
    ------
    ValueError
        Naming the file and its problem: a missing file, an unknown format,
        a malformed file, fewer than 3 frames or 2 trajectories, infinite
        or out-of-range coordinates, labels that do not match the rows.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> from sklearn_gpca.datasets import load_trajectories
    >>> path = Path(tempfile.mkdtemp()) / "Tracks3.dat"
    >>> _ = path.write_text("3 2  0 3 1 2 0 3 4 1 5 6 2  0 2 7 8 2 9 9 0")
    >>> X, y = load_trajectories(path)
    >>> X
    array([[ 1.,  2.,  3.,  4.,  5.,  6.],
           [ 9.,  9., nan, nan,  7.,  8.]])
    >>> print(y)
    None
    """
    try:
        return read_trajectories(path)
    except UsageError as exc:
        raise ValueError(str(exc)) from None
