"""Loader and fetcher for the Hopkins155 motion segmentation benchmark."""

# SPDX-License-Identifier: BSD-3-Clause

import os
import re
import shutil
import tempfile
import urllib.request
import zipfile
from numbers import Integral
from pathlib import Path

import numpy as np
import scipy.io
from sklearn.utils import Bunch
from sklearn.utils._param_validation import Interval, StrOptions, validate_params

from sklearn_gpca.datasets._home import default_data_home

HOPKINS155_URL = "http://www.vision.jhu.edu/data/hopkins155/Hopkins155.zip"

#: The sequences with more than 3 motions, outside the 155 of the benchmark.
HOPKINS155_EXTRA = ("dancing",)

CATEGORIES = ("checkerboard", "traffic", "articulated")

_CATEGORY_PATTERNS = (
    # Checkerboard: 1R2RC .. 2T3RTCR (names start with the object number) and
    # three-cars. Checked before "cars" below.
    ("checkerboard", re.compile(r"^(\d|three-cars)")),
    ("traffic", re.compile(r"^(cars|truck|kanatani[12]$)")),
    (
        "articulated",
        re.compile(r"^(arm|articulated|head|people|kanatani3$|two_cranes|dancing)"),
    ),
)


def hopkins155_category(name):
    """Category of a Hopkins155 sequence, from its name.

    The rules follow the benchmark's README: checkerboard sequences are
    ``1R2RC`` to ``2T3RTCR`` and ``three-cars``; traffic sequences are
    ``cars*``, ``truck*``, ``kanatani1`` and ``kanatani2``; articulated and
    non-rigid ones are ``arm``, ``articulated``, ``head``, ``people*``,
    ``kanatani3``, ``two_cranes`` and ``dancing``. The ``_g12``-style
    suffixes (two-motion subsets of three-motion sequences) keep the category
    of their sequence.

    Parameters
    ----------
    name : str
        Sequence name, e.g. ``"1R2RC_g12"``.

    Returns
    -------
    category : {"checkerboard", "traffic", "articulated"} or None
        None for a name outside the benchmark.

    Examples
    --------
    >>> from sklearn_gpca.datasets import hopkins155_category
    >>> [hopkins155_category(n) for n in ["2T3RCR_g12", "cars2B", "kanatani3"]]
    ['checkerboard', 'traffic', 'articulated']
    """
    for category, pattern in _CATEGORY_PATTERNS:
        if pattern.match(name):
            return category
    return None


def _truth_file(folder):
    return folder / f"{folder.name}_truth.mat"


def _sequence_dirs(folder):
    """Sub-folders ``<name>`` of ``folder`` that hold ``<name>_truth.mat``."""
    if not folder.is_dir():
        return {}
    return {
        d.name: d for d in folder.iterdir() if d.is_dir() and _truth_file(d).is_file()
    }


def _resolve_hopkins155_home(data_home):
    """Folder holding the sequences, or None; plus the folder searched."""
    base = default_data_home() if data_home is None else Path(data_home)
    base = base.expanduser()
    for candidate in (base / "hopkins155", base / "Hopkins155", base):
        sequences = _sequence_dirs(candidate)
        if sequences:
            return candidate, sequences
    return base, {}


def _not_found(base):
    return FileNotFoundError(
        f"No Hopkins155 sequences (<name>/<name>_truth.mat) found in {base} or "
        f"{base / 'hopkins155'}. Download them with "
        "sklearn_gpca.datasets.fetch_hopkins155(data_home=...), or get "
        f"{HOPKINS155_URL} and extract it there."
    )


def _get_array(data, key, path, ndim):
    if key not in data:
        raise ValueError(
            f"Malformed Hopkins155 file {path}: missing variable {key!r} "
            f"(found {sorted(k for k in data if not k.startswith('__'))})."
        )
    value = np.asarray(data[key])
    if value.ndim != ndim:
        raise ValueError(
            f"Malformed Hopkins155 file {path}: {key!r} must have {ndim} "
            f"dimensions, got shape {value.shape}."
        )
    return value


def _read_sequence(path):
    """Read one ``<name>_truth.mat`` into a Bunch in the library's layout."""
    try:
        data = scipy.io.loadmat(path)
    except Exception as exc:  # scipy raises several types on bad files
        raise ValueError(f"Could not read Hopkins155 file {path}: {exc}") from exc
    name = path.parent.name
    x = _get_array(data, "x", path, 3)
    y = _get_array(data, "y", path, 3)
    s = _get_array(data, "s", path, 2)
    if x.shape[0] != 3 or y.shape != x.shape:
        raise ValueError(
            f"Malformed Hopkins155 file {path}: 'x' and 'y' must both have shape "
            f"(3, n_points, n_frames), got {x.shape} and {y.shape}."
        )
    _, n_points, n_frames = x.shape
    if n_points == 0 or n_frames == 0:
        raise ValueError(
            f"Malformed Hopkins155 file {path}: no "
            f"{'points' if n_points == 0 else 'frames'} (x has shape {x.shape})."
        )
    for key, points in (("x", x), ("y", y)):
        n_bad = np.sum(~np.isfinite(points[:2]))
        if n_bad:
            raise ValueError(
                f"Malformed Hopkins155 file {path}: {key!r} holds {n_bad} NaN or "
                f"infinite value{'s' if n_bad > 1 else ''}; Hopkins155 "
                "trajectories are complete."
            )
    fractional = s[s != np.round(s)] if s.dtype.kind == "f" else s[:0]
    if fractional.size:
        raise ValueError(
            f"Malformed Hopkins155 file {path}: 's' holds {fractional.flat[0]:g}; "
            "labels must be integers."
        )
    labels = s.ravel().astype(np.int64)
    if labels.shape[0] != n_points or labels.min(initial=1) < 1:
        raise ValueError(
            f"Malformed Hopkins155 file {path}: 's' must hold {n_points} labels "
            f"numbered from 1, got shape {s.shape} and minimum "
            f"{labels.min() if labels.size else None}."
        )
    labels = np.unique(labels, return_inverse=True)[1].astype(np.intp)

    def to_rows(points):
        # (2, P, F) -> (P, F, 2) -> (P, 2F) with rows [x_1, y_1, ..., x_F, y_F]
        return np.ascontiguousarray(
            points[:2].transpose(1, 2, 0).reshape(n_points, 2 * n_frames),
            dtype=np.float64,
        )

    return Bunch(
        X=to_rows(x),
        y=labels,
        n_motions=int(labels.max()) + 1,
        name=name,
        category=hopkins155_category(name),
        n_frames=int(n_frames),
        n_points=int(n_points),
        X_pixels=to_rows(y),
    )


def _peek_n_motions(path):
    """Number of motions from ``s`` alone, without reading the trajectories."""
    try:
        s = scipy.io.loadmat(path, variable_names=["s"]).get("s")
    except Exception as exc:  # scipy raises several types on bad files
        raise ValueError(f"Could not read Hopkins155 file {path}: {exc}") from exc
    if s is None:
        raise ValueError(f"Malformed Hopkins155 file {path}: missing variable 's'.")
    return np.unique(np.asarray(s).ravel()).size


_LOAD_CONSTRAINTS = {
    "sequences": [str, "array-like", None],
    "n_motions": [Interval(Integral, 1, None, closed="left"), "array-like", None],
    "category": [StrOptions(set(CATEGORIES)), "array-like", None],
    "include_extra": ["boolean"],
    "return_iterator": ["boolean"],
}


def _as_set(value):
    return None if value is None else {value} if np.isscalar(value) else set(value)


def _load(data_home, sequences, n_motions, category, include_extra, return_iterator):
    folder, available = _resolve_hopkins155_home(data_home)
    if not available:
        raise _not_found(folder)
    names = _as_set(sequences)
    if names is not None:
        unknown = sorted(names - set(available))
        if unknown:
            raise ValueError(
                f"Unknown Hopkins155 sequences {unknown} (not in {folder}); "
                f"there are {len(available)} sequences, e.g. "
                f"{sorted(available)[:3]}."
            )
        selected = sorted(names)
    else:
        selected = sorted(
            n for n in available if include_extra or n not in HOPKINS155_EXTRA
        )
    categories = _as_set(category)
    if categories is not None:
        bad = sorted(categories - set(CATEGORIES))
        if bad:
            raise ValueError(f"Unknown categories {bad}; choose from {CATEGORIES}.")
        selected = [n for n in selected if hopkins155_category(n) in categories]
    motions = _as_set(n_motions)

    def generate():
        for name in selected:
            path = _truth_file(available[name])
            if motions is not None and _peek_n_motions(path) not in motions:
                continue
            yield _read_sequence(path)

    return generate() if return_iterator else list(generate())


@validate_params(
    {"data_home": [str, os.PathLike, None], **_LOAD_CONSTRAINTS},
    prefer_skip_nested_validation=True,
)
def load_hopkins155(
    data_home=None,
    *,
    sequences=None,
    n_motions=None,
    category=None,
    include_extra=False,
    return_iterator=False,
):
    """Load the Hopkins155 motion segmentation benchmark from disk.

    Reads the standard layout ``<data_home>/<name>/<name>_truth.mat`` (other
    ``.mat`` files are ignored) into the library's layout: one row per
    tracked point, ``[x_1, y_1, ..., x_F, y_F]``. All trajectories are
    complete. The benchmark is the 155 sequences with 2 or 3 motions (120 +
    35); ``dancing`` (5 motions) is left out unless ``include_extra=True`` or
    it is named in ``sequences``.

    Parameters
    ----------
    data_home : str or path-like, default=None
        Folder holding the sequence folders, or its parent holding
        ``hopkins155/`` (or ``Hopkins155/``). None means
        ``$SKLEARN_GPCA_DATA/hopkins155`` if that environment variable is
        set, else ``sklearn.datasets.get_data_home()/hopkins155``.

    sequences : str or list of str, default=None
        Names of the sequences to load (``include_extra`` then does not
        apply). None loads all.

    n_motions : int or list of int, default=None
        Keep only sequences with this number of motions.

    category : {"checkerboard", "traffic", "articulated"} or list, default=None
        Keep only sequences of these categories (see
        :func:`hopkins155_category`).

    include_extra : bool, default=False
        Also load ``dancing``, which is not part of the 155.

    return_iterator : bool, default=False
        Return a generator reading one file at a time instead of a list.

    Returns
    -------
    sequences : list of Bunch, or generator of Bunch
        Sorted by name. Each Bunch has:

        - ``X``: ndarray of shape (n_points, 2 * n_frames), float64, the
          normalised image coordinates ``x[:2]`` of the file, used by the
          published results;
        - ``y``: ndarray of shape (n_points,), motion labels from 0 (the
          file's 1-based ``s``);
        - ``n_motions``, ``n_frames``, ``n_points``: int;
        - ``name``: str; ``category``: ``"checkerboard"``, ``"traffic"`` or
          ``"articulated"``;
        - ``X_pixels``: like ``X``, in pixels (the file's ``y[:2]``).

    Raises
    ------
    FileNotFoundError
        If no sequence is found under ``data_home``.
    ValueError
        For unknown sequence names or a malformed ``.mat`` file.

    See Also
    --------
    fetch_hopkins155 : Download the data first if it is missing.

    Notes
    -----
    Tron & Vidal's table of the benchmark: checkerboard 78 + 26, traffic
    31 + 7, articulated 11 + 2 sequences with 2 + 3 motions. In the four
    ``three-cars*`` sequences ``x`` is an affine rescaling of ``y`` rather
    than ``K^-1 y``; ``X`` uses ``x`` everywhere, as the published results
    do.

    References
    ----------
    .. [1] R. Tron and R. Vidal, "A benchmark for the comparison of 3-D
       motion segmentation algorithms", CVPR 2007.

    Examples
    --------
    >>> from sklearn_gpca.datasets import load_hopkins155
    >>> data = load_hopkins155(sequences=["1R2RC"])  # doctest: +SKIP
    >>> data[0].X.shape, data[0].n_motions, data[0].category  # doctest: +SKIP
    ((459, 58), 3, 'checkerboard')
    """
    return _load(
        data_home, sequences, n_motions, category, include_extra, return_iterator
    )


def _download(url, path):
    """Download ``url`` to ``path`` (replaced in tests; never called there)."""
    urllib.request.urlretrieve(url, path)


@validate_params(
    {
        "data_home": [str, os.PathLike, None],
        "download_if_missing": ["boolean"],
        **_LOAD_CONSTRAINTS,
    },
    prefer_skip_nested_validation=True,
)
def fetch_hopkins155(
    data_home=None,
    *,
    download_if_missing=True,
    sequences=None,
    n_motions=None,
    category=None,
    include_extra=False,
    return_iterator=False,
):
    """Load Hopkins155, downloading the official archive if it is missing.

    If ``data_home`` (or ``data_home/hopkins155``) holds the sequences they
    are loaded as by :func:`load_hopkins155`. Otherwise the archive
    ``Hopkins155.zip`` (about 1 GB with the videos) is downloaded from the
    JHU Vision Lab, extracted to ``data_home/hopkins155`` and then loaded.

    Parameters
    ----------
    data_home : str or path-like, default=None
        Folder to look in and download to. None means ``$SKLEARN_GPCA_DATA``
        if set, else ``sklearn.datasets.get_data_home()``.

    download_if_missing : bool, default=True
        If False, raise an ``OSError`` instead of downloading missing data.

    sequences, n_motions, category, include_extra, return_iterator
        As in :func:`load_hopkins155`.

    Returns
    -------
    sequences : list of Bunch, or generator of Bunch
        As in :func:`load_hopkins155`.

    Raises
    ------
    OSError
        If the data is missing and ``download_if_missing`` is False.

    See Also
    --------
    load_hopkins155 : Load data already on disk.

    Examples
    --------
    >>> from sklearn_gpca.datasets import fetch_hopkins155
    >>> data = fetch_hopkins155(n_motions=2)  # doctest: +SKIP
    >>> len(data)  # doctest: +SKIP
    120
    """
    folder, available = _resolve_hopkins155_home(data_home)
    if not available:
        if not download_if_missing:
            raise OSError(
                f"Hopkins155 not found in {folder} and download_if_missing=False."
            )
        base = default_data_home() if data_home is None else Path(data_home)
        base = base.expanduser()
        base.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryDirectory(dir=base) as tmp:
            archive = Path(tmp) / "Hopkins155.zip"
            _download(HOPKINS155_URL, archive)
            with zipfile.ZipFile(archive) as zf:
                zf.extractall(Path(tmp) / "extracted")
            root = Path(tmp) / "extracted"
            # The archive holds one top folder; move the folder that holds
            # the sequences to data_home/hopkins155.
            source = next(
                (
                    d
                    for d in [root, *sorted(root.rglob("*"))]
                    if d.is_dir() and _sequence_dirs(d)
                ),
                None,
            )
            if source is None:
                raise OSError(
                    f"The archive from {HOPKINS155_URL} holds no Hopkins155 sequences."
                )
            target = base / "hopkins155"
            target.mkdir(exist_ok=True)
            for child in source.iterdir():
                if not (target / child.name).exists():
                    shutil.move(str(child), str(target / child.name))
        data_home = base
    return _load(
        data_home, sequences, n_motions, category, include_extra, return_iterator
    )
