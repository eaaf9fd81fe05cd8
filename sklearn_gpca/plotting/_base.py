"""Shared helpers of the displays: lazy matplotlib, axes, labels."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
from scipy.optimize import linear_sum_assignment
from sklearn.exceptions import NotFittedError
from sklearn.utils.validation import check_is_fitted

from sklearn_gpca.metrics._misclassification import NOISE, noise_mask


def check_matplotlib_support(caller_name):
    """Import matplotlib, or raise an ImportError that says how to install it.

    Parameters
    ----------
    caller_name : str
        Name of the function or method that needs matplotlib.
    """
    try:
        import matplotlib  # noqa: F401
    except ImportError as exc:
        raise ImportError(
            f"{caller_name} requires matplotlib: pip install 'sklearn_gpca[plot]'"
        ) from exc


def get_axes(ax):
    """``(figure, ax)``: ``ax`` and its figure, or a new figure's axes."""
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots()
    return ax.figure, ax


def label_colors(n_labels):
    """``n_labels`` distinct colours (tab10, then tab20, then a colormap)."""
    import matplotlib as mpl

    if n_labels <= 10:
        return list(mpl.colormaps["tab10"].colors[:n_labels])
    if n_labels <= 20:
        return list(mpl.colormaps["tab20"].colors[:n_labels])
    return list(mpl.colormaps["turbo"](np.linspace(0, 1, n_labels)))


#: Colour of the noise label ``-1`` (outlier trajectories): mid grey.
NOISE_COLOR = "0.5"


def encode_labels(labels):
    """Labels as ``0 .. n - 1`` (sorted), and the original values."""
    values, codes = np.unique(np.asarray(labels), return_inverse=True)
    return codes.ravel(), values


def match_labels(y_true, y_pred):
    """``y_pred`` relabelled to agree best with ``y_true`` (Hungarian matching).

    The motions of ``y_true`` are coded ``0 .. n - 1`` (sorted); predicted
    groups matched to one of them take its code, the others the codes after.
    The noise label ``-1`` is never renamed: it stays ``-1`` on both sides,
    as in :func:`sklearn_gpca.metrics.misclassification_rate`.
    """
    y_true, y_pred = np.asarray(y_true).ravel(), np.asarray(y_pred).ravel()
    true_noise, pred_noise = noise_mask(y_true), noise_mask(y_pred)
    true = np.full(y_true.shape, NOISE, dtype=np.intp)
    pred = np.full(y_pred.shape, NOISE, dtype=np.intp)
    true_values, true[~true_noise] = np.unique(y_true[~true_noise], return_inverse=True)
    pred_values, pred_codes = np.unique(y_pred[~pred_noise], return_inverse=True)
    n_true, n_pred = true_values.size, pred_values.size
    pred[~pred_noise] = pred_codes
    both = ~true_noise & ~pred_noise
    counts = np.zeros((n_pred, n_true), dtype=np.int64)
    np.add.at(counts, (pred[both], true[both]), 1)
    rows, cols = linear_sum_assignment(-counts)
    mapping = np.empty(n_pred, dtype=np.intp)
    mapping[rows] = cols
    others = np.setdiff1d(np.arange(n_pred), rows)
    mapping[others] = n_true + np.arange(others.size)
    pred[~pred_noise] = mapping[pred_codes]
    return pred, true


def last_step(estimator):
    """The final estimator of a pipeline, or the estimator itself."""
    steps = getattr(estimator, "steps", None)
    return steps[-1][1] if steps else estimator


def is_fitted(estimator):
    try:
        check_is_fitted(estimator)
    except NotFittedError:
        return False
    return True


def cluster_labels(estimator, X):
    """``fit_predict(X)`` for an unfitted estimator, else ``predict(X)``."""
    if is_fitted(estimator):
        return np.asarray(estimator.predict(X))
    if hasattr(estimator, "fit_predict"):
        return np.asarray(estimator.fit_predict(X))
    return np.asarray(estimator.fit(X).predict(X))
