"""Veronese embedding of points and derivatives of homogeneous polynomials.

The Veronese map of degree ``n`` sends a point ``x`` in :math:`R^K` to the vector
``nu_n(x)`` of all ``M_n = C(n + K - 1, n)`` monomials ``x^e = x_1^e_1 ...
x_K^e_K`` with ``|e| = n`` (section 2.2.2 of Vidal & Hartley, CVPR 2004). A
homogeneous polynomial of degree ``n`` is ``p(x) = c^T nu_n(x)`` and its gradient
is again linear in ``c``: ``d x^e / d x_k = e_k x^(e - u_k)`` with ``u_k`` the
``k``-th unit vector, a monomial of degree ``n - 1``. Everything here is
vectorised over samples: time and memory are linear in ``n_samples``.
"""

# SPDX-License-Identifier: BSD-3-Clause

from itertools import combinations_with_replacement
from math import comb

import numpy as np


def n_monomials(n_features, degree):
    """Number ``M_n = C(degree + n_features - 1, degree)`` of monomials."""
    return comb(degree + n_features - 1, degree)


def _monomial_indices(n_features, degree):
    """Variable indices of each monomial, shape ``(M_n, degree)``.

    Row ``m`` lists the (sorted, repeated) variables whose product is the
    ``m``-th monomial, e.g. ``(0, 0, 2)`` for ``x_0^2 x_2``.
    """
    combos = list(combinations_with_replacement(range(n_features), degree))
    return np.array(combos, dtype=np.intp).reshape(len(combos), degree)


def veronese_exponents(n_features, degree):
    """Exponent matrix of the monomials of degree ``degree`` in ``n_features``.

    Parameters
    ----------
    n_features : int
        Number of variables ``K``.
    degree : int
        Degree ``n`` of the monomials, ``n >= 0``.

    Returns
    -------
    exponents : ndarray of shape (M_n, n_features), dtype=intp
        Row ``m`` holds the exponents ``e`` of monomial ``x^e``; every row sums
        to ``degree``. Rows follow ``itertools.combinations_with_replacement``
        order, the order used by :func:`veronese_map`.

    Examples
    --------
    >>> from sklearn_gpca._veronese import veronese_exponents
    >>> veronese_exponents(2, 2)
    array([[2, 0],
           [1, 1],
           [0, 2]])
    """
    indices = _monomial_indices(n_features, degree)
    n_mono = indices.shape[0]
    exponents = np.zeros((n_mono, n_features), dtype=np.intp)
    rows = np.repeat(np.arange(n_mono), degree)
    np.add.at(exponents, (rows, indices.ravel()), 1)
    return exponents


def veronese_map(X, degree):
    """Veronese embedding ``nu_n`` of every row of ``X``.

    Parameters
    ----------
    X : ndarray of shape (n_samples, n_features)
        Points in :math:`R^K`.
    degree : int
        Degree ``n >= 0`` of the embedding.

    Returns
    -------
    embedded : ndarray of shape (n_samples, M_n)
        ``embedded[i, m] = X[i] ** exponents[m]`` (product over features) with
        ``exponents = veronese_exponents(n_features, degree)``.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._veronese import veronese_map
    >>> veronese_map(np.array([[1.0, 2.0], [3.0, -1.0]]), 2)
    array([[ 1.,  2.,  4.],
           [ 9., -3.,  1.]])
    """
    X = np.asarray(X)
    indices = _monomial_indices(X.shape[1], degree)
    embedded = np.ones((X.shape[0], indices.shape[0]), dtype=X.dtype)
    for position in range(degree):
        embedded *= X[:, indices[:, position]]
    return embedded


def _derivative_terms(n_features, degree):
    """Sparse form of ``d nu_n / d x``.

    Returns arrays ``(mono, feature, lower, multiplicity)``, one entry per pair
    ``(m, k)`` with ``e_mk > 0``, such that ``d x^(e_m) / d x_k =
    multiplicity * x^(e_lower)``, where ``lower`` indexes the monomials of degree
    ``n - 1``.
    """
    exponents = veronese_exponents(n_features, degree)
    lower_exponents = veronese_exponents(n_features, degree - 1)
    mono, feature = np.nonzero(exponents)
    multiplicity = exponents[mono, feature]
    reduced = exponents[mono].copy()
    reduced[np.arange(mono.size), feature] -= 1
    # Exponent vectors are digits in base ``degree + 1``: match them by code.
    powers = (degree + 1) ** np.arange(n_features, dtype=np.int64)
    lower_codes = lower_exponents.astype(np.int64) @ powers
    order = np.argsort(lower_codes)
    positions = np.searchsorted(
        lower_codes, reduced.astype(np.int64) @ powers, sorter=order
    )
    lower = order[positions]
    return mono, feature, lower, multiplicity


def _check_degree(degree):
    if degree < 1:
        raise ValueError(f"Derivatives need degree >= 1, got degree={degree}.")


def polynomial_gradients(X, coef, degree):
    """Gradients of homogeneous polynomials ``c^T nu_n(x)`` at every row of ``X``.

    Parameters
    ----------
    X : ndarray of shape (n_samples, n_features)
        Points in :math:`R^K`.
    coef : ndarray of shape (M_n,) or (M_n, n_polynomials)
        Coefficients of one polynomial, or one polynomial per column, in the
        monomial order of :func:`veronese_exponents`.
    degree : int
        Degree ``n >= 1`` of the polynomials.

    Returns
    -------
    gradients : ndarray of shape (n_samples, n_features) or \
            (n_samples, n_polynomials, n_features)
        ``Dp(X[i])``; the 3-D shape is returned when ``coef`` is 2-D.

    Notes
    -----
    The gradient of a degree-``n`` polynomial is a vector of degree-``(n - 1)``
    polynomials, so it is computed as ``nu_{n-1}(X) @ G`` where ``G`` holds
    ``e_mk c_m`` at the row of monomial ``x^(e_m - u_k)``: one matrix product,
    linear in ``n_samples``.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._veronese import polynomial_gradients
    >>> # p(x, y) = x * y has gradient (y, x)
    >>> polynomial_gradients(np.array([[2.0, 3.0]]), np.array([0.0, 1.0, 0.0]), 2)
    array([[3., 2.]])
    """
    _check_degree(degree)
    X = np.asarray(X)
    coef = np.asarray(coef)
    n_features = X.shape[1]
    coef_2d = coef.reshape(coef.shape[0], -1)
    mono, feature, lower, multiplicity = _derivative_terms(n_features, degree)
    derivative = np.zeros(
        (n_monomials(n_features, degree - 1), n_features, coef_2d.shape[1]),
        dtype=np.result_type(X, coef),
    )
    derivative[lower, feature] = multiplicity[:, None] * coef_2d[mono]
    gradients = np.einsum(
        "pr,rkl->plk", veronese_map(X, degree - 1), derivative, optimize=True
    )
    return gradients[:, 0, :] if coef.ndim == 1 else gradients
