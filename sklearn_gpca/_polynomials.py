"""Vanishing polynomials of a union of subspaces and their normal subspaces.

Section 2.2.4 of Vidal & Hartley (CVPR 2004), "Modelling low-dimension
subspaces": when the subspaces are not hyperplanes, the embedded data matrix
``W~`` (one Veronese-embedded point per column) has a null space of dimension
greater than one. Each null vector ``c_l`` is a homogeneous polynomial
``p_l(x) = c_l^T nu_n(x)`` vanishing on every subspace, and at a point ``x`` of
subspace ``S`` the gradients ``Dp_l(x)`` span the orthogonal complement of
``S`` (for generic points). Everything is computed from the ``M_n x M_n`` Gram
matrix ``W~ W~^T``, accumulated over chunks of rows: linear in the number of
points.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
from scipy.linalg import eigh

from sklearn_gpca._chunks import row_chunks
from sklearn_gpca._memory import chunk_rows
from sklearn_gpca._rows import canonical_sign, unit_rows
from sklearn_gpca._veronese import n_monomials, polynomial_gradients, veronese_map


def embedded_spectrum(points, degree):
    """Singular values and right singular vectors of ``veronese_map(points, degree)``.

    Parameters
    ----------
    points : ndarray of shape (n_samples, n_features)
        Points, one per row.
    degree : int
        Degree ``n`` of the embedding.

    Returns
    -------
    singular_values : ndarray of shape (n_monomials,)
        In increasing order.
    vectors : ndarray of shape (n_monomials, n_monomials)
        Column ``l`` is the coefficient vector of the polynomial with the
        ``l``-th smallest residual ``||W~^T c||``.
    """
    gram = 0.0
    n_mono = n_monomials(points.shape[1], degree)
    for rows in row_chunks(points.shape[0], chunk_rows(2 * 8 * n_mono)):
        embedded = veronese_map(points[rows], degree)
        gram = gram + embedded.T @ embedded
    values, vectors = eigh(gram)
    return np.sqrt(np.maximum(values, 0.0)), vectors


def null_space_dimension(singular_values):
    """Numerical dimension of the null space of the embedded data.

    The largest gap in the log singular values: with ``s_1 <= ... <= s_M``
    (floored at ``1e-12 s_M``), the ``m`` maximising ``s_{m + 1} / s_m``.
    Noise lifts the zero singular values of the null space to the noise
    level; the gap to the first singular value carried by the data stays the
    largest as long as the noise is small against the subspaces' separation.

    Parameters
    ----------
    singular_values : ndarray of shape (n_monomials,)
        In increasing order, as returned by :func:`embedded_spectrum`.

    Returns
    -------
    n_polynomials : int
        Between 1 and ``n_monomials - 1``.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._polynomials import null_space_dimension
    >>> null_space_dimension(np.array([1e-3, 2e-3, 0.5, 0.7, 1.0]))
    2
    """
    values = np.maximum(singular_values, 1e-12 * singular_values[-1])
    if values.shape[0] < 2:
        return 1
    return int(np.argmax(np.diff(np.log(values)))) + 1


def vanishing_polynomials(points, degree):
    """The homogeneous polynomials of degree ``degree`` that vanish on ``points``.

    Step 2 of Algorithm 1 (equation (9)) and section 2.2.4: the right singular
    vectors of the embedded data ``W~`` for its smallest singular values, as
    many as :func:`null_space_dimension` finds.

    Parameters
    ----------
    points : ndarray of shape (n_samples, n_features)
        Points, one per row.
    degree : int
        Degree ``n`` of the polynomials: the number of subspaces.

    Returns
    -------
    polynomials : ndarray of shape (n_polynomials, n_monomials)
        Orthonormal coefficient vectors, each signed so that its
        largest-magnitude entry is positive; the first is the single polynomial
        of the paper, the best fit ``argmin ||W~^T c||`` with ``||c|| = 1``.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._polynomials import vanishing_polynomials
    >>> # the lines y = 0 and x = 0 of the plane: p(x, y) = x y
    >>> points = np.array([[1.0, 0.0], [2.0, 0.0], [0.0, 1.0], [0.0, -3.0]])
    >>> np.round(vanishing_polynomials(points, 2), 6) + 0.0
    array([[0., 1., 0.]])
    """
    singular_values, vectors = embedded_spectrum(points, degree)
    n_polynomials = null_space_dimension(singular_values)
    return canonical_sign(vectors[:, :n_polynomials].T)


def unit_gradients(points, coef, degree):
    """Unit gradients ``Dp(x) / ||Dp(x)||`` of the polynomial ``coef`` at ``points``.

    Section 2.2.3: the normal at each point. Computed in chunks of rows;
    zero gradients stay zero.

    Parameters
    ----------
    points : ndarray of shape (n_samples, n_features)
        Points, one per row.
    coef : ndarray of shape (n_monomials,)
        Coefficients of the polynomial.
    degree : int
        Its degree.

    Returns
    -------
    normals : ndarray of shape (n_samples, n_features)

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca.stages import (
    ...     unit_rows, vanishing_polynomials, unit_gradients)
    >>> rng = np.random.RandomState(0)
    >>> # two planes of R^3: z = 0 and x = 0
    >>> unit = unit_rows(np.vstack([rng.randn(20, 3) * [1, 1, 0],
    ...                             rng.randn(20, 3) * [0, 1, 1]]))
    >>> coef = vanishing_polynomials(unit, 2)[0]  # the polynomial x z
    >>> np.abs(unit_gradients(unit, coef, 2)[[0, -1]]).round(3)
    array([[0., 0., 1.],
           [1., 0., 0.]])
    """
    normals = np.empty_like(points)
    for rows in row_chunks(points.shape[0]):
        normals[rows] = unit_rows(polynomial_gradients(points[rows], coef, degree))
    return normals


def polynomial_normal_bases(points, coefs, degree, tol):
    """Normal subspace at each point from the gradients of several polynomials.

    Parameters
    ----------
    points : ndarray of shape (n_samples, n_features)
        Points (unit vectors).
    coefs : ndarray of shape (n_monomials, n_polynomials)
        Orthonormal coefficient vectors of the vanishing polynomials.
    degree : int
        Their degree.
    tol : float
        A direction of the ``(n_polynomials, n_features)`` gradient matrix
        ``[Dp_1(x_i); ...]`` with singular value ``s_l <= tol * s_1`` is
        noise; the others span the normal subspace (at least one does).

    Returns
    -------
    bases : ndarray of shape (n_samples, n_features, n_features)
        ``bases[i][:, l]`` for ``l < codims[i]`` is an orthonormal basis of
        the normal subspace at point ``i``, strongest direction first; the
        remaining columns are zero.
    codims : ndarray of shape (n_samples,), dtype=intp
        Its dimension, at most ``min(n_polynomials, n_features - 1)``.
    """
    n_samples, n_features = points.shape
    bases = np.zeros((n_samples, n_features, n_features))
    codims = np.ones(n_samples, dtype=np.intp)
    per_row = 3 * 8 * coefs.shape[1] * n_features
    for rows in row_chunks(n_samples, chunk_rows(per_row)):
        gradients = polynomial_gradients(points[rows], coefs, degree)
        _, values, vt = np.linalg.svd(gradients, full_matrices=False)
        keep = values > tol * values[:, :1]
        keep[:, 0] = True
        keep[:, n_features - 1 :] = False
        width = vt.shape[1]
        bases[rows, :, :width] = vt.transpose(0, 2, 1) * keep[:, None, :]
        codims[rows] = np.count_nonzero(keep, axis=1)
    return bases, codims
