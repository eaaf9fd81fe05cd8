"""Helpers for matrices with missing entries (NaN or masked)."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np


def masked_to_nan(X):
    """Return ``X`` with the masked entries of a ``np.ma.MaskedArray`` as NaN.

    Anything that is not a masked array is returned unchanged, so that
    scikit-learn's validation sees lists, DataFrames and arrays as usual.
    """
    if not isinstance(X, np.ma.MaskedArray):
        return X
    dtype = X.dtype if np.issubdtype(X.dtype, np.floating) else np.float64
    return X.astype(dtype).filled(np.nan)


def describe_indices(indices, n_show=5):
    """Format ``indices`` as 'N (i, j, k, ...)' for error messages."""
    indices = np.asarray(indices)
    shown = ", ".join(str(i) for i in indices[:n_show])
    more = ", ..." if indices.size > n_show else ""
    return f"{indices.size} ({shown}{more})"
