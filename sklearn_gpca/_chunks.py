"""Row chunks that bound the temporaries of per-row computations."""

# SPDX-License-Identifier: BSD-3-Clause

# Default rows per chunk: the per-row temporaries stay small whatever n_rows.
CHUNK_ROWS = 2**16


def row_chunks(n_rows, size=CHUNK_ROWS):
    """Slices of at most ``size`` consecutive rows covering ``range(n_rows)``.

    Examples
    --------
    >>> from sklearn_gpca._chunks import row_chunks
    >>> list(row_chunks(5, size=2))
    [slice(0, 2, None), slice(2, 4, None), slice(4, 5, None)]
    """
    for start in range(0, n_rows, size):
        yield slice(start, min(start + size, n_rows))
