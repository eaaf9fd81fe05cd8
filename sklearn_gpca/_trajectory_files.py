"""Trajectory files of the command line: read ``.npz``, ``.csv``, ``.mat``,
``.dat`` (Brox & Malik's tracker, :mod:`sklearn_gpca._brox_tracks`); write
atomically.

Every problem with a file is raised as :class:`UsageError`, whose message
names the file (and the line of a ``.csv``) and says what is wrong.
"""

# SPDX-License-Identifier: BSD-3-Clause

import csv
import os
import tempfile
from pathlib import Path

import numpy as np

#: Least number of frames for a trajectory file.
MIN_FRAMES = 3

FORMATS = (".npz", ".csv", ".mat", ".dat")

#: Cells of a ``.csv`` that mean a missing entry (compared in lower case).
MISSING_CELLS = ("", "na", "n/a", "nan")

#: Header names of a ``.csv`` column holding ground-truth labels (lower case).
LABEL_COLUMNS = ("label", "labels", "s", "y_true", "truth", "ground_truth", "motion")

#: Largest coordinate magnitude accepted: squares and sums of squares of
#: larger values overflow float64 (about 1.8e308).
MAX_MAGNITUDE = 1e150

#: Smallest nonzero largest magnitude accepted: below it, squares underflow.
MIN_MAGNITUDE = 1e-150

_ZIP_MAGIC = b"PK\x03\x04"


class UsageError(Exception):
    """A mistake in the user's input: reported on one line, exit status 2."""


# ---------------------------------------------------------------------------
# .npz


def _read_npz(path):
    with open(path, "rb") as f:
        head = f.read(len(_ZIP_MAGIC))
    if not head:
        raise UsageError(f"{path}: the file is empty (0 bytes), not a .npz archive")
    if head != _ZIP_MAGIC:
        raise UsageError(
            f"{path}: not a .npz archive (a zip of .npy arrays, as written by "
            "numpy.savez)"
        )
    try:
        with np.load(path, allow_pickle=False) as data:
            if "X" not in data.files:
                raise UsageError(
                    f"{path}: no array 'X' in the .npz file (found "
                    f"{', '.join(sorted(data.files)) or 'nothing'})"
                )
            X = data["X"]
            y = data["y"] if "y" in data.files else None
    except UsageError:
        raise
    except Exception as exc:  # zipfile, numpy and OS errors of a damaged file
        raise UsageError(f"{path}: cannot read as .npz ({exc})") from exc
    return X, y


# ---------------------------------------------------------------------------
# .csv


def _is_missing(cell):
    return cell.strip().lower() in MISSING_CELLS


def _parse_number(cell):
    """``float(cell)``, NaN for a missing cell, None if not a number."""
    if _is_missing(cell):
        return np.nan
    try:
        return float(cell)
    except ValueError:
        return None


def _is_header(row):
    """A header holds no number at all, and some cell that is not missing."""
    if any(_parse_number(cell) is not None and not _is_missing(cell) for cell in row):
        return False
    return any(not _is_missing(cell) for cell in row)


def _read_csv_rows(path):
    """``[(line number, cells)]`` of the non-blank lines; a BOM is dropped."""
    try:
        with open(path, newline="", encoding="utf-8-sig") as f:
            reader = csv.reader(f)
            rows = [
                (reader.line_num, row)
                for row in reader
                if not (len(row) == 0 or (len(row) == 1 and not row[0].strip()))
            ]
    except UnicodeDecodeError as exc:
        raise UsageError(f"{path}: not UTF-8 text ({exc.reason})") from exc
    except (OSError, csv.Error) as exc:
        raise UsageError(f"{path}: cannot read as .csv ({exc})") from exc
    if not rows:
        raise UsageError(f"{path}: the file holds no trajectories")
    return rows


def _label_column(path, header):
    if header is None:
        return None
    names = [name.strip().lower() for name in header]
    found = [j for j, name in enumerate(names) if name in LABEL_COLUMNS]
    if len(found) > 1:
        raise UsageError(
            f"{path}: several label columns "
            f"({', '.join(repr(header[j].strip()) for j in found)}); keep one"
        )
    return found[0] if found else None


def _labels_from_cells(path, cells, lines, name):
    missing = [
        line for cell, line in zip(cells, lines, strict=True) if _is_missing(cell)
    ]
    if missing:
        raise UsageError(
            f"{path}: label column {name!r} is empty on line {missing[0]}"
            + (f" and {len(missing) - 1} more" if len(missing) > 1 else "")
        )
    labels = np.array([cell.strip() for cell in cells])
    try:
        numbers = labels.astype(np.float64)
    except ValueError:
        return labels  # names such as "car", "background"
    if np.all(numbers == np.round(numbers)):
        return numbers.astype(np.int64)
    return labels


def _read_csv(path):
    """One trajectory per row; see :data:`CSV_RULES` for header and labels."""
    rows = _read_csv_rows(path)
    header = None
    if _is_header(rows[0][1]):
        header, rows = rows[0][1], rows[1:]
        if not rows:
            raise UsageError(f"{path}: the file holds a header and no trajectories")
    width = len(header) if header is not None else len(rows[0][1])
    for line, row in rows:
        if len(row) != width:
            what = "the header" if header is not None else f"line {rows[0][0]}"
            raise UsageError(
                f"{path}, line {line}: {len(row)} cells where {what} has {width}"
            )
    label = _label_column(path, header)
    lines = [line for line, _ in rows]
    y = None
    if label is not None:
        y = _labels_from_cells(
            path, [row[label] for _, row in rows], lines, header[label].strip()
        )
        rows = [(line, row[:label] + row[label + 1 :]) for line, row in rows]
    values = np.empty((len(rows), width - (label is not None)))
    for i, (line, row) in enumerate(rows):
        for j, cell in enumerate(row):
            number = _parse_number(cell)
            if number is None:
                raise UsageError(
                    f"{path}, line {line}: cell {j + 1} ({cell.strip()!r}) is not a "
                    "number"
                    + (
                        "; a header row must hold names only"
                        if line == 1 and header is None
                        else ""
                    )
                )
            values[i, j] = number
    return values, y


#: The rules for ``.csv`` files, as the command line's help states them.
CSV_RULES = (
    "A .csv holds one trajectory x_1, y_1, ..., x_F, y_F per row; empty cells, "
    "NA, N/A and NaN (any case) are missing entries; blank lines are skipped and "
    "a UTF-8 byte-order mark is ignored. The first row is a header only if it "
    "holds no number at all. A header column named label, labels, s, y_true, "
    "truth, ground_truth or motion (any case) holds ground-truth labels; every "
    "other column is a coordinate. Without a header every column is a coordinate."
)


# ---------------------------------------------------------------------------
# .mat


def _read_mat(path):
    """Hopkins155 layout: ``x`` (else ``y``) of shape (3, P, F); ``s`` optional."""
    import scipy.io

    try:
        data = scipy.io.loadmat(path)
    except Exception as exc:  # scipy raises several types on bad files
        raise UsageError(f"{path}: cannot read as .mat ({exc})") from exc
    key = "x" if "x" in data else "y" if "y" in data else None
    if key is None:
        found = sorted(k for k in data if not k.startswith("__"))
        raise UsageError(
            f"{path}: no field 'x' or 'y' (3 x points x frames) in the .mat file "
            f"(found {', '.join(found) or 'nothing'})"
        )
    points = np.asarray(data[key])
    if points.dtype.kind not in "biuf":
        raise UsageError(f"{path}: field {key!r} must be numeric, got {points.dtype}")
    if points.ndim != 3 or points.shape[0] not in (2, 3):
        raise UsageError(
            f"{path}: field {key!r} must have shape (3, points, frames), got "
            f"{points.shape}"
        )
    n_points = points.shape[1]
    X = points[:2].astype(np.float64).transpose(1, 2, 0).reshape(n_points, -1)
    y = None
    if "s" in data:
        y = np.asarray(data["s"]).ravel()
        if y.shape[0] != n_points:
            raise UsageError(
                f"{path}: field 's' holds {y.shape[0]} labels for {n_points} points"
            )
    return X, y


# ---------------------------------------------------------------------------


def _check_magnitude(path, X):
    observed = np.abs(X[~np.isnan(X)])
    if observed.size == 0:
        raise UsageError(f"{path}: every entry is missing")
    largest = observed.max()
    if largest > MAX_MAGNITUDE:
        raise UsageError(
            f"{path}: coordinates as large as {largest:.3g} exceed "
            f"{MAX_MAGNITUDE:.0e} and overflow float64 arithmetic; rescale them "
            "(the segmentation does not depend on the unit)"
        )
    if largest < MIN_MAGNITUDE:
        raise UsageError(
            f"{path}: the largest coordinate is {largest:.3g}, below "
            f"{MIN_MAGNITUDE:.0e}: the trajectories are all (nearly) zero"
        )


def read_trajectories(path):
    """Read ``X`` of shape (n_points, 2 * n_frames) and optional labels ``y``.

    Parameters
    ----------
    path : str or path-like
        A ``.npz`` (array ``X``, optional ``y``), ``.csv`` (see
        :data:`CSV_RULES`), Hopkins155-style ``.mat`` file (field ``x``,
        else ``y``, of shape 3 x points x frames; optional labels ``s``) or
        Brox & Malik ``.dat`` track file
        (:func:`sklearn_gpca._brox_tracks.read_brox_tracks`).

    Returns
    -------
    X : ndarray of shape (n_points, 2 * n_frames), float64
        NaN where missing.
    y : ndarray of shape (n_points,) or None
        Ground-truth labels, if the file holds them.

    Raises
    ------
    UsageError
        For a missing or unreadable file, an unknown format, a wrong shape,
        infinite or out-of-range values, or labels that do not match the rows.
    """
    path = Path(path)
    if not path.exists():
        raise UsageError(f"{path}: no such file")
    if path.is_dir():
        raise UsageError(f"{path}: is a directory, not a trajectory file")
    suffix = path.suffix.lower()
    from sklearn_gpca._brox_tracks import read_brox_tracks

    readers = {
        ".npz": _read_npz,
        ".csv": _read_csv,
        ".mat": _read_mat,
        ".dat": read_brox_tracks,
    }
    if suffix not in readers:
        raise UsageError(
            f"{path}: unknown format {suffix or '(no extension)'!r}; "
            f"expected one of {', '.join(FORMATS)}"
        )
    X, y = readers[suffix](path)
    X = np.asarray(X)
    if X.dtype.kind not in "biuf":
        raise UsageError(f"{path}: X must be numeric, got dtype {X.dtype}")
    X = X.astype(np.float64)
    if X.ndim != 2:
        raise UsageError(
            f"{path}: X must be 2-D (points x 2 * frames), got shape {X.shape}"
        )
    n_points, n_columns = X.shape
    if n_columns % 2:
        hint = (
            "; name a label column in a header row (label, labels, s, y_true, ...)"
            if suffix == ".csv"
            else ""
        )
        raise UsageError(
            f"{path}: X has an odd number of columns ({n_columns}); rows must be "
            f"[x_1, y_1, ..., x_F, y_F]{hint}"
        )
    if n_columns // 2 < MIN_FRAMES:
        raise UsageError(
            f"{path}: {n_columns // 2} frames; at least {MIN_FRAMES} are needed"
        )
    if n_points < 2:
        raise UsageError(f"{path}: {n_points} trajectories; at least 2 are needed")
    if np.isinf(X).any():
        raise UsageError(f"{path}: X holds infinite values")
    _check_magnitude(path, X)
    if y is not None:
        y = np.asarray(y)
        if y.ndim != 1 and y.size == n_points:
            y = y.ravel()
        if y.ndim != 1 or y.shape[0] != n_points:
            raise UsageError(
                f"{path}: y of shape {y.shape} does not hold one label for each "
                f"of the {n_points} points"
            )
        if y.dtype.kind == "f" and np.isnan(y).any():
            raise UsageError(f"{path}: y holds missing labels (NaN)")
    return X, y


# ---------------------------------------------------------------------------
# Writing


def same_file(a, b):
    """Whether paths ``a`` and ``b`` name the same file (links included)."""
    a, b = Path(a), Path(b)
    try:
        return a.exists() and b.exists() and os.path.samefile(a, b)
    except OSError:
        return False


def write_atomically(path, write):
    """Call ``write(temporary_path)`` then rename the file to ``path``.

    The temporary file sits in the same folder with the same suffix (so that
    writers that read the format from the suffix, such as matplotlib, work),
    and is removed if ``write`` fails: ``path`` is either left untouched or
    replaced whole.
    """
    path = Path(path)
    fd, tmp = tempfile.mkstemp(
        prefix=f".{path.stem}.", suffix=path.suffix, dir=path.parent
    )
    os.close(fd)
    umask = os.umask(0)
    os.umask(umask)
    try:
        # mkstemp makes the file private (0600); give it the usual mode.
        os.chmod(tmp, 0o666 & ~umask)
        write(tmp)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
