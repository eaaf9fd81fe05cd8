"""Estimator around :func:`sklearn_gpca.segment_motions`."""

# SPDX-License-Identifier: BSD-3-Clause

from numbers import Integral, Real

import numpy as np
from sklearn.base import BaseEstimator, ClusterMixin, _fit_context
from sklearn.utils._param_validation import Interval, StrOptions
from sklearn.utils.validation import check_is_fitted, validate_data

from sklearn_gpca._missing import masked_to_nan
from sklearn_gpca._motion_models import MotionModels
from sklearn_gpca._observed_subspaces import observed_entries
from sklearn_gpca._segment import segment_motions
from sklearn_gpca._validation import Count


class MotionSegmentation(ClusterMixin, BaseEstimator):
    """Segment raw tracks with missing entries into rigid motions.

    The estimator of :func:`segment_motions`: full-space segmentation of
    trajectories as a tracker gives them (NaN where a track is not seen),
    beyond the paper's projection to ``R^5``. Candidate segmentations from
    motion-affinity fragments, from ``PowerFactorization`` +
    ``GPCAClustering`` and from votes for local perspective and subspace
    hypotheses (as :class:`PerspectiveClustering`; ``init="auto"`` leaves
    them out) are refined by smoothed
    K-subspaces on each track's observed entries in ``R^{2F}``, and one is
    kept by ``selection`` (by default the best fit among the candidates
    whose own motion models, a perspective camera for the largest, explain
    the most tracks better than the other motions' models do);
    optionally, tracks that fit no motion are labelled ``-1``. See
    :func:`segment_motions` for the stages and every parameter.

    Parameters
    ----------
    n_clusters : int, default=2
        Number of motions.

    init : {"auto", "all", "fragments", "gpca", "votes", "peel", "subsample"}, \
            default="all"
        Candidate segmentations (see :func:`segment_motions`).

    selection : {"consistency", "separability", "fitted_separability", \
            "coding_length"}, default="consistency"
        How the refined candidate is kept (see :func:`segment_motions`).

    merge_split : bool, default=False
        Try merge/split moves on the kept segmentation (see
        :func:`segment_motions`).

    misfit_moves : bool, default=True
        Give a label to the tracks that misfit the kept background's
        perspective cameras (see :func:`segment_motions`).

    subspace_dim : int, default=4
        Dimension of the motion subspaces.

    smoothing : float, default=3.0
        Cost of a neighbour with another label, in units of a track's typical
        misfit, weighted by how alike the two tracks move.

    n_neighbors : int, default=10
        Neighbours of the smoothing term.

    per_cluster : bool, default=True
        One misfit scale per motion.

    max_iter : int, default=30
        Maximum rounds of the refinement.

    outlier_threshold : float in (0, 1) or None, default=None
        Label ``-1`` the tracks that fit no motion, at this false-alarm
        probability per track (e.g. ``1e-3``; see
        :func:`~sklearn_gpca.segment_motions`); None labels every track.

    screen_outliers : bool or "kept", default=True
        Without ``outlier_threshold``: set aside the tracks the outlier test
        flags at ``1e-3`` while the motions are found, then give each the
        nearest motion; the candidates drawn from every track are judged
        too, on the kept tracks, unless ``"kept"`` (see
        :func:`~sklearn_gpca.segment_motions`).

    perspective_background : bool, default=True
        Also refine every candidate with its largest motion (the background of
        tracker output) seen by a perspective camera, and choose among both
        sets (see :func:`~sklearn_gpca.segment_motions`).

    n_init : int, default=1
        Runs of the segmentation with different random states (the first
        ``random_state`` itself); the run the consistency rule judges best is
        kept, as :class:`~sklearn.cluster.KMeans` keeps its run of least
        inertia (see :func:`~sklearn_gpca.segment_motions`). A little more
        than ``n_init`` times the time (the runs are judged too).

    random_state : int, RandomState instance or None, default=None
        Seeds the spectral clustering, k-means and the projections.

    n_jobs : int or None, default=None
        Processes that refine and judge the candidates; the labels do not
        depend on it (see :func:`~sklearn_gpca.segment_motions`). None means
        1 unless in a :func:`joblib.parallel_config` context, -1 every core.

    Attributes
    ----------
    labels_ : ndarray of shape (n_samples,)
        Motion of each track, ``-1`` for the outliers.

    candidates_ : list of str
        Names of the candidate segmentations compared.

    coding_lengths_ : ndarray of shape (n_candidates,)
        Coding length (bits) of each refined candidate.

    ambiguity_ : ndarray of shape (n_candidates,)
        Share of ambiguous tracks of each refined candidate (see
        :func:`sklearn_gpca._segment_selection.ambiguous_fraction`).

    inconsistency_ : ndarray of shape (n_candidates,)
        Share of tracks nearer another motion's model than their own, for
        each refined candidate (see
        :func:`sklearn_gpca._model_consistency.model_consistency`).

    objectives_ : ndarray of shape (n_candidates,)
        Value of the refinement's objective at each refined candidate (see
        :func:`sklearn_gpca._refine_observed.refinement_objective`; lower fits
        better, NaN for a candidate with outliers).

    chosen_ : str
        The candidate kept.

    n_iter_ : int
        Rounds of the refinement of the chosen candidate.

    noise_ : float
        Estimated noise variance per coordinate, in units of the tracks
        scaled by the RMS of their observed entries.

    n_features_in_ : int
        Number of features seen during :term:`fit`.

    sizes_ : ndarray of shape (n_clusters,)
        Tracks of each motion in ``labels_``.

    See Also
    --------
    segment_motions : The function this estimator calls.
    GPCAClustering : Subspace clustering of projected trajectories (the paper).

    Examples
    --------
    >>> from sklearn_gpca import MotionSegmentation
    >>> from sklearn_gpca.datasets import make_motions
    >>> from sklearn_gpca.metrics import misclassification_rate
    >>> X, y = make_motions(2, n_points=[120, 60], n_frames=10, missing=0.3,
    ...                     missing_pattern="occlusion", random_state=0)
    >>> labels = MotionSegmentation(2, random_state=0).fit_predict(X)
    >>> misclassification_rate(y, labels) < 0.05
    True
    """

    _parameter_constraints: dict = {
        "n_clusters": [Count(1, None, closed="left")],
        "init": [
            StrOptions(
                {"auto", "all", "fragments", "gpca", "votes", "peel", "subsample"}
            )
        ],
        "selection": [
            StrOptions(
                {"consistency", "coding_length", "separability", "fitted_separability"}
            )
        ],
        "merge_split": ["boolean"],
        "misfit_moves": ["boolean"],
        "subspace_dim": [Count(1, None, closed="left")],
        "smoothing": [Interval(Real, 0, None, closed="left")],
        "n_neighbors": [Count(1, None, closed="left")],
        "per_cluster": ["boolean"],
        "max_iter": [Count(1, None, closed="left")],
        "outlier_threshold": [Interval(Real, 0, 1, closed="neither"), None],
        "screen_outliers": ["boolean", StrOptions({"kept"})],
        "perspective_background": ["boolean"],
        "n_init": [Count(1, None, closed="left")],
        "random_state": ["random_state"],
        "n_jobs": [Integral, None],
    }

    def __init__(
        self,
        n_clusters=2,
        *,
        init="all",
        selection="consistency",
        merge_split=False,
        misfit_moves=True,
        subspace_dim=4,
        smoothing=3.0,
        n_neighbors=10,
        per_cluster=True,
        max_iter=30,
        outlier_threshold=None,
        screen_outliers=True,
        perspective_background=True,
        n_init=1,
        random_state=None,
        n_jobs=None,
    ):
        self.n_clusters = n_clusters
        self.init = init
        self.selection = selection
        self.merge_split = merge_split
        self.misfit_moves = misfit_moves
        self.subspace_dim = subspace_dim
        self.smoothing = smoothing
        self.n_neighbors = n_neighbors
        self.per_cluster = per_cluster
        self.max_iter = max_iter
        self.outlier_threshold = outlier_threshold
        self.screen_outliers = screen_outliers
        self.perspective_background = perspective_background
        self.n_init = n_init
        self.random_state = random_state
        self.n_jobs = n_jobs

    @_fit_context(prefer_skip_nested_validation=True)
    def fit(self, X, y=None):
        """Segment the tracks ``X``.

        Parameters
        ----------
        X : array-like or masked array of shape (n_samples, n_features)
            Trajectories ``[x_1, y_1, ..., x_F, y_F]``, one per row; missing
            entries are NaN (or masked).

        y : Ignored
            Not used, present for API consistency by convention.

        Returns
        -------
        self : object
            Fitted estimator.
        """
        X = validate_data(
            self,
            masked_to_nan(X),
            dtype=np.float64,
            ensure_all_finite="allow-nan",
            ensure_min_samples=2,
        )
        if self.n_clusters > X.shape[0]:
            raise ValueError(
                f"n_clusters={self.n_clusters} is larger than the number of "
                f"tracks ({X.shape[0]})."
            )
        labels, info = segment_motions(
            X,
            self.n_clusters,
            init=self.init,
            selection=self.selection,
            merge_split=self.merge_split,
            misfit_moves=self.misfit_moves,
            subspace_dim=self.subspace_dim,
            smoothing=self.smoothing,
            n_neighbors=self.n_neighbors,
            per_cluster=self.per_cluster,
            max_iter=self.max_iter,
            outlier_threshold=self.outlier_threshold,
            screen_outliers=self.screen_outliers,
            perspective_background=self.perspective_background,
            n_init=self.n_init,
            random_state=self.random_state,
            return_info=True,
            n_jobs=self.n_jobs,
        )
        self.labels_ = labels
        self.candidates_ = list(info.candidates)
        self.coding_lengths_ = np.asarray(info.get("coding_lengths", []), dtype=float)
        self.ambiguity_ = np.asarray(info.get("ambiguity", []), dtype=float)
        self.inconsistency_ = np.asarray(info.get("inconsistency", []), dtype=float)
        self.objectives_ = np.asarray(info.get("objectives", []), dtype=float)
        self.chosen_ = self.candidates_[info.chosen] if info.chosen >= 0 else "trivial"
        self.noise_ = float(info.get("noise", np.nan))
        self.n_iter_ = int(info.n_iters[info.chosen]) if info.chosen >= 0 else 0
        self.sizes_ = np.bincount(labels[labels >= 0], minlength=self.n_clusters)
        # the models predict assigns new tracks to
        X0, mask = observed_entries(X)
        self._models = MotionModels(
            X0,
            mask,
            labels,
            self.n_clusters,
            subspace_dim=self.subspace_dim,
            perspective=self.perspective_background,
            min_tracks=self.subspace_dim + 1,
        )
        return self

    def predict(self, X):
        """Assign tracks to the fitted motions, each by its observed entries.

        Each motion of ``labels_`` with more tracks than ``subspace_dim`` is
        modelled, once at :term:`fit`, by the ``subspace_dim``-dimensional
        subspace of its tracks on their observed entries (the affine camera
        of the paper) and, for the largest with ``perspective_background``,
        also by a perspective camera per frame (the better fit of the two is
        kept for each track). A track goes to the model it fits with the
        least residual per degree of freedom; a track none can test (seen in
        too few frames) goes to the largest motion. Every track gets a
        motion: ``predict`` labels no track ``-1``.

        Parameters
        ----------
        X : array-like or masked array of shape (n_samples, n_features)
            Trajectories over the frames of the tracks seen in :term:`fit`,
            NaN (or masked) where not seen.

        Returns
        -------
        labels : ndarray of shape (n_samples,)
            The motion of each track.
        """
        check_is_fitted(self)
        X = validate_data(
            self,
            masked_to_nan(X),
            dtype=np.float64,
            ensure_all_finite="allow-nan",
            reset=False,
        )
        X0, mask = observed_entries(X)
        per_dof = self._models.per_dof(X0, mask)
        labels = np.argmin(per_dof, axis=1)
        labels[~np.isfinite(per_dof).any(axis=1)] = self._models.largest
        return labels

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.input_tags.allow_nan = True
        return tags
