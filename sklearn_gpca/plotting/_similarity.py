"""Similarity (affinity) matrices ordered by label."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
from sklearn.utils import check_array

from sklearn_gpca.plotting._base import (
    check_matplotlib_support,
    cluster_labels,
    encode_labels,
    get_axes,
    is_fitted,
    last_step,
)

#: Largest number of points for which a dense similarity matrix is formed.
MAX_SAMPLES = 5000


def gpca_similarity(point_normals):
    """Dense GPCA similarity ``S_ij = cos^2(theta_ij) = (n_i . n_j)^2``.

    Parameters
    ----------
    point_normals : array-like of shape (n_samples, n_features)
        Unit normals, e.g. ``GPCAClustering.point_normals_``.

    Returns
    -------
    S : ndarray of shape (n_samples, n_samples)
    """
    normals = check_array(point_normals, dtype=np.float64)
    return (normals @ normals.T) ** 2


class SimilarityMatrixDisplay:
    """A similarity matrix with its rows and columns ordered by label.

    For a good segmentation the matrix is block diagonal, as in Figure 2 of
    Vidal & Hartley (2004), which compares the Costeira-Kanade shape
    interaction matrix with the GPCA similarity ``cos^2`` of the angles
    between the normals. Use :meth:`from_estimator` or
    :meth:`from_predictions` to create one.

    Parameters
    ----------
    similarity : ndarray of shape (n_samples, n_samples)
        Symmetric similarity matrix.
    labels : ndarray of shape (n_samples,), default=None
        Labels by which to order (stably) the rows and columns; None keeps the
        given order.

    Attributes
    ----------
    im_ : matplotlib AxesImage
        The drawn matrix.
    order_ : ndarray of shape (n_samples,)
        Permutation applied to the rows and columns.
    ax_ : matplotlib Axes
        Axes with the matrix.
    figure_ : matplotlib Figure
        Figure containing the axes.

    See Also
    --------
    sklearn_gpca.shape_interaction_matrix : Costeira-Kanade matrix ``Q``.
    TrajectoryDisplay : Trajectories coloured by label.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from sklearn.pipeline import make_pipeline
    >>> from sklearn_gpca import GPCAClustering, PowerFactorization
    >>> from sklearn_gpca.datasets import make_motions
    >>> from sklearn_gpca.plotting import SimilarityMatrixDisplay
    >>> X, y = make_motions(2, n_points=50, random_state=0)
    >>> pipe = make_pipeline(PowerFactorization(), GPCAClustering(2, random_state=0))
    >>> display = SimilarityMatrixDisplay.from_estimator(pipe, X, y=y)
    >>> display.similarity.shape
    (50, 50)
    """

    def __init__(self, similarity, labels=None):
        self.similarity = similarity
        self.labels = labels

    def plot(self, ax=None, *, cmap="viridis", colorbar=True, title=None, **kwargs):
        """Draw the ordered matrix, with lines between the label blocks.

        Parameters
        ----------
        ax : matplotlib Axes, default=None
            Axes to draw on; None creates a figure.
        cmap : str or matplotlib Colormap, default="viridis"
            Colour map.
        colorbar : bool, default=True
            Add a colour bar.
        title : str, default=None
            Axes title.
        **kwargs : dict
            Passed to ``ax.imshow`` (e.g. ``vmin``, ``vmax``).

        Returns
        -------
        display : SimilarityMatrixDisplay
        """
        check_matplotlib_support("SimilarityMatrixDisplay.plot")
        S = check_array(self.similarity, dtype=np.float64)
        if S.shape[0] != S.shape[1]:
            raise ValueError(f"similarity must be square, got shape {S.shape}.")
        fig, ax = get_axes(ax)
        if self.labels is None:
            order, boundaries = np.arange(S.shape[0]), []
        else:
            codes, _ = encode_labels(self.labels)
            if codes.shape[0] != S.shape[0]:
                raise ValueError(
                    f"labels has {codes.shape[0]} entries for a "
                    f"{S.shape[0]} x {S.shape[0]} similarity matrix."
                )
            order = np.argsort(codes, kind="stable")
            boundaries = np.cumsum(np.bincount(codes))[:-1]
        self.im_ = ax.imshow(
            S[np.ix_(order, order)], cmap=cmap, interpolation="nearest", **kwargs
        )
        for b in boundaries:
            ax.axhline(b - 0.5, color="white", linewidth=0.8)
            ax.axvline(b - 0.5, color="white", linewidth=0.8)
        ax.set_xticks([])
        ax.set_yticks([])
        if colorbar:
            fig.colorbar(self.im_, ax=ax, fraction=0.046, pad=0.04)
        if title is not None:
            ax.set_title(title)
        self.order_ = order
        self.ax_ = ax
        self.figure_ = fig
        return self

    @classmethod
    def from_predictions(cls, similarity, labels=None, *, ax=None, **kwargs):
        """Draw a given similarity matrix ordered by given labels.

        Parameters
        ----------
        similarity : array-like of shape (n_samples, n_samples)
            E.g. ``np.abs(shape_interaction_matrix(X, rank))``.
        labels : array-like of shape (n_samples,), default=None
            Labels (true or predicted) that order the rows and columns.
        ax : matplotlib Axes, default=None
            Axes to draw on; None creates a figure.
        **kwargs : dict
            Passed to :meth:`plot`.

        Returns
        -------
        display : SimilarityMatrixDisplay
        """
        check_matplotlib_support(f"{cls.__name__}.from_predictions")
        return cls(similarity, labels).plot(ax=ax, **kwargs)

    @classmethod
    def from_estimator(
        cls, estimator, X=None, *, y=None, ax=None, max_samples=MAX_SAMPLES, **kwargs
    ):
        """Draw the similarity a fitted clusterer used.

        For :class:`~sklearn_gpca.GPCAClustering` (alone or at the end of a
        pipeline) this is the dense GPCA similarity ``(n_i . n_j)^2`` of its
        ``point_normals_``, which the estimator itself never forms (it works on
        a sparse graph or a low-rank factor), so ``n_samples`` is capped by
        ``max_samples``. For estimators with an ``affinity_matrix_``
        (:class:`~sklearn_gpca.ShapeInteractionClustering`,
        :class:`sklearn.cluster.SpectralClustering`) it is that matrix.

        Parameters
        ----------
        estimator : estimator or Pipeline
            A clusterer; fitted on `X` first if it is not fitted.
        X : array-like of shape (n_samples, n_features), default=None
            Training data; needed only if `estimator` is not fitted.
        y : array-like of shape (n_samples,), default=None
            Labels that order the matrix; None uses the estimator's labels.
        ax : matplotlib Axes, default=None
            Axes to draw on; None creates a figure.
        max_samples : int, default=5000
            Refuse to form a larger dense matrix.
        **kwargs : dict
            Passed to :meth:`plot`.

        Returns
        -------
        display : SimilarityMatrixDisplay
        """
        check_matplotlib_support(f"{cls.__name__}.from_estimator")
        if not is_fitted(estimator):
            if X is None:
                raise ValueError("X is required to fit an unfitted estimator.")
            cluster_labels(estimator, X)
        final = last_step(estimator)
        if hasattr(final, "point_normals_"):
            n_samples = final.point_normals_.shape[0]
            if n_samples > max_samples:
                raise ValueError(
                    f"n_samples={n_samples} exceeds max_samples={max_samples}: the "
                    f"dense similarity would have {n_samples**2} entries."
                )
            similarity = gpca_similarity(final.point_normals_)
        elif hasattr(final, "affinity_matrix_"):
            similarity = final.affinity_matrix_
            if hasattr(similarity, "toarray"):
                similarity = similarity.toarray()
        else:
            raise ValueError(
                f"{type(final).__name__} exposes neither point_normals_ nor "
                "affinity_matrix_; use from_predictions with a similarity matrix."
            )
        labels = final.labels_ if y is None else y
        return cls(similarity, labels).plot(ax=ax, **kwargs)
