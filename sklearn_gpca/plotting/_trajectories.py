"""Trajectories in the image plane, coloured by motion."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
from sklearn.utils import check_array

from sklearn_gpca._missing import masked_to_nan
from sklearn_gpca.metrics._misclassification import noise_mask
from sklearn_gpca.plotting._base import (
    NOISE_COLOR,
    check_matplotlib_support,
    cluster_labels,
    encode_labels,
    get_axes,
    label_colors,
    match_labels,
)


def _check_trajectories(X):
    X = check_array(masked_to_nan(X), dtype=np.float64, ensure_all_finite="allow-nan")
    if X.shape[1] % 2:
        raise ValueError(
            f"X must have an even number of columns [x_1, y_1, ..., x_F, y_F], "
            f"got {X.shape[1]}."
        )
    return X


class TrajectoryDisplay:
    """Point trajectories coloured by their motion label.

    Draws the tracks of Figure 1 of Vidal & Hartley (2004): every trajectory
    ``[x_1, y_1, ..., x_F, y_F]`` in the image plane, with one colour per
    label. Missing entries (NaN) break the track. Use
    :meth:`from_estimator` or :meth:`from_predictions` to create one.

    Parameters
    ----------
    X : ndarray or masked array of shape (n_samples, 2 * n_frames)
        Trajectories, one per row, NaN (or masked) for missing entries.
    labels : ndarray of shape (n_samples,)
        Label of each trajectory; ``-1`` (noise, outlier trajectories) is
        drawn in grey as "outliers (-1)".
    misclassified : ndarray of shape (n_samples,), dtype=bool, default=None
        Trajectories to mark as wrong (black crosses at their last point).

    Attributes
    ----------
    lines_ : list of matplotlib LineCollection or Quiver
        One artist per label.
    ax_ : matplotlib Axes
        Axes with the trajectories.
    figure_ : matplotlib Figure
        Figure containing the axes.

    See Also
    --------
    SimilarityMatrixDisplay : Similarity matrix ordered by label.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from sklearn.pipeline import make_pipeline
    >>> from sklearn_gpca import GPCAClustering, PowerFactorization
    >>> from sklearn_gpca.datasets import make_motions
    >>> from sklearn_gpca.plotting import TrajectoryDisplay
    >>> X, y = make_motions(2, n_points=50, random_state=0)
    >>> pipe = make_pipeline(PowerFactorization(), GPCAClustering(2, random_state=0))
    >>> display = TrajectoryDisplay.from_estimator(pipe, X, y_true=y)
    >>> len(display.lines_)
    2
    """

    def __init__(self, X, labels, *, misclassified=None):
        self.X = X
        self.labels = labels
        self.misclassified = misclassified

    def plot(
        self,
        ax=None,
        *,
        kind="tracks",
        frames=None,
        invert_yaxis=True,
        legend=True,
        title=None,
    ):
        """Draw the trajectories.

        Parameters
        ----------
        ax : matplotlib Axes, default=None
            Axes to draw on; None creates a figure.
        kind : {"tracks", "displacement"}, default="tracks"
            ``"tracks"``: the image positions over the frames as a polyline
            with a dot at the last observed one. ``"displacement"``: an arrow
            from the first to the last of ``frames``.
        frames : tuple of int, default=None
            Frames (0-based) to draw: ``(first, last)``; None uses all frames.
        invert_yaxis : bool, default=True
            Image convention: y grows downwards.
        legend : bool, default=True
            Show one legend entry per label.
        title : str, default=None
            Axes title.

        Returns
        -------
        display : TrajectoryDisplay
        """
        check_matplotlib_support("TrajectoryDisplay.plot")
        from matplotlib.collections import LineCollection

        if kind not in ("tracks", "displacement"):
            raise ValueError(f"kind must be 'tracks' or 'displacement', got {kind!r}.")
        X = _check_trajectories(self.X)
        n_frames = X.shape[1] // 2
        first, last = (0, n_frames - 1) if frames is None else frames
        if not 0 <= first < last < n_frames:
            raise ValueError(
                f"frames must satisfy 0 <= first < last < n_frames={n_frames}, "
                f"got {(first, last)}."
            )
        tracks = X.reshape(X.shape[0], n_frames, 2)[:, first : last + 1]
        codes, values = encode_labels(self.labels)
        if codes.shape[0] != X.shape[0]:
            raise ValueError(
                f"labels has {codes.shape[0]} entries for {X.shape[0]} trajectories."
            )
        is_noise = noise_mask(values)
        motion_colors = iter(label_colors(int(np.sum(~is_noise))))
        colors = [NOISE_COLOR if noise else next(motion_colors) for noise in is_noise]
        names = [
            "outliers (-1)" if noise else f"motion {value}"
            for value, noise in zip(values, is_noise, strict=True)
        ]
        fig, ax = get_axes(ax)
        self.lines_ = []
        for k in range(values.size):
            members = tracks[codes == k]
            if kind == "tracks":
                artist = LineCollection(
                    list(members),
                    colors=[colors[k]],
                    linewidths=0.8,
                    alpha=0.8,
                    label=names[k],
                )
                ax.add_collection(artist)
                ends = np.array([_last_observed(track) for track in members]).reshape(
                    -1, 2
                )
                ax.scatter(ends[:, 0], ends[:, 1], s=6, color=colors[k])
            else:
                start, end = members[:, 0], members[:, -1]
                artist = ax.quiver(
                    start[:, 0],
                    start[:, 1],
                    end[:, 0] - start[:, 0],
                    end[:, 1] - start[:, 1],
                    color=colors[k],
                    angles="xy",
                    scale_units="xy",
                    scale=1,
                    width=0.003,
                    label=names[k],
                )
            self.lines_.append(artist)
        if self.misclassified is not None and np.any(self.misclassified):
            wrong = np.array(
                [_last_observed(t) for t in tracks[np.asarray(self.misclassified)]]
            ).reshape(-1, 2)
            ax.scatter(
                wrong[:, 0],
                wrong[:, 1],
                marker="x",
                color="black",
                s=25,
                label=f"misclassified ({wrong.shape[0]})",
            )
        ax.autoscale_view()
        shared = any(
            len(group.get_siblings(ax)) > 1
            for group in (ax.get_shared_x_axes(), ax.get_shared_y_axes())
        )
        ax.set_aspect("equal", adjustable="box" if shared else "datalim")
        if invert_yaxis and not ax.yaxis_inverted():
            ax.invert_yaxis()
        ax.set_xlabel("x")
        ax.set_ylabel("y")
        if title is not None:
            ax.set_title(title)
        if legend:
            ax.legend(loc="best", fontsize="small")
        self.ax_ = ax
        self.figure_ = fig
        return self

    @classmethod
    def from_predictions(cls, X, labels, *, y_true=None, ax=None, **kwargs):
        """Draw trajectories coloured by given labels.

        Parameters
        ----------
        X : array-like of shape (n_samples, 2 * n_frames)
            Trajectories, NaN (or masked) for missing entries.
        labels : array-like of shape (n_samples,)
            Predicted (or true) label of each trajectory.
        y_true : array-like of shape (n_samples,), default=None
            Ground truth. If given, ``labels`` are matched to it (optimal
            assignment) so that colours agree, and the misclassified
            trajectories are marked, with the rule of
            :func:`~sklearn_gpca.metrics.misclassification_rate`: the noise
            label ``-1`` is never renamed, so a true outlier is right only as
            ``-1`` and an inlier labelled ``-1`` is wrong.
        ax : matplotlib Axes, default=None
            Axes to draw on; None creates a figure.
        **kwargs : dict
            Passed to :meth:`plot` (``kind``, ``frames``, ``invert_yaxis``,
            ``legend``, ``title``).

        Returns
        -------
        display : TrajectoryDisplay
        """
        check_matplotlib_support(f"{cls.__name__}.from_predictions")
        n_samples = _check_trajectories(X).shape[0]
        labels = np.asarray(labels).ravel()
        for name, values in (("labels", labels), ("y_true", y_true)):
            if values is not None and len(np.ravel(values)) != n_samples:
                raise ValueError(
                    f"{name} has {len(np.ravel(values))} entries for {n_samples} "
                    "trajectories."
                )
        misclassified = None
        if y_true is not None:
            labels, true = match_labels(y_true, labels)
            misclassified = labels != true
        return cls(X, labels, misclassified=misclassified).plot(ax=ax, **kwargs)

    @classmethod
    def from_estimator(cls, estimator, X, *, y_true=None, ax=None, **kwargs):
        """Segment `X` with a clusterer and draw the trajectories.

        Parameters
        ----------
        estimator : estimator or Pipeline
            A clusterer, e.g. ``make_pipeline(PowerFactorization(),
            GPCAClustering(n))``. If it is not fitted its ``fit_predict(X)``
            gives the labels, else its ``predict(X)``.
        X : array-like of shape (n_samples, 2 * n_frames)
            Trajectories, NaN (or masked) for missing entries.
        y_true : array-like of shape (n_samples,), default=None
            Ground truth, see :meth:`from_predictions`.
        ax : matplotlib Axes, default=None
            Axes to draw on; None creates a figure.
        **kwargs : dict
            Passed to :meth:`plot`.

        Returns
        -------
        display : TrajectoryDisplay
        """
        check_matplotlib_support(f"{cls.__name__}.from_estimator")
        labels = cluster_labels(estimator, X)
        return cls.from_predictions(X, labels, y_true=y_true, ax=ax, **kwargs)


def _last_observed(track):
    observed = np.flatnonzero(~np.isnan(track).any(axis=1))
    return track[observed[-1]] if observed.size else np.full(2, np.nan)
