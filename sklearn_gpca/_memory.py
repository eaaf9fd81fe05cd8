"""Memory the GPCA stages ask for, estimated before they allocate it.

Two kinds of arrays. Per-row temporaries (a chunk of the Veronese embedding,
the features of a chunk of graph edges) are cut into chunks that fit in
scikit-learn's ``working_memory`` (``sklearn.set_config``, 1 GiB by default).
The arrays a stage must hold whole (the ``M_n x M_n`` Gram matrix of the
embedding, the normal basis of every point, the factor of the all-pairs
kernel) are added up before the fit starts; when they exceed the machine's
physical memory the fit stops with an error that names the sizes and how to
reduce them, instead of asking the system for them.
"""

# SPDX-License-Identifier: BSD-3-Clause

import os

from sklearn import get_config

from sklearn_gpca._chunks import CHUNK_ROWS
from sklearn_gpca._veronese import n_monomials

_FLOAT = 8  # bytes of a float64
_GIB = 2**30


def physical_memory():
    """Bytes of physical memory of this machine, or None if unknown."""
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        return None


def chunk_rows(bytes_per_row, max_rows=CHUNK_ROWS):
    """Rows per chunk so that a chunk's temporaries fit in ``working_memory``.

    Examples
    --------
    >>> from sklearn_gpca._memory import chunk_rows
    >>> chunk_rows(8 * 35)  # the Veronese rows of degree 3 in R^5
    65536
    >>> chunk_rows(2**30)
    1
    """
    working = get_config()["working_memory"] * 2**20
    return int(max(1, min(max_rows, working // max(bytes_per_row, 1))))


def gpca_memory(n_samples, n_features, n_clusters, p):
    """The arrays :func:`~sklearn_gpca.gpca` holds whole, in bytes, by name.

    Parameters
    ----------
    n_samples, n_features : int
        Shape of ``X``.
    n_clusters : int
        Degree of the polynomials.
    p : dict
        The keyword arguments of :func:`~sklearn_gpca.gpca`.

    Returns
    -------
    parts : dict of str to int
        Upper bounds of the largest arrays of each stage (with the
        workspace of their decompositions), which are alive at once.
    """
    n_mono = n_monomials(n_features, n_clusters)
    n_pairs = n_features * (n_features + 1) // 2
    graph = p["affinity"] == "nearest_neighbors"
    limit = p["max_spectral_samples"]
    segmented = min(n_samples, limit) if graph and limit else n_samples
    columns = 1 if p["point_normals"] == "one_polynomial" else n_features
    parts = {
        "the points (unit rows, copies)": 4 * n_samples * n_features * _FLOAT,
        f"the {n_mono} x {n_mono} Gram matrix of the Veronese embedding "
        "and its eigenvectors": 3 * n_mono**2 * _FLOAT,
        "the normal basis of every point": 3
        * segmented
        * n_features
        * columns
        * _FLOAT,
    }
    # chunked temporaries: at most working_memory at a time
    chunks = get_config()["working_memory"] * 2**20
    if graph:
        # the coarse scale of init="multi" has 1.5 n_neighbors neighbours
        n_edges = segmented * min(2 * p["n_neighbors"], max(segmented - 1, 1))
        parts["the nearest-neighbour graphs"] = (
            segmented * n_pairs * _FLOAT
            + 6 * 3 * n_edges * _FLOAT
            + min(chunks, 2 * n_edges * n_pairs * _FLOAT)
        )
    else:
        parts["the factor of the all-pairs kernel and its SVD"] = (
            3 * n_samples * n_pairs * _FLOAT
            + min(chunks, 2 * n_samples * n_pairs * columns * _FLOAT)
        )
    return parts


def check_gpca_memory(n_samples, n_features, n_clusters, p):
    """Raise before :func:`~sklearn_gpca.gpca` asks for more than the machine has.

    Raises
    ------
    ValueError
        Naming the total, its largest part, the machine's memory and the
        projection that would reduce it.

    Examples
    --------
    >>> from sklearn_gpca._memory import check_gpca_memory
    >>> p = dict(affinity="nearest_neighbors", max_spectral_samples=5000,
    ...          point_normals="local", n_neighbors=30)
    >>> check_gpca_memory(300_000, 50, 4, p)
    Traceback (most recent call last):
    ...
    ValueError: GPCAClustering(n_clusters=4) on X of 300000 x 50 needs about ...
    """
    available = physical_memory()
    parts = gpca_memory(n_samples, n_features, n_clusters, p)
    total = sum(parts.values())
    if available is None or total <= available:
        return
    largest = max(parts, key=parts.get)
    raise ValueError(
        f"GPCAClustering(n_clusters={n_clusters}) on X of {n_samples} x "
        f"{n_features} needs about {total / _GIB:.1f} GiB, more than this "
        f"machine's {available / _GIB:.1f} GiB; the largest part is {largest} "
        f"({parts[largest] / _GIB:.1f} GiB). The polynomial has "
        f"C(n_clusters + n_features - 1, n_clusters) monomials and the normals "
        "n_features^2 entries per point: project the points to a few "
        "dimensions first, e.g. make_pipeline(PowerFactorization("
        "n_components=5), GPCAClustering(...)), and keep max_spectral_samples "
        "bounded."
    )
