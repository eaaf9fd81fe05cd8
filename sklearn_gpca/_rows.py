"""Row-wise helpers shared by the GPCA stages: unit rows and a canonical sign."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

TINY = np.finfo(np.float64).tiny


def unit_rows(X):
    """Rows of ``X`` scaled to unit Euclidean norm; zero rows stay zero.

    Each row is first multiplied by the power of two that brings its largest
    entry into ``[0.5, 1)``. That multiplication is exact, so for rows of
    ordinary scale the result is bit for bit ``x / ||x||``, and for rows near
    the ends of the floating-point range (``1e-300``, ``1e300``) the squared
    norm neither underflows to zero nor overflows to infinity.

    Parameters
    ----------
    X : ndarray of shape (n_samples, n_features)
        Finite rows.

    Returns
    -------
    unit : ndarray of shape (n_samples, n_features)

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._rows import unit_rows
    >>> unit_rows(np.array([[3e-300, 4e-300], [0.0, 0.0], [0.0, -2e300]]))
    array([[ 0.6,  0.8],
           [ 0. ,  0. ],
           [ 0. , -1. ]])
    """
    X = np.asarray(X, dtype=np.float64)
    _, exponents = np.frexp(np.max(np.abs(X), axis=1, keepdims=True))
    scaled = np.ldexp(X, -exponents)
    norms = np.linalg.norm(scaled, axis=1, keepdims=True)
    return scaled / np.maximum(norms, TINY)


def power_of_two_scale(X):
    """``X`` times the power of two that brings its largest entry into ``[0.5, 1)``.

    A global scale changes no linear subspace and no ratio between rows, and a
    power of two changes no digit: the result is exact.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._rows import power_of_two_scale
    >>> power_of_two_scale(np.array([[1.0, -3.0], [0.5, 2.0]]))
    array([[ 0.25 , -0.75 ],
           [ 0.125,  0.5  ]])
    """
    X = np.asarray(X, dtype=np.float64)
    largest = np.max(np.abs(X)) if X.size else 0.0
    if largest == 0.0:
        return X
    return np.ldexp(X, -np.frexp(largest)[1])


def canonical_sign(vectors):
    """Flip each row so that its largest-magnitude entry is positive.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._rows import canonical_sign
    >>> canonical_sign(np.array([[0.1, -0.9], [0.5, 0.2]]))
    array([[-0.1,  0.9],
           [ 0.5,  0.2]])
    """
    vectors = np.atleast_2d(vectors)
    largest = vectors[np.arange(vectors.shape[0]), np.argmax(np.abs(vectors), axis=1)]
    return vectors * np.where(largest < 0, -1.0, 1.0)[:, None]
