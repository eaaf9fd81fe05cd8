"""Generalized PCA clustering of points on a union of linear hyperplanes.

Steps 2 and 3 of Algorithm 1 in Vidal & Hartley, "Motion Segmentation with
Missing Data using PowerFactorization and GPCA" (CVPR 2004): fit one homogeneous
polynomial to the Veronese-embedded points, take its gradient at every point as
that point's normal, and segment by spectral clustering of the squared cosines
between normals.
"""

# SPDX-License-Identifier: BSD-3-Clause

import warnings
from numbers import Integral

import numpy as np
from scipy.linalg import eigh
from scipy.special import logsumexp
from sklearn.base import BaseEstimator, ClusterMixin, _fit_context
from sklearn.utils import check_random_state
from sklearn.utils._param_validation import Interval, StrOptions
from sklearn.utils.validation import check_is_fitted, validate_data

from sklearn_gpca._missing import describe_indices
from sklearn_gpca._spectral import (
    normal_subspace_features,
    spectral_clustering_lowrank,
)
from sklearn_gpca._veronese import (
    n_monomials,
    polynomial_gradients,
    veronese_exponents,
    veronese_map,
)

# Sine distances below this floor count as a perfect fit in ``score``.
_SCORE_FLOOR = 1e-6


def _unit_rows(X):
    norms = np.linalg.norm(X, axis=1, keepdims=True)
    return X / np.maximum(norms, np.finfo(X.dtype).tiny)


def _canonical_sign(vectors):
    """Flip each row so that its largest-magnitude entry is positive."""
    vectors = np.atleast_2d(vectors)
    largest = vectors[np.arange(vectors.shape[0]), np.argmax(np.abs(vectors), axis=1)]
    return vectors * np.where(largest < 0, -1.0, 1.0)[:, None]


def _least_singular_vector(embedded):
    """Right singular vector of ``embedded`` for its smallest singular value.

    Computed from the ``(M_n, M_n)`` Gram matrix so that the cost is linear in
    the number of rows.
    """
    _, vectors = eigh(embedded.T @ embedded)
    return vectors[:, 0]


def _cluster_normals(point_normals, labels, n_clusters):
    """Leading eigenvector of ``sum_i n_i n_i^T`` over each cluster."""
    n_features = point_normals.shape[1]
    normals = np.zeros((n_clusters, n_features))
    for k in range(n_clusters):
        members = point_normals[labels == k]
        _, vectors = eigh(members.T @ members)
        normals[k] = vectors[:, -1]
    return _canonical_sign(normals)


class GPCAClustering(ClusterMixin, BaseEstimator):
    """Segment points lying on a union of linear hyperplanes with GPCA.

    Fits a single homogeneous polynomial of degree ``n_clusters`` that vanishes
    on the data, takes its gradient at every point as the normal of the
    hyperplane through that point, and clusters the points by spectral
    clustering of the similarity ``S_ij = cos^2(theta_ij)`` between normals.
    Subspaces of lower dimension (degenerate motions) are segmented through one
    hyperplane that contains them. The subspaces pass through the origin: do
    not centre or standardise the data first.

    Parameters
    ----------
    n_clusters : int, default=2
        Number of subspaces ``n``, which is also the degree of the fitted
        polynomial.
    assign_labels : {"kmeans"}, default="kmeans"
        How the spectral embedding is turned into labels: k-means on the
        row-normalised eigenvectors (Ng, Jordan & Weiss).
    n_init : int, default=10
        Number of k-means runs with different centroid seeds.
    random_state : int, RandomState instance or None, default=None
        Seeds k-means. Pass an int for reproducible results.

    Attributes
    ----------
    labels_ : ndarray of shape (n_samples,), dtype=intp
        Subspace label of each training point, in ``0 .. n_clusters - 1``;
        all-zero rows get 0.
    normals_ : ndarray of shape (n_clusters, n_features)
        Unit normal of each fitted hyperplane: the leading eigenvector of
        ``sum_i n_i n_i^T`` over the per-point normals of its members, signed so
        that its largest-magnitude entry is positive.
    point_normals_ : ndarray of shape (n_samples, n_features)
        Unit gradient ``Dp(w_i) / ||Dp(w_i)||`` at each training point; zero
        for all-zero rows.
    coef_ : ndarray of shape (n_monomials,)
        Unit-norm coefficients ``c`` of the fitted polynomial
        ``p(w) = c^T nu_n(w)``, one per row of ``exponents_``.
    exponents_ : ndarray of shape (n_monomials, n_features)
        Exponents of the monomials of degree ``n_clusters``; ``n_monomials =
        C(n_clusters + n_features - 1, n_clusters)``. The polynomial at ``w`` is
        ``coef_ @ np.prod(w ** exponents_, axis=1)``.
    n_features_in_ : int
        Number of features seen during :term:`fit`.
    feature_names_in_ : ndarray of shape (n_features_in_,)
        Names of features seen during :term:`fit`. Defined only when `X`
        has feature names that are all strings.

    See Also
    --------
    sklearn.cluster.SpectralClustering : Spectral clustering of a dense
        affinity matrix.
    sklearn.decomposition.PCA : Single linear subspace, fitted after centring.
    sklearn_gpca.PowerFactorization : Projection onto a low-dimensional space
        with missing entries; put it in front of this estimator.

    Notes
    -----
    With ``P`` points ``w_i`` in ``R^K`` and ``n = n_clusters``, the Veronese
    map ``nu_n`` stacks the ``M_n = C(n + K - 1, n)`` monomials of degree ``n``
    of each point (section 2.2.2). The coefficients ``c`` are the least-squares
    solution of equation (9), ``W~^T c = 0`` with ``||c|| = 1``: the eigenvector
    of the ``M_n x M_n`` matrix ``W~ W~^T`` for its smallest eigenvalue. The
    normal at ``w_i`` is ``Dp(w_i)`` (section 2.2.3), computed in closed form.
    The similarity ``S_ij = cos^2(theta_ij) = (n_i . n_j)^2`` equals
    ``<vec(n_i n_i^T), vec(n_j n_j^T)>``, so ``S = Phi Phi^T`` with ``Phi`` of
    width ``K (K + 1) / 2``; the Ng-Jordan-Weiss spectral clustering of ``S`` is
    computed from a thin SVD of ``D^{-1/2} Phi`` and never forms the ``P x P``
    matrix. Time and memory are linear in ``P``.

    For degenerate (lower-dimensional) or dependent subspaces (section 2.2.4)
    the single polynomial picks one hyperplane containing each subspace; the
    segmentation succeeds as long as that hyperplane differs from the others.
    With two or more lower-dimensional subspaces the vanishing polynomials form
    a space of dimension greater than one and the gradient of a single one of
    them varies along each subspace, so the segmentation degrades (e.g. two
    2-D planes in ``R^5``); several polynomials are needed then (section 2.2.4,
    "Modelling low-dimension subspaces").
    Points whose gradient vanishes, e.g. on the intersection of two subspaces,
    carry no normal information and are labelled arbitrarily.

    References
    ----------
    .. [1] R. Vidal and R. Hartley, "Motion Segmentation with Missing Data
       using PowerFactorization and GPCA", CVPR 2004.
    .. [2] A. Ng, M. Jordan and Y. Weiss, "On Spectral Clustering: Analysis
       and an algorithm", NIPS 2001.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._gpca import GPCAClustering
    >>> rng = np.random.RandomState(0)
    >>> normals = np.eye(3)[:2]
    >>> X = np.vstack([rng.randn(20, 3) * (1 - b) for b in normals])
    >>> gpca = GPCAClustering(n_clusters=2, random_state=0).fit(X)
    >>> np.bincount(gpca.labels_)
    array([20, 20])
    >>> first, last = gpca.labels_[[0, -1]]
    >>> np.round(np.abs(gpca.normals_[[first, last]]), 3)
    array([[1., 0., 0.],
           [0., 1., 0.]])
    >>> gpca.predict([[0.0, 1.0, 1.0], [2.0, 0.0, 1.0]]) == [first, last]
    array([ True,  True])
    """

    _parameter_constraints: dict = {
        "n_clusters": [Interval(Integral, 1, None, closed="left")],
        "assign_labels": [StrOptions({"kmeans"})],
        "n_init": [Interval(Integral, 1, None, closed="left")],
        "random_state": ["random_state"],
    }

    def __init__(
        self, n_clusters=2, *, assign_labels="kmeans", n_init=10, random_state=None
    ):
        self.n_clusters = n_clusters
        self.assign_labels = assign_labels
        self.n_init = n_init
        self.random_state = random_state

    def _validate_X(self, X, reset):
        X = validate_data(
            self,
            X,
            reset=reset,
            dtype=np.float64,
            ensure_min_features=2 if reset else 1,
            ensure_all_finite="allow-nan",
        )
        n_missing = np.count_nonzero(np.isnan(X))
        if n_missing:
            raise ValueError(
                f"Input X contains NaN ({n_missing} missing entries). "
                "GPCAClustering needs complete data: put "
                "sklearn_gpca.PowerFactorization in front of it, e.g. "
                "make_pipeline(PowerFactorization(n_components=5), "
                "GPCAClustering(...))."
            )
        return X

    def _nonzero_rows(self, X):
        """Mask of the rows used in the fit, after checking there are enough."""
        n_samples, n_features = X.shape
        nonzero = np.any(X, axis=1)
        n_zero = n_samples - np.count_nonzero(nonzero)
        n_mono = n_monomials(n_features, self.n_clusters)
        if n_samples - n_zero < n_mono - 1:
            zeros = f" ({n_zero} of them all-zero)" if n_zero else ""
            raise ValueError(
                f"n_samples={n_samples}{zeros} is too few for the Veronese "
                f"embedding of degree n_clusters={self.n_clusters} in "
                f"n_features={n_features} dimensions: it has {n_mono} monomials, "
                f"so at least {n_mono - 1} non-zero samples are needed."
            )
        if n_zero:
            warnings.warn(
                f"X has {describe_indices(np.flatnonzero(~nonzero))} all-zero "
                "rows. The origin lies on every linear subspace: these rows are "
                "left out of the fit, get label 0 and a zero point normal.",
                UserWarning,
                stacklevel=4,
            )
        return nonzero

    @_fit_context(prefer_skip_nested_validation=True)
    def fit(self, X, y=None):
        """Fit the polynomial and segment the points of `X`.

        Parameters
        ----------
        X : array-like of shape (n_samples, n_features)
            Points, e.g. trajectories projected onto ``R^5``. Needs
            ``n_features >= 2`` and no NaN. All-zero rows carry no information:
            they are left out with a warning.
        y : Ignored
            Not used, present for API consistency by convention.

        Returns
        -------
        self : object
            Fitted estimator.
        """
        X = self._validate_X(X, reset=True)
        nonzero = self._nonzero_rows(X)
        random_state = check_random_state(self.random_state)
        degree = self.n_clusters
        points = X[nonzero]

        coef = _least_singular_vector(veronese_map(points, degree))
        self.coef_ = _canonical_sign(coef)[0]
        self.exponents_ = veronese_exponents(X.shape[1], degree)
        normals = _unit_rows(polynomial_gradients(points, self.coef_, degree))
        labels = spectral_clustering_lowrank(
            normal_subspace_features(normals),
            degree,
            n_init=self.n_init,
            random_state=random_state,
        )
        self.normals_ = _cluster_normals(normals, labels, degree)
        self.point_normals_ = np.zeros_like(X)
        self.point_normals_[nonzero] = normals
        self.labels_ = np.zeros(X.shape[0], dtype=np.intp)
        self.labels_[nonzero] = labels
        return self

    def _sine_distances(self, X):
        """Sine distance ``|n_k . x| / ||x||`` of each point to each hyperplane."""
        return np.abs(_unit_rows(X) @ self.normals_.T)

    def predict(self, X):
        """Assign each point to the nearest fitted hyperplane.

        Parameters
        ----------
        X : array-like of shape (n_samples, n_features)
            New points.

        Returns
        -------
        labels : ndarray of shape (n_samples,), dtype=intp
            ``argmin_k |normals_[k] . x| / ||x||``; the origin, which lies on
            every hyperplane, gets label 0.
        """
        check_is_fitted(self)
        X = self._validate_X(X, reset=False)
        return np.argmin(self._sine_distances(X), axis=1).astype(np.intp)

    def score(self, X, y=None):
        """Penalised mixture log-likelihood of `X` under the fitted hyperplanes.

        Higher is better. With ``d_ik = |normals_[k] . x_i| / ||x_i||`` the sine
        of the angle between point ``x_i`` and hyperplane ``k``, the score is ::

            mean_i log( (1 / n) sum_k 1 / (d_ik + 1e-6) )
                - n_params * log(n_samples) / (2 * n_samples)

        with ``n = n_clusters`` and ``n_params = n * (n_features - 1)``, the
        degrees of freedom of the unit normals. The first term is the average
        log-likelihood, up to a constant shared by all models, of an
        equal-weight mixture of scale-free (``1 / d``) densities of the sine
        distance, resolved down to ``1e-6``; it is about ``-log(min_k d_ik) -
        log(n)``, so an extra hyperplane must fit the data better by a factor
        ``(n + 1) / n`` in sine distance to pay for the cost of labelling the
        points. The second term is the BIC penalty per sample. On data from
        ``n`` hyperplanes the score peaks at ``n_clusters = n``, which makes it
        usable for model selection (e.g. ``GridSearchCV`` over ``n_clusters``
        or over the rank of a preceding projection). Points at the origin have
        ``d_ik = 0`` for every ``k``.

        Parameters
        ----------
        X : array-like of shape (n_samples, n_features)
            Points to score, e.g. held-out data.
        y : Ignored
            Not used, present for API consistency by convention.

        Returns
        -------
        score : float
            Penalised mean log-likelihood (nats per sample).
        """
        check_is_fitted(self)
        X = self._validate_X(X, reset=False)
        n_samples, n_features = X.shape
        log_density = -np.log(self._sine_distances(X) + _SCORE_FLOOR)
        fit = np.mean(logsumexp(log_density, axis=1)) - np.log(self.n_clusters)
        n_params = self.n_clusters * (n_features - 1)
        return float(fit - n_params * np.log(n_samples) / (2 * n_samples))
