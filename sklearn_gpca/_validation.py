"""Parameter constraints shared by the estimators."""

# SPDX-License-Identifier: BSD-3-Clause

from numbers import Integral

from sklearn.utils._param_validation import Interval


class Count(Interval):
    """An integer interval that refuses booleans.

    ``True`` is an :class:`numbers.Integral` in Python, so scikit-learn's
    ``Interval(Integral, ...)`` lets ``n_clusters=True`` through as 1.

    Examples
    --------
    >>> from sklearn_gpca._validation import Count
    >>> count = Count(1, None, closed="left")
    >>> count.is_satisfied_by(3), count.is_satisfied_by(True)
    (True, False)
    """

    def __init__(self, left, right, *, closed):
        super().__init__(Integral, left, right, closed=closed)

    def is_satisfied_by(self, val):
        return not isinstance(val, bool) and super().is_satisfied_by(val)
