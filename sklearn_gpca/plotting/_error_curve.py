"""Segmentation error against a parameter, e.g. the fraction of missing data."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
from sklearn.base import clone
from sklearn.utils import check_random_state

from sklearn_gpca.plotting._base import check_matplotlib_support, get_axes

#: ``param_name`` that removes entries of ``X`` instead of setting a parameter.
MISSING_FRACTION = "missing_fraction"


class ErrorCurveDisplay:
    """Error (mean and spread over repeats) against a parameter.

    Use :meth:`from_estimator` to compute the curve, e.g. against the
    fraction of missing entries, or :meth:`from_predictions` to draw errors
    computed elsewhere.

    Parameters
    ----------
    param_values : ndarray of shape (n_values,)
        The values of the parameter (x axis).
    errors : ndarray of shape (n_values,) or (n_values, n_repeats)
        The error at every value, one column per repeat.
    param_name : str, default=None
        Label of the x axis.
    error_name : str, default="misclassification rate"
        Label of the y axis.
    name : str, default=None
        Name of the curve in the legend.

    Attributes
    ----------
    line_ : matplotlib Line2D
        The mean error.
    fill_between_ : matplotlib PolyCollection or None
        The band between the smallest and largest error over the repeats.
    ax_ : matplotlib Axes
        Axes with the curve.
    figure_ : matplotlib Figure
        Figure containing the axes.

    See Also
    --------
    sklearn.model_selection.ValidationCurveDisplay : Scores against a
        hyper-parameter, with cross-validation.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from sklearn_gpca.plotting import ErrorCurveDisplay
    >>> display = ErrorCurveDisplay.from_predictions(
    ...     [0.0, 0.2, 0.4], [0.01, 0.02, 0.05], param_name="missing fraction"
    ... )
    >>> display.line_.get_ydata().tolist()
    [0.01, 0.02, 0.05]
    """

    def __init__(
        self,
        param_values,
        errors,
        *,
        param_name=None,
        error_name="misclassification rate",
        name=None,
    ):
        self.param_values = param_values
        self.errors = errors
        self.param_name = param_name
        self.error_name = error_name
        self.name = name

    def plot(self, ax=None, *, name=None, band=True, **kwargs):
        """Draw the mean error, and its range over repeats as a band.

        Parameters
        ----------
        ax : matplotlib Axes, default=None
            Axes to draw on; None creates a figure. Draw several curves on
            the same axes to compare estimators.
        name : str, default=None
            Legend entry; overrides the ``name`` given at construction.
        band : bool, default=True
            Shade between the smallest and largest error over the repeats.
        **kwargs : dict
            Passed to ``ax.plot``.

        Returns
        -------
        display : ErrorCurveDisplay
        """
        check_matplotlib_support("ErrorCurveDisplay.plot")
        x = np.asarray(self.param_values, dtype=np.float64).ravel()
        errors = np.asarray(self.errors, dtype=np.float64)
        if errors.ndim == 1:
            errors = errors[:, None]
        if errors.ndim != 2 or errors.shape[0] != x.shape[0]:
            raise ValueError(
                f"errors must have shape ({x.shape[0]},) or ({x.shape[0]}, "
                f"n_repeats), got {np.shape(self.errors)}."
            )
        fig, ax = get_axes(ax)
        name = self.name if name is None else name
        kwargs.setdefault("marker", "o")
        (self.line_,) = ax.plot(x, errors.mean(axis=1), label=name, **kwargs)
        self.fill_between_ = None
        if band and errors.shape[1] > 1:
            self.fill_between_ = ax.fill_between(
                x,
                errors.min(axis=1),
                errors.max(axis=1),
                alpha=0.2,
                color=self.line_.get_color(),
            )
        if self.param_name is not None:
            ax.set_xlabel(self.param_name)
        ax.set_ylabel(self.error_name)
        if name is not None:
            ax.legend(loc="best")
        self.ax_ = ax
        self.figure_ = fig
        return self

    @classmethod
    def from_predictions(
        cls,
        param_values,
        errors,
        *,
        param_name=None,
        error_name="misclassification rate",
        name=None,
        ax=None,
        **kwargs,
    ):
        """Draw errors computed elsewhere.

        Parameters
        ----------
        param_values : array-like of shape (n_values,)
            The values of the parameter.
        errors : array-like of shape (n_values,) or (n_values, n_repeats)
            The errors.
        param_name : str, default=None
            Label of the x axis.
        error_name : str, default="misclassification rate"
            Label of the y axis.
        name : str, default=None
            Legend entry.
        ax : matplotlib Axes, default=None
            Axes to draw on; None creates a figure.
        **kwargs : dict
            Passed to :meth:`plot`.

        Returns
        -------
        display : ErrorCurveDisplay
        """
        check_matplotlib_support(f"{cls.__name__}.from_predictions")
        display = cls(
            param_values,
            errors,
            param_name=param_name,
            error_name=error_name,
            name=name,
        )
        return display.plot(ax=ax, **kwargs)

    @classmethod
    def from_estimator(
        cls,
        estimator,
        X,
        y,
        *,
        param_name,
        param_values,
        n_repeats=1,
        missing_pattern="occlusion",
        scoring=None,
        random_state=None,
        name=None,
        ax=None,
        **kwargs,
    ):
        """Segment `X` for every parameter value and draw the error.

        Parameters
        ----------
        estimator : estimator or Pipeline
            A clusterer; cloned for every fit.
        X : array-like of shape (n_samples, n_features)
            Data (complete if ``param_name="missing_fraction"``).
        y : array-like of shape (n_samples,)
            Ground-truth labels.
        param_name : str
            A parameter of `estimator` (``set_params`` syntax, e.g.
            ``"gpcaclustering__n_neighbors"``), or ``"missing_fraction"`` to
            remove that fraction of the entries of `X` with
            :func:`sklearn_gpca.datasets.make_missing` instead.
        param_values : array-like of shape (n_values,)
            Values of the parameter.
        n_repeats : int, default=1
            Fits per value (new missing-data masks each time, and the
            estimator's own randomness if its ``random_state`` is None).
        missing_pattern : {"occlusion", "random"}, default="occlusion"
            Pattern of the removed entries for ``"missing_fraction"``.
        scoring : callable, default=None
            ``scoring(y_true, y_pred)``, an error (lower is better); None is
            :func:`sklearn_gpca.metrics.misclassification_rate`.
        random_state : int, RandomState instance or None, default=None
            Seeds the missing-data masks.
        name : str, default=None
            Legend entry.
        ax : matplotlib Axes, default=None
            Axes to draw on; None creates a figure.
        **kwargs : dict
            Passed to :meth:`plot`.

        Returns
        -------
        display : ErrorCurveDisplay
        """
        check_matplotlib_support(f"{cls.__name__}.from_estimator")
        from sklearn_gpca.datasets import make_missing
        from sklearn_gpca.metrics import misclassification_rate

        scoring = misclassification_rate if scoring is None else scoring
        rng = check_random_state(random_state)
        values = list(param_values)
        errors = np.empty((len(values), n_repeats))
        for i, value in enumerate(values):
            for r in range(n_repeats):
                model = clone(estimator)
                data = X
                if param_name == MISSING_FRACTION:
                    data = make_missing(
                        X, value, pattern=missing_pattern, random_state=rng
                    )
                else:
                    model.set_params(**{param_name: value})
                errors[i, r] = scoring(y, model.fit_predict(data))
        return cls.from_predictions(
            values,
            errors,
            param_name=param_name.replace("_", " "),
            name=name,
            ax=ax,
            **kwargs,
        )
