"""Loader for low-rank matrix factorisation benchmarks with missing data."""

# SPDX-License-Identifier: BSD-3-Clause

import os
from pathlib import Path

import numpy as np
import scipy.io
import scipy.sparse
from sklearn.utils import Bunch
from sklearn.utils._param_validation import validate_params

from sklearn_gpca.datasets._home import default_data_home


def _lowrank_home(data_home):
    if data_home is None:
        data_home = default_data_home()
    data_home = Path(data_home).expanduser()
    return data_home / "lowrank" if (data_home / "lowrank").is_dir() else data_home


def _find_file(name_or_path, data_home):
    path = Path(name_or_path).expanduser()
    if path.suffix.lower() == ".mat":
        if not path.is_file():
            raise FileNotFoundError(f"No such .mat file: {path}.")
        return path
    home = _lowrank_home(data_home)
    folders = (
        {d.name.lower(): d for d in home.iterdir() if d.is_dir()}
        if home.is_dir()
        else {}
    )
    folder = folders.get(str(name_or_path).lower())
    if folder is not None:
        path = folder / f"{folder.name.lower()}.mat"
        if path.is_file():
            return path
        mats = sorted(p for p in folder.iterdir() if p.suffix.lower() == ".mat")
        if len(mats) == 1:
            return mats[0]
        if not mats:
            raise FileNotFoundError(f"{folder} holds no .mat file.")
        raise ValueError(
            f"{folder} holds several .mat files ({', '.join(p.name for p in mats)})"
            "; pass the path of one of them."
        )
    if not folders:
        raise FileNotFoundError(
            f"No low-rank datasets (<Name>/<name>.mat) found in {home}; pass "
            "data_home or set SKLEARN_GPCA_DATA."
        )
    raise ValueError(
        f"Unknown low-rank dataset {name_or_path!r} in {home}; available: "
        f"{sorted(d.name for d in folders.values())}."
    )


def _get_matrix(data, key, path):
    if key not in data:
        raise ValueError(
            f"Malformed low-rank file {path}: missing variable {key!r} "
            f"(found {sorted(k for k in data if not k.startswith('__'))})."
        )
    value = data[key]
    if scipy.sparse.issparse(value):
        value = value.toarray()
    value = np.asarray(value)
    if value.ndim != 2:
        raise ValueError(
            f"Malformed low-rank file {path}: {key!r} must be a matrix, got shape "
            f"{value.shape}."
        )
    return value


def _layout(mask):
    """How the rows/columns of ``M`` are organised, judged from the mask."""
    n_rows, n_cols = mask.shape
    if n_rows % 2 == 0 and np.array_equal(mask[0::2], mask[1::2]):
        return "tracks"
    if n_cols % 2 == 0 and np.array_equal(mask[:, 0::2], mask[:, 1::2]):
        return "tracks_transposed"
    return "matrix"


@validate_params(
    {"name_or_path": [str, os.PathLike], "data_home": [str, os.PathLike, None]},
    prefer_skip_nested_validation=True,
)
def load_lowrank(name_or_path, *, data_home=None):
    """Load a low-rank matrix completion benchmark with missing entries.

    The benchmarks collected for Hong & Fitzgibbon (ICCV 2015) store a
    measurement matrix ``M`` and a mask ``W`` (1 observed, 0 missing) in
    ``<Name>/<name>.mat``. Feature tracks are returned in the library's
    layout, one row per point ``[x_1, y_1, ..., x_F, y_F]`` with NaN where
    missing.

    Parameters
    ----------
    name_or_path : str or path-like
        Dataset name, case-insensitive (``"Dino_trimmed"``, ``"Dino"``,
        ``"Giraffe"``, ``"Um_boy"``, ``"Face"``, ...), or the path of a
        ``.mat`` file holding ``M`` and ``W``.

    data_home : str or path-like, default=None
        Folder holding the ``<Name>`` folders, or its parent holding
        ``lowrank/``. None means ``$SKLEARN_GPCA_DATA`` if set, else
        ``sklearn.datasets.get_data_home()``.

    Returns
    -------
    data : Bunch
        - ``X``: ndarray of shape (n_samples, n_features), float64, NaN where
          missing;
        - ``mask``: bool ndarray of the same shape, True where observed;
        - ``name``: str, the file name without ``.mat``;
        - ``layout``: ``"tracks"``, ``"tracks_transposed"`` or ``"matrix"``,
          how ``M`` was stored (see Notes);
        - ``n_frames``: int, or None for ``layout="matrix"``.

    Raises
    ------
    FileNotFoundError
        If the file or the data folder does not exist.
    ValueError
        For an unknown name, or a file without matrices ``M`` and ``W`` of
        the same shape.

    See Also
    --------
    load_hopkins155 : Complete trajectories with ground-truth motions.

    Notes
    -----
    The layout is read from the mask, in which both coordinates of a point
    are missing together:

    - ``"tracks"``: ``M`` is ``2F x P`` (rows ``x_1, y_1, x_2, ...``); ``X``
      is ``M.T``. Dino, Dino_trimmed, Um_boy, Um_giraffe_bg, Um_giraffe_fg.
    - ``"tracks_transposed"``: ``M`` is ``P x 2F``, already one row per
      point ``[x_1, y_1, ..., x_F, y_F]``, so ``X`` is ``M`` (Giraffe: 166
      points x 120 frames; consecutive columns of a pair move by about a
      pixel between frames, whereas rows jump between unrelated points).
    - ``"matrix"``: no x/y pairing, e.g. the photometric-stereo matrices
      Face, Face_trimmed (20 images x pixels) and Sculpture (46 images x
      pixels) whose entries are intensities in [0, 1]; ``X`` is ``M.T`` (one
      row per pixel, one column per image) and ``n_frames`` is None.

    A mask with no missing entry cannot tell the layouts apart; ``"tracks"``
    is assumed. Entries of ``M`` that are not finite are treated as missing.
    In the files as distributed, ``M`` holds NaN at the missing entries of
    the track matrices and arbitrary numbers at those of Face; both become
    NaN.

    References
    ----------
    .. [1] J. H. Hong and A. Fitzgibbon, "Secrets of matrix factorization:
       approximations, numerics, manifold optimization and random restarts",
       ICCV 2015.

    Examples
    --------
    >>> from sklearn_gpca.datasets import load_lowrank
    >>> dino = load_lowrank("Dino_trimmed")  # doctest: +SKIP
    >>> dino.X.shape, dino.n_frames  # doctest: +SKIP
    ((319, 72), 36)
    """
    path = _find_file(name_or_path, data_home)
    try:
        data = scipy.io.loadmat(path)
    except Exception as exc:  # scipy raises several types on bad files
        raise ValueError(f"Could not read low-rank file {path}: {exc}") from exc
    M = _get_matrix(data, "M", path).astype(np.float64)
    W = _get_matrix(data, "W", path)
    if M.shape != W.shape:
        raise ValueError(
            f"Malformed low-rank file {path}: 'M' and 'W' must have the same "
            f"shape, got {M.shape} and {W.shape}."
        )
    mask = (W != 0) & np.isfinite(M)
    layout = _layout(W != 0)
    if layout == "tracks_transposed":
        # Already one row per point, [x_1, y_1, ..., x_F, y_F].
        n_frames = M.shape[1] // 2
    else:
        M, mask = M.T, mask.T
        n_frames = M.shape[1] // 2 if layout == "tracks" else None
    X = np.where(mask, M, np.nan)
    return Bunch(
        X=np.ascontiguousarray(X),
        mask=np.ascontiguousarray(mask),
        name=path.stem,
        layout=layout,
        n_frames=n_frames,
    )
