"""Misclassification rate under the best one-to-one matching of labels."""

# SPDX-License-Identifier: BSD-3-Clause

import copy

import numpy as np
from scipy.optimize import linear_sum_assignment
from sklearn.metrics import get_scorer as _sklearn_get_scorer
from sklearn.metrics import make_scorer
from sklearn.utils._param_validation import StrOptions, validate_params

#: The label of points that belong to no motion (as DBSCAN and HDBSCAN).
NOISE = -1


def noise_mask(labels):
    """Where ``labels`` hold the noise label ``-1`` (numeric labels only)."""
    labels = np.asarray(labels)
    if labels.dtype.kind not in "iuf":
        return np.zeros(labels.shape, dtype=bool)
    return labels == NOISE


def _n_matched(y_true, y_pred):
    """Most points on which ``y_pred``, renamed one-to-one, agrees with
    ``y_true`` (the Hungarian algorithm on the contingency matrix)."""
    if y_true.size == 0:
        return 0
    _, true_idx = np.unique(y_true, return_inverse=True)
    _, pred_idx = np.unique(y_pred, return_inverse=True)
    contingency = np.zeros((true_idx.max() + 1, pred_idx.max() + 1), dtype=np.int64)
    np.add.at(contingency, (true_idx, pred_idx), 1)
    rows, cols = linear_sum_assignment(contingency, maximize=True)
    return int(contingency[rows, cols].sum())


@validate_params(
    {
        "y_true": ["array-like"],
        "y_pred": ["array-like"],
        "noise": [StrOptions({"class", "ignore"})],
    },
    prefer_skip_nested_validation=True,
)
def misclassification_rate(y_true, y_pred, *, noise="class"):
    """Fraction of points misclassified under the best matching of labels.

    Clustering labels are arbitrary names, so the predicted clusters are first
    matched one-to-one to the true groups so as to maximise the number of
    agreeing points (the Hungarian algorithm on the contingency matrix), and
    the rate is the fraction of points outside the matched pairs. This is the
    misclassification error reported for motion segmentation (Vidal & Hartley
    2004, Table 1; the Hopkins155 benchmark).

    The label ``-1`` marks noise (outlier trajectories), as in
    :class:`~sklearn.cluster.DBSCAN` and :class:`~sklearn.cluster.HDBSCAN`.
    It is a name with a meaning, so it is never renamed: a point is right
    as noise only where both labels are ``-1``, a true outlier put in a
    motion is an error, and so is an inlier flagged as noise.

    Parameters
    ----------
    y_true : array-like of shape (n_samples,)
        Ground-truth labels (any hashable values of one type; ``-1`` is
        noise for numeric labels).

    y_pred : array-like of shape (n_samples,)
        Predicted cluster labels (``-1`` is noise for numeric labels).

    noise : {"class", "ignore"}, default="class"
        How points whose true label is ``-1`` are scored.

        - ``"class"``: they count, as a class that is never renamed; the
          rate then also charges outliers assigned to a motion.
        - ``"ignore"``: they are left out, and the rate is over the true
          inliers only (an inlier predicted ``-1`` still counts as an
          error). This is the misclassification of the inliers that the
          motion-segmentation literature reports beside a separate score of
          the outlier detection (Rao et al. 2010).

    Returns
    -------
    rate : float
        Misclassification rate in ``[0, 1]``; ``0.0`` for a perfect
        segmentation up to a renaming of the labels.

    Raises
    ------
    ValueError
        If the labels are not 1-D, differ in length or are empty, or if
        ``noise="ignore"`` leaves no point.

    See Also
    --------
    sklearn.metrics.adjusted_rand_score : Chance-adjusted pair-counting index.
    sklearn.metrics.normalized_mutual_info_score : Information-based index.

    Notes
    -----
    With contingency matrix :math:`C_{ij} = |\\{p : y^{true}_p = i,\\;
    y^{pred}_p = j\\}|` over the points whose labels are both not noise,
    and :math:`n_{-1}` the points labelled ``-1`` on both sides, the rate is

    .. math:: 1 - \\frac{1}{n} \\left(n_{-1} + \\max_{\\sigma} \\sum_i
       C_{i \\sigma(i)}\\right)

    over one-to-one partial matchings :math:`\\sigma` between true and
    predicted labels, solved exactly with
    :func:`scipy.optimize.linear_sum_assignment`. The numbers of clusters may
    differ: points of clusters left unmatched on either side count as
    misclassified, so splitting a group or merging two groups is penalised.

    References
    ----------
    .. [1] S. Rao, R. Tron, R. Vidal and Y. Ma, "Motion segmentation in the
       presence of outlying, incomplete, or corrupted trajectories", IEEE
       TPAMI 32(10), 2010.

    Examples
    --------
    >>> from sklearn_gpca.metrics import misclassification_rate
    >>> misclassification_rate([0, 0, 1, 1], [1, 1, 0, 0])
    0.0
    >>> round(misclassification_rate([0, 0, 0, 1, 1, 1], [1, 1, 0, 0, 0, 0]), 4)
    0.1667
    >>> round(misclassification_rate([0, 0, 1, 1, 2, 2], [0, 0, 1, 1, 1, 1]), 4)
    0.3333

    An outlier (``-1``) put in a motion is an error, unless outliers are
    left out:

    >>> misclassification_rate([-1, 0, 0, 1, 1], [1, 0, 0, 1, 1])
    0.2
    >>> misclassification_rate([-1, 0, 0, 1, 1], [1, 0, 0, 1, 1], noise="ignore")
    0.0
    """
    y_true = np.asarray(y_true)
    y_pred = np.asarray(y_pred)
    for name, labels in (("y_true", y_true), ("y_pred", y_pred)):
        if labels.ndim != 1:
            raise ValueError(
                f"{name} must be 1-D, got an array of shape {labels.shape}."
            )
    if y_true.shape[0] != y_pred.shape[0]:
        raise ValueError(
            "y_true and y_pred must have the same length, got "
            f"{y_true.shape[0]} and {y_pred.shape[0]}."
        )
    if y_true.shape[0] == 0:
        raise ValueError("y_true and y_pred are empty; need at least 1 label.")
    true_noise, pred_noise = noise_mask(y_true), noise_mask(y_pred)
    if noise == "ignore":
        inliers = ~true_noise
        if not inliers.any():
            raise ValueError(
                "every point of y_true is noise (-1): nothing to score with "
                "noise='ignore'."
            )
        y_true, y_pred = y_true[inliers], y_pred[inliers]
        true_noise, pred_noise = true_noise[inliers], pred_noise[inliers]
    both = ~true_noise & ~pred_noise
    n_right = np.sum(true_noise & pred_noise) + _n_matched(y_true[both], y_pred[both])
    n_samples = y_true.shape[0]
    return float((n_samples - n_right) / n_samples)


misclassification_scorer = make_scorer(misclassification_rate, greater_is_better=False)
misclassification_scorer.__doc__ = """Scorer returning minus the misclassification rate.

Built with ``make_scorer(misclassification_rate, greater_is_better=False)``;
it calls ``estimator.predict(X)``, so the estimator (a clusterer such as a
pipeline ending in a fitted clusterer) must implement ``predict``. The noise
label ``-1`` is scored as in :func:`misclassification_rate`; for the rate on
the true inliers only, use ``make_scorer(misclassification_rate,
greater_is_better=False, noise="ignore")``.
"""

_SCORERS = {"neg_misclassification_rate": misclassification_scorer}


def get_scorer(scoring):
    """Get a scorer by name, knowing this package's scorers as well.

    scikit-learn has no public registry for third-party scorer names
    (``sklearn.metrics.get_scorer`` reads a private dictionary), so a string
    like ``scoring="neg_misclassification_rate"`` cannot be given to
    :class:`~sklearn.model_selection.GridSearchCV` directly. Pass the scorer
    object instead (``scoring=misclassification_scorer``, or a dict such as
    ``{"misclassification": misclassification_scorer}`` for multi-metric
    search), or resolve the name with this function first.

    Parameters
    ----------
    scoring : str, callable or None
        ``"neg_misclassification_rate"``, any name known to
        :func:`sklearn.metrics.get_scorer`, a callable (returned as is) or
        None (returned as is).

    Returns
    -------
    scorer : callable or None
        A copy of the named scorer, or ``scoring`` itself if not a string.

    Examples
    --------
    >>> from sklearn_gpca.metrics import get_scorer
    >>> get_scorer("neg_misclassification_rate")
    make_scorer(misclassification_rate, greater_is_better=False, ...)
    >>> get_scorer("adjusted_rand_score")
    make_scorer(adjusted_rand_score, ...)
    """
    if isinstance(scoring, str) and scoring in _SCORERS:
        return copy.deepcopy(_SCORERS[scoring])
    return _sklearn_get_scorer(scoring)


def get_scorer_names():
    """Names accepted by :func:`get_scorer`: this package's and scikit-learn's.

    Returns
    -------
    names : list of str
        Sorted scorer names.

    Examples
    --------
    >>> from sklearn_gpca.metrics import get_scorer_names
    >>> "neg_misclassification_rate" in get_scorer_names()
    True
    """
    from sklearn.metrics import get_scorer_names as _sklearn_names

    return sorted({*_SCORERS, *_sklearn_names()})
