"""What a pattern of observed entries can determine in a rank-r fit.

The observed entries of ``X`` form a bipartite graph between rows
(trajectories) and columns (image coordinates of a frame). A rank-r fit has
``r`` unknowns per row and per column, so a row or a column observed fewer
than ``r`` times cannot be determined, and a graph that falls apart into
several pieces leaves the fit across pieces arbitrary.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
from scipy import sparse
from scipy.sparse.csgraph import connected_components


def determinable(mask, rank):
    """Rows and columns that can take part in a rank-``rank`` fit.

    Rows observed in fewer than ``rank`` of the kept columns and columns
    observed in fewer than ``rank`` of the kept rows are removed, repeatedly,
    since removing one can leave another short (the ``rank``-core of the
    bipartite graph of observed entries).

    Parameters
    ----------
    mask : ndarray of shape (n_samples, n_features)
        1.0 where observed, 0.0 where missing.
    rank : int

    Returns
    -------
    rows : ndarray of shape (n_samples,), dtype=bool
    columns : ndarray of shape (n_features,), dtype=bool

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._mask_graph import determinable
    >>> mask = np.ones((4, 5))
    >>> mask[0, 1:] = 0  # row 0 seen once, so column 0 is seen by 3 kept rows
    >>> rows, columns = determinable(mask, 3)
    >>> rows.astype(int), columns.astype(int)
    (array([0, 1, 1, 1]), array([1, 1, 1, 1, 1]))
    """
    rows = np.ones(mask.shape[0], dtype=bool)
    columns = np.ones(mask.shape[1], dtype=bool)
    while True:
        kept_rows = rows & (mask @ columns >= rank)
        kept_columns = columns & (kept_rows @ mask >= rank)
        if np.array_equal(kept_rows, rows) and np.array_equal(kept_columns, columns):
            return rows, columns
        rows, columns = kept_rows, kept_columns


def n_connected_blocks(mask):
    """Number of pieces of the bipartite graph of observed entries.

    Rows and columns with no observed entry are not counted.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._mask_graph import n_connected_blocks
    >>> mask = np.zeros((4, 4))
    >>> mask[:2, :2] = mask[2:, 2:] = 1
    >>> n_connected_blocks(mask)
    2
    """
    mask = mask[mask.any(axis=1)][:, mask.any(axis=0)]
    n_rows = mask.shape[0]
    edges = sparse.csr_matrix(mask != 0)
    graph = sparse.bmat([[None, edges], [edges.T, None]])
    if n_rows + mask.shape[1] == 0:
        return 0
    n_blocks, _ = connected_components(graph, directed=False)
    return n_blocks
