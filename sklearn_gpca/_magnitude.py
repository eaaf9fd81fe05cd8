"""Exact rescaling of coordinates of extreme magnitude.

The segmentations do not depend on the unit of the coordinates, but their
sums of squares underflow below about ``1e-154`` and overflow above about
``1e154``. Coordinates outside a safe range are multiplied by a power of two,
which is exact in floating point: every other input is left bit for bit as
it was.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

#: Largest observed magnitudes left unchanged: their squares, and sums of
#: billions of them, stay far from the float64 limits.
SAFE_RANGE = (2.0**-128, 2.0**128)


def in_safe_range(X):
    """``X`` brought into the safe range by an exact power-of-two factor.

    Parameters
    ----------
    X : ndarray
        Coordinates, NaN where missing (finite otherwise).

    Returns
    -------
    X : ndarray
        ``X`` itself when its largest observed magnitude is zero or within
        :data:`SAFE_RANGE`; otherwise ``X * factor`` with its largest
        magnitude in ``[0.5, 1)``.
    factor : float
        The power of two applied (1.0 when ``X`` is returned unchanged).
    """
    peak = np.nanmax(np.abs(X), initial=0.0)
    if peak == 0 or SAFE_RANGE[0] <= peak <= SAFE_RANGE[1]:
        return X, 1.0
    exponent = int(np.frexp(peak)[1])
    return np.ldexp(X, -exponent), float(np.ldexp(1.0, -exponent))
