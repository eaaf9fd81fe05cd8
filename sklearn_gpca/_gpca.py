"""Generalized PCA clustering of points on a union of linear hyperplanes.

Steps 2 and 3 of Algorithm 1 in Vidal & Hartley, "Motion Segmentation with
Missing Data using PowerFactorization and GPCA" (CVPR 2004): fit one homogeneous
polynomial to the Veronese-embedded points, take its gradient at every point as
that point's normal, and segment by spectral clustering of the squared cosines
between normals.
"""

# SPDX-License-Identifier: BSD-3-Clause

import warnings
from numbers import Integral, Real

import numpy as np
from scipy.linalg import eigh
from scipy.special import logsumexp
from sklearn.base import BaseEstimator, ClusterMixin, _fit_context, clone
from sklearn.exceptions import ConvergenceWarning
from sklearn.utils import check_random_state
from sklearn.utils._param_validation import Interval, StrOptions
from sklearn.utils.validation import check_is_fitted, validate_data

from sklearn_gpca._affinity import (
    merge_clusters,
    normal_affinity_graph,
    normalized_cut,
    sign_invariant_neighbors,
)
from sklearn_gpca._coding_length import coding_length
from sklearn_gpca._ksubspaces import (
    fit_subspace,
    refine_ksubspaces,
    sine_residuals,
    smoothed_cost,
)
from sklearn_gpca._missing import describe_indices
from sklearn_gpca._normals import local_normal_bases
from sklearn_gpca._polynomials import (
    polynomial_normal_bases,
    unit_gradients,
    vanishing_polynomials,
)
from sklearn_gpca._rows import canonical_sign as _canonical_sign
from sklearn_gpca._rows import unit_rows as _unit_rows
from sklearn_gpca._spectral import (
    embedding_kmeans,
    leading_eigenvectors,
    normal_subspace_features,
    spectral_clustering_lowrank,
)
from sklearn_gpca._veronese import (
    n_monomials,
    veronese_exponents,
)

# Distortion (root mean squared error per unit point) of the coding length
# that picks the number of subspaces with n_clusters="auto".
_CODING_DISTORTION = 0.03
# init="multi" drops the candidates whose subspaces fit the points (sum of
# squared sine distances) more than this many times worse than the best one.
_FIT_GATE = 3.0
# Sine distances below this floor count as a perfect fit in ``score``.
_SCORE_FLOOR = 1e-6


def _coarse(n_neighbors):
    """Neighbourhood size of the coarse-scale graph of ``init="multi"``."""
    return (3 * n_neighbors + 1) // 2


def _cluster_normals(point_normals, labels, n_clusters, smallest=False):
    """Leading (or, with ``smallest``, last) eigenvector of ``sum_i v_i v_i^T``.

    Over the per-point normals ``v_i`` of each cluster its leading eigenvector
    is the cluster's normal; over the points themselves the last one is.
    """
    n_features = point_normals.shape[1]
    normals = np.zeros((n_clusters, n_features))
    for k in range(n_clusters):
        members = point_normals[labels == k]
        _, vectors = eigh(members.T @ members)
        normals[k] = vectors[:, 0] if smallest else vectors[:, -1]
    return _canonical_sign(normals)


def _residual_energy(unit, labels, n_clusters, subspace_dim, rank_tol):
    """Sum of squared sine distances of unit points to their cluster's subspace."""
    energy = 0.0
    for k in range(n_clusters):
        members = unit[labels == k]
        if members.shape[0]:
            basis = fit_subspace(members, subspace_dim, rank_tol)
            energy += np.sum(sine_residuals(members, [basis]))
    return energy


def _complement(normal):
    """Orthonormal basis, as columns, of the hyperplane orthogonal to ``normal``."""
    return np.linalg.svd(normal[None, :], full_matrices=True)[2][1:].T


class GPCAClustering(ClusterMixin, BaseEstimator):
    """Segment points lying on a union of linear subspaces with GPCA.

    By default (beyond the paper) the points are scaled to the unit sphere,
    a hyperplane (or lower-dimensional subspace) is fitted to the nearest
    neighbours of every point, the points are clustered spectrally on the
    sparse nearest-neighbour graph weighted by a power of the squared cosine
    between these local normals, and the segmentation is refined by K-subspaces
    with a neighbourhood smoothing term. With ``normalize=False,
    affinity="polynomial", n_neighbors=None, affinity_power=1, refine=False``
    it is the paper's algorithm: one homogeneous polynomial of degree
    ``n_clusters`` fitted to the Veronese-embedded points, its gradients as
    normals, and spectral clustering of ``S_ij = cos^2(theta_ij)`` (see
    :func:`sklearn_gpca.paper_pipeline`). The subspaces pass through the
    origin: do not centre or standardise the data first.

    Parameters
    ----------
    n_clusters : int or "auto", default=2
        Number of subspaces ``n``, which is also the degree of the fitted
        polynomial. ``"auto"`` (beyond the paper) fits every ``n`` from 1 to
        ``max_clusters`` and keeps the segmentation with the shortest lossy
        coding length of the (unit) points (Ma et al., PAMI 2007) at
        distortion 0.03; see ``n_clusters_`` and ``coding_lengths_``.
    max_clusters : int, default=5
        Largest number of subspaces tried by ``n_clusters="auto"``; ignored
        otherwise. Values whose Veronese embedding needs more points than
        there are are skipped.
    normalize : bool, default=True
        Scale every point to unit norm first. Subspaces are linear, so this
        changes no subspace; it equalises the weight of the points in the
        polynomial fit and in the K-subspaces fits. The paper uses ``False``.
    affinity : {"local", "polynomial", "polynomials"}, default="local"
        Where the per-point normals come from. ``"polynomial"``: the unit
        gradient of the fitted polynomial (paper, section 2.2.3).
        ``"polynomials"``: the span of the gradients of all the vanishing
        polynomials, ``n_polynomials_`` of them, estimated from the spectrum
        of the embedded data (paper, section 2.2.4, for subspaces of lower
        dimension); directions of the gradient matrix with singular value
        ``<= rank_tol`` times the largest are dropped. ``"local"``: the least
        singular directions of the point and its ``n_neighbors // 3``
        nearest neighbours (sign-invariant angular distance); their number, the
        local codimension, is estimated with ``rank_tol``.
    n_neighbors : int or None, default=30
        Size of the nearest-neighbour graph on which the affinity is evaluated
        (``O(n_samples * n_neighbors)`` memory), clipped to ``n_samples - 1``.
        ``None`` uses all pairs through the rank-``K(K+1)/2`` kernel
        ``tr(P_i P_j)`` (paper); it requires ``affinity_power=1``. Its third
        also sets the neighbourhoods of the local normals and of the smoothing.
    affinity_power : int, default=4
        Exponent ``q`` of the graph weights ``(tr(P_i P_j) / max(c_i, c_j))^q``,
        i.e. ``cos^(2q)`` of the angle between normals for hyperplanes. The
        paper uses ``q = 1``.
    refine : bool, default=True
        Refine the spectral labels by K-subspaces: alternately fit one subspace
        per cluster and reassign the points. The paper uses ``False``.
    smoothing : float, default=5.0
        Weight ``lambda`` of the neighbourhood term in the K-subspaces
        reassignment (0 gives plain K-subspaces). See Notes.
    subspace_dim : int, "auto" or None, default=None
        Dimension of the subspaces fitted by the refinement. ``None`` fits
        hyperplanes (``n_features - 1``); ``"auto"`` estimates each cluster's
        dimension with ``rank_tol``; an int is clipped to ``n_features - 1``.
    rank_tol : float, default=0.05
        Relative singular-value threshold for the estimated dimensions: a
        cluster keeps the directions with ``s_l > rank_tol * s_1``; a local
        neighbourhood counts the directions ``l >= 3`` with ``s_l <= rank_tol *
        s_2`` as normal directions (the last one always is). 0 keeps
        hyperplanes everywhere.
    max_iter : int, default=50
        Maximum number of K-subspaces rounds.
    init : {"multi", "spectral"}, default="multi"
        Initial segmentation(s) of the refinement, when ``n_neighbors`` is an
        int. ``"spectral"``: spectral clustering of the ``affinity`` graph.
        ``"multi"`` (beyond the paper): six candidates from three graphs --
        the ``affinity`` graph, the same graph at the coarser scale of
        ``1.5 * n_neighbors`` neighbours, and its entrywise product with the
        polynomial-normal graph -- each split into ``n_clusters`` clusters
        and into ``n_clusters + 1`` clusters greedily merged back (recovers a
        small motion that the plain split would share out); each candidate is
        refined and, among those whose subspaces fit the points no more than 3
        times worse than the best one, the one with the smallest normalised
        cut on the polynomial-normal kNN graph kept (see Notes). About three
        times the cost of ``"spectral"``.
    assign_labels : {"kmeans"}, default="kmeans"
        How the spectral embedding is turned into labels: k-means on the
        row-normalised eigenvectors (Ng, Jordan & Weiss).
    n_init : int, default=10
        Number of k-means runs with different centroid seeds.
    max_spectral_samples : int or None, default=5000
        Largest number of points segmented by the graph route (neighbour
        graph, spectral initialisations, smoothed refinement) when
        ``n_neighbors`` is an int. Beyond it (beyond the paper) that route
        runs on a uniform random subsample of this size, the subspaces fitted
        to its clusters label all points, and smoothed
        K-subspaces refines them on all points, with each point's nearest
        subsample points as its neighbours in the smoothing term: time and
        memory linear in ``n_samples``. See Notes. None always uses all
        points. Irrelevant with ``n_neighbors=None``, whose low-rank route is
        exact and linear.
    n_jobs : int or None, default=None
        Number of parallel jobs of the neighbour searches (joblib threads;
        ``None`` means 1 unless in a :func:`joblib.parallel_config` context,
        -1 all processors).
    random_state : int, RandomState instance or None, default=None
        Seeds the Lanczos start vector, k-means, the reseeding of emptied
        clusters and the subsample. Pass an int for reproducible results.

    Attributes
    ----------
    n_clusters_ : int
        Number of subspaces fitted: ``n_clusters``, or the one chosen by
        ``n_clusters="auto"``.
    coding_lengths_ : ndarray of shape (max_clusters,)
        With ``n_clusters="auto"`` only: the coding length in bits of the
        segmentation into ``n = 1 .. max_clusters`` subspaces (``inf`` where
        skipped for lack of points).
    labels_ : ndarray of shape (n_samples,), dtype=intp
        Subspace label of each training point, in ``0 .. n_clusters - 1``;
        all-zero rows get 0.
    normals_ : ndarray of shape (n_clusters, n_features)
        Unit normal of each cluster, signed so that its largest-magnitude entry
        is positive. With ``refine=True`` the least singular direction of the
        cluster's (unit) points, i.e. the leading normal of a lower-dimensional
        subspace; otherwise the leading eigenvector of ``sum_i n_i n_i^T`` over
        the per-point normals of its members (paper).
    subspace_bases_ : list of ndarray of shape (n_features, d_k)
        Orthonormal basis (columns) of each fitted subspace; ``d_k =
        n_features - 1`` for hyperplanes. ``predict`` and ``score`` use them.
    point_normals_ : ndarray of shape (n_samples, n_features)
        Unit normal at each training point: the gradient ``Dp(w_i) /
        ||Dp(w_i)||`` for ``affinity="polynomial"``, the strongest direction
        of the gradients for ``"polynomials"``, the least singular direction
        of its neighbourhood for ``"local"``; zero for all-zero rows.
        Points outside the subsample of ``max_spectral_samples`` get the unit
        gradient of the polynomial.
    n_spectral_samples_ : int
        Number of points segmented by the graph route: ``n_samples`` (less
        all-zero rows) or ``max_spectral_samples``.
    n_iter_ : int
        Number of K-subspaces rounds run (0 without refinement); the largest
        over the candidates with ``init="multi"``.
    init_scores_ : ndarray of shape (n_candidates,)
        Normalised cut of each (refined) candidate segmentation on the
        polynomial-normal graph with ``init="multi"``; ``[0.]`` otherwise.
    init_residuals_ : ndarray of shape (n_candidates,)
        Sum of squared sine distances of the (unit) points to their cluster's
        fitted subspace, for each candidate; ``[0.]`` without candidates. The
        kept candidate has the smallest ``init_scores_`` among those within
        a factor 3 of the smallest residual (see Notes).
    init_chosen_ : int
        Index of the kept candidate: ``2 g + s`` with graph ``g`` (0: the
        ``affinity`` graph, 1: its coarse scale, 2: the product graph; the
        coarse graph is skipped, and the product graph is 1, when there are
        too few points for a coarser neighbourhood) and ``s`` (0: plain
        split, 1: over-segmented and merged).
    coef_ : ndarray of shape (n_monomials,)
        Unit-norm coefficients ``c`` of the fitted polynomial
        ``p(w) = c^T nu_n(w)``, one per row of ``exponents_``.
    polynomials_ : ndarray of shape (n_polynomials, n_monomials)
        Orthonormal coefficients of the vanishing polynomials: the right
        singular vectors of the embedded data for its ``n_polynomials_``
        smallest singular values, the first being ``coef_``.
    n_polynomials_ : int
        Estimated dimension of the null space of the embedded data: the
        largest gap between consecutive (log) singular values. 1 for
        hyperplanes; more for subspaces of lower dimension.
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
    "Modelling low-dimension subspaces"): ``affinity="polynomials"`` takes the
    ``n_polynomials_`` least singular vectors of ``W~`` (their number from the
    largest gap of its log singular values) and, at each point, the span of
    their gradients (singular values above ``rank_tol`` times the largest) as
    the normal subspace ``N_i``, compared through ``tr(P_i P_j)`` as below.
    Points whose gradient vanishes, e.g. on the intersection of two subspaces,
    carry no normal information and are labelled arbitrarily.

    Beyond the paper (defaults). With unit points ``x_i`` and ``N(i)`` the
    ``k = n_neighbors`` nearest lines through the origin, the local normal
    basis ``N_i`` (codimension ``c_i``) spans the least singular directions of
    ``[x_i; x_j, j in N(i)[:k/3]]``. The graph weight of the edge ``(i, j)``,
    ``j in N(i)``, is ``(tr(P_i P_j) / max(c_i, c_j))^q`` with ``P_i = N_i
    N_i^T`` (``cos^(2q)`` between hyperplane normals), symmetrised by the
    maximum; spectral clustering uses the leading ``n`` eigenvectors of ``D^{-1/2}
    A D^{-1/2}`` (Lanczos on the sparse graph). The refinement minimises, by
    iterated conditional modes,

        sum_i r_{i,l_i} / sigma^2 + lambda * #{j in N(i)[:k/3] : l_j != l_i}

    over the labels ``l``, where ``r_ik = 1 - ||U_k^T x_i||^2`` is the squared
    sine distance to subspace ``k`` (basis ``U_k`` from the SVD of the
    cluster's points) and ``sigma^2`` the median of ``r_{i,l_i}``: a Potts
    model on the neighbour graph, which fixes points near the intersection of
    two subspaces where the distances alone are ambiguous. Time and memory
    are ``O(P k)``; no ``P x P`` array is formed.

    With ``init="multi"`` the refinement runs from six spectral
    initialisations and keeps the labels ``l`` minimising the normalised cut
    ``sum_k cut(C_k, rest) / vol(C_k)`` on the kNN graph weighted by the
    polynomial gradients (the paper's normals, power ``q``). On Hopkins155 its
    per-sequence rank correlation with the error was 0.5, against 0.1-0.2 for
    the K-subspaces residual energy, which often prefers a wrong split (a
    hyperplane in ``R^5`` can hold two degenerate 2-D motions). The residual
    serves as a gate only: candidates whose residual exceeds 3 times the
    smallest are not considered. Where two motions overlap in ``R^5`` the cut
    can otherwise prefer merging them and splitting a third one in two, a
    segmentation whose hyperplanes fit several times worse (3.7 times on a
    ``make_motions`` draw of 20,000 points); on Hopkins155 the cut's choice
    is never gated (largest ratio 2.0).

    Large ``n_samples`` (beyond the paper). The Lanczos iterations on the
    kNN graph grow faster than linearly with ``P`` (more iterations on larger
    graphs) and the exact neighbour search costs ``O(P log P)`` with a large
    constant. Above ``max_spectral_samples`` points the graph route therefore
    runs on a random subsample of ``m`` points. Every other point gets as
    neighbours its ``k / 3`` nearest subsample points (a KD-tree on the ``2 m``
    points ``+-x_j``, ``O(P log m)``) and the subsample points keep theirs; on
    this graph the points are assigned by the smoothed cost above with the
    subspaces of the subsample's segments, and the smoothed K-subspaces
    iterations (``O(P K^2 n + P k)`` each) run on all points. Without the
    smoothing term the extension fails near intersections: plain nearest
    hyperplane mislabelled 9 % of 10^4 points of three motions in ``R^5``
    that the smoothed extension labels as the full route does (0.2 %). The
    polynomial is fitted to all points through the
    chunked ``M_n x M_n`` Gram matrix of the embedding, exactly. Time and
    memory are ``O(m k + P K^2 n)``. The dense-kernel route
    (``n_neighbors=None``) is linear and exact at any size and never
    subsamples.

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
        "n_clusters": [
            Interval(Integral, 1, None, closed="left"),
            StrOptions({"auto"}),
        ],
        "max_clusters": [Interval(Integral, 1, None, closed="left")],
        "normalize": ["boolean"],
        "affinity": [StrOptions({"local", "polynomial", "polynomials"})],
        "n_neighbors": [Interval(Integral, 1, None, closed="left"), None],
        "affinity_power": [Interval(Integral, 1, None, closed="left")],
        "refine": ["boolean"],
        "smoothing": [Interval(Real, 0, None, closed="left")],
        "subspace_dim": [
            Interval(Integral, 1, None, closed="left"),
            StrOptions({"auto"}),
            None,
        ],
        "rank_tol": [Interval(Real, 0, 1, closed="both")],
        "max_iter": [Interval(Integral, 1, None, closed="left")],
        "init": [StrOptions({"multi", "spectral"})],
        "assign_labels": [StrOptions({"kmeans"})],
        "n_init": [Interval(Integral, 1, None, closed="left")],
        "max_spectral_samples": [Interval(Integral, 2, None, closed="left"), None],
        "n_jobs": [Integral, None],
        "random_state": ["random_state"],
    }

    def __init__(
        self,
        n_clusters=2,
        *,
        max_clusters=5,
        normalize=True,
        affinity="local",
        n_neighbors=30,
        affinity_power=4,
        refine=True,
        smoothing=5.0,
        subspace_dim=None,
        rank_tol=0.05,
        max_iter=50,
        init="multi",
        assign_labels="kmeans",
        n_init=10,
        max_spectral_samples=5000,
        n_jobs=None,
        random_state=None,
    ):
        self.n_clusters = n_clusters
        self.max_clusters = max_clusters
        self.normalize = normalize
        self.affinity = affinity
        self.n_neighbors = n_neighbors
        self.affinity_power = affinity_power
        self.refine = refine
        self.smoothing = smoothing
        self.subspace_dim = subspace_dim
        self.rank_tol = rank_tol
        self.max_iter = max_iter
        self.init = init
        self.assign_labels = assign_labels
        self.n_init = n_init
        self.max_spectral_samples = max_spectral_samples
        self.n_jobs = n_jobs
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
        if self.n_clusters == "auto":
            return self._fit_auto(X)
        nonzero = self._nonzero_rows(X)
        if self.affinity_power != 1 and self.n_neighbors is None:
            raise ValueError(
                f"affinity_power={self.affinity_power} needs a neighbour graph: "
                "powers of the dense low-rank kernel are not low rank. Set "
                "n_neighbors to an int or affinity_power=1."
            )
        random_state = check_random_state(self.random_state)
        n_clusters = self.n_clusters
        points = X[nonzero]
        if self.normalize:
            points = _unit_rows(points)

        self.polynomials_ = vanishing_polynomials(points, n_clusters)
        self.coef_ = self.polynomials_[0]
        self.n_polynomials_ = self.polynomials_.shape[0]
        self.exponents_ = veronese_exponents(X.shape[1], n_clusters)
        subspace_dim = self.subspace_dim
        if subspace_dim is None:
            subspace_dim = X.shape[1] - 1

        n_points = points.shape[0]
        sample = None
        if (
            self.max_spectral_samples is not None
            and self.n_neighbors is not None
            and n_points > self.max_spectral_samples
        ):
            sample = np.sort(
                random_state.choice(n_points, self.max_spectral_samples, replace=False)
            )
        labels, normals, local, converged = self._segment(
            points if sample is None else points[sample], subspace_dim, random_state
        )
        unit = _unit_rows(points)
        if sample is not None:
            if not self.refine:
                self.normals_ = _cluster_normals(normals, labels, n_clusters)
                self.subspace_bases_ = [_complement(n) for n in self.normals_]
            labels, converged = self._extend(
                unit, sample, labels, local, subspace_dim, random_state
            )
            sample_normals = normals
            normals = unit_gradients(points, self.coef_, n_clusters)
            normals[sample] = sample_normals
        if not converged:
            warnings.warn(
                f"K-subspaces refinement stopped at max_iter={self.max_iter} "
                "before the labels settled; increase max_iter.",
                ConvergenceWarning,
                stacklevel=3,
            )
        if self.refine:
            self.subspace_bases_ = [
                fit_subspace(unit[labels == k], subspace_dim, self.rank_tol)
                if np.any(labels == k)
                else np.eye(X.shape[1])[:, : X.shape[1] - 1]
                for k in range(n_clusters)
            ]
            self.normals_ = _cluster_normals(unit, labels, n_clusters, smallest=True)
        elif sample is None:
            self.normals_ = _cluster_normals(normals, labels, n_clusters)
            self.subspace_bases_ = [_complement(n) for n in self.normals_]
        self.point_normals_ = np.zeros_like(X)
        self.point_normals_[nonzero] = normals
        self.labels_ = np.zeros(X.shape[0], dtype=np.intp)
        self.labels_[nonzero] = labels
        self.n_spectral_samples_ = n_points if sample is None else sample.size
        self.n_clusters_ = n_clusters
        return self

    def _fit_auto(self, X):
        """``n_clusters="auto"``: the fit of ``1 .. max_clusters`` subspaces
        whose segmentation codes the unit points in the fewest bits."""
        lengths = np.full(self.max_clusters, np.inf)
        unit = _unit_rows(X)
        n_nonzero = np.count_nonzero(np.any(X, axis=1))
        models, caught = {}, {}
        for n_clusters in range(1, self.max_clusters + 1):
            # degree n needs n_monomials - 1 points (n = 1 raises the error)
            if n_clusters > 1 and n_monomials(X.shape[1], n_clusters) - 1 > n_nonzero:
                break
            model = clone(self).set_params(n_clusters=n_clusters)
            with warnings.catch_warnings(record=True) as records:
                warnings.simplefilter("always")
                model.fit(X)
            # the same warning (e.g. all-zero rows) once, not once per fit
            caught.update(dict.fromkeys((r.category, str(r.message)) for r in records))
            models[n_clusters] = model
            lengths[n_clusters - 1] = coding_length(
                unit, model.labels_, _CODING_DISTORTION
            )
        for category, message in caught:
            warnings.warn(message, category, stacklevel=3)
        best = models[int(np.argmin(lengths)) + 1]
        fitted = {
            name: value
            for name, value in vars(best).items()
            if name.endswith("_")
            and name not in ("n_features_in_", "feature_names_in_")
        }
        vars(self).update(fitted)
        self.coding_lengths_ = lengths
        return self

    def _segment(self, points, subspace_dim, random_state):
        """Labels and point normals of ``points`` by the full route.

        Sets ``n_iter_``, ``init_scores_`` and ``init_chosen_``; returns
        whether the refinement converged.
        """
        n_clusters = self.n_clusters
        unit = _unit_rows(points)
        neighbors = local = None
        if self.n_neighbors is not None or self.refine or self.affinity == "local":
            n_neighbors = min(
                self.n_neighbors if self.n_neighbors is not None else 30,
                points.shape[0] - 1,
            )
            # the coarse scale of init="multi" reuses the same (sorted) search
            n_search = n_neighbors
            if self.init == "multi" and self.n_neighbors is not None:
                n_search = min(_coarse(n_neighbors), points.shape[0] - 1)
            searched = sign_invariant_neighbors(unit, n_search, n_jobs=self.n_jobs)
            neighbors = searched[:, :n_neighbors]
            local = neighbors[:, : max(n_neighbors // 3, 1)]

        if self.affinity == "polynomial":
            normals = unit_gradients(points, self.coef_, n_clusters)
            bases, codims = normals[:, :, None], np.ones(points.shape[0], np.intp)
        elif self.affinity == "polynomials":
            bases, codims = polynomial_normal_bases(
                unit, self.polynomials_.T, n_clusters, self.rank_tol
            )
            normals = bases[:, :, 0]
        else:
            bases, codims = local_normal_bases(unit, local, self.rank_tol)
            normals = bases[:, :, 0]

        refine_kwargs = dict(
            neighbors=local if self.refine else None,
            smoothing=self.smoothing,
            subspace_dim=subspace_dim,
            rank_tol=self.rank_tol,
            max_iter=self.max_iter,
            random_state=random_state,
        )
        self.n_iter_ = 0
        converged = True
        if n_clusters == 1:
            candidates = [np.zeros(points.shape[0], dtype=np.intp)]
        elif self.n_neighbors is None:
            candidates = [
                spectral_clustering_lowrank(
                    normal_subspace_features(bases),
                    n_clusters,
                    n_init=self.n_init,
                    random_state=random_state,
                )
            ]
        else:
            candidates, poly_graph = self._spectral_candidates(
                unit, bases, codims, searched, random_state
            )
        if self.refine:
            refined = []
            for initial in candidates:
                labels, _, n_iter, settled = refine_ksubspaces(
                    unit, initial, n_clusters, **refine_kwargs
                )
                refined.append(labels)
                self.n_iter_ = max(self.n_iter_, n_iter)
                converged = converged and settled
            candidates = refined
        # kept for diagnostics (benchmarks/bench_selection.py); on the
        # subsample when there is one, so at most max_spectral_samples each
        self._candidate_labels = candidates
        if len(candidates) > 1:
            # a candidate whose hyperplanes fit much worse than another's has
            # merged two subspaces (and split one): it cannot be n hyperplanes
            residuals = np.array(
                [
                    _residual_energy(unit, c, n_clusters, subspace_dim, self.rank_tol)
                    for c in candidates
                ]
            )
            admissible = residuals <= _FIT_GATE * residuals.min()
            # normalised cut on the polynomial-normal graph, an affinity the
            # candidates were not all built from, picks the segmentation
            cuts = np.array(
                [normalized_cut(poly_graph, c, n_clusters) for c in candidates]
            )
            self.init_scores_ = cuts
            self.init_residuals_ = residuals
            self.init_chosen_ = int(np.argmin(np.where(admissible, cuts, np.inf)))
            labels = candidates[self.init_chosen_]
        else:
            labels = candidates[0]
            self.init_scores_ = np.zeros(1)
            self.init_residuals_ = np.zeros(1)
            self.init_chosen_ = 0
        return labels, normals, local, converged

    def _extend(self, unit, sample, labels, local, subspace_dim, random_state):
        """Labels of all points from the segmentation of a subsample.

        Every point gets the ``n_neighbors // 3`` nearest subsample points
        (sign invariant) as neighbours; the subsample keeps its own graph.
        The points outside the subsample are assigned by the smoothed cost
        (sine residual to the subsample's subspaces plus the Potts term
        against the subsample's labels); with ``refine`` smoothed K-subspaces
        then runs on all points on that graph. Returns the labels and whether
        the refinement converged.
        """
        n_points = unit.shape[0]
        n_clusters = self.n_clusters
        classes = np.arange(n_clusters)
        others = np.ones(n_points, dtype=bool)
        others[sample] = False
        neighbors = np.empty((n_points, local.shape[1]), dtype=np.intp)
        neighbors[sample] = sample[local]
        neighbors[others] = sample[
            sign_invariant_neighbors(
                unit[sample], local.shape[1], queries=unit[others], n_jobs=self.n_jobs
            )
        ]
        if self.refine:
            bases = []
            for k in classes:
                members = unit[sample][labels == k]
                if members.shape[0] < unit.shape[1] - 1:
                    members = unit[sample]
                bases.append(fit_subspace(members, subspace_dim, self.rank_tol))
        else:
            bases = self.subspace_bases_
        residuals = sine_residuals(unit[others], bases)
        full = np.empty(n_points, dtype=np.intp)
        full[sample] = labels
        scale = np.median(
            sine_residuals(unit[sample], bases)[np.arange(sample.size), labels]
        )
        neighbor_labels = full[neighbors[others]] if self.smoothing > 0 else None
        cost = smoothed_cost(residuals, scale, neighbor_labels, self.smoothing)
        full[others] = np.argmin(cost, axis=1)
        if not self.refine:
            return full, True
        full, _, n_iter, converged = refine_ksubspaces(
            unit,
            full,
            n_clusters,
            neighbors=neighbors,
            smoothing=self.smoothing,
            subspace_dim=subspace_dim,
            rank_tol=self.rank_tol,
            max_iter=self.max_iter,
            random_state=random_state,
        )
        self.n_iter_ = max(self.n_iter_, n_iter)
        return full, converged

    def _kmeans(self, embedding, n_clusters, random_state):
        return embedding_kmeans(
            embedding, n_clusters, n_init=self.n_init, random_state=random_state
        )

    def _spectral_candidates(self, unit, bases, codims, searched, random_state):
        """Initial segmentations from the sparse graphs, and the polynomial graph.

        ``init="spectral"``: spectral clustering of the ``affinity`` graph.
        ``init="multi"``: three graphs -- the ``affinity`` graph, the same
        graph at the coarser scale of ``1.5 n_neighbors`` neighbours (local
        normals from ``n_neighbors // 2`` of them), and the entrywise product
        of the ``affinity`` graph with the polynomial-normal graph -- each
        split into ``n_clusters`` clusters and into ``n_clusters + 1``
        clusters merged back by :func:`merge_clusters`. The ``n_clusters + 1``
        leading eigenvectors of each graph are computed once; their first
        ``n_clusters`` give the plain embedding. ``unit`` are the points
        scaled to unit norm, ``searched`` their sorted neighbours at the
        largest scale needed.
        """
        n_samples, n_features = unit.shape
        n_clusters = self.n_clusters
        n_neighbors = min(self.n_neighbors, n_samples - 1)
        neighbors = searched[:, :n_neighbors]
        if bases.shape[2] < n_features:
            pad = n_features - bases.shape[2]
            bases = np.pad(bases, ((0, 0), (0, 0), (0, pad)))
        power = self.affinity_power
        graph = normal_affinity_graph(bases, codims, neighbors, power)
        multi = self.init == "multi" and n_samples > n_clusters + 2
        if not multi:
            vectors = leading_eigenvectors(graph, n_clusters, random_state)
            return [self._kmeans(vectors, n_clusters, random_state)], None
        if self.affinity == "polynomial":
            poly_graph = graph
        else:
            gradients = unit_gradients(unit, self.coef_, n_clusters)
            poly_graph = normal_affinity_graph(
                gradients[:, :, None], np.ones(n_samples), neighbors, power
            )
        graphs = [graph, graph.multiply(poly_graph).tocsr()]
        if searched.shape[1] > n_neighbors:
            if self.affinity == "local":
                coarse_bases, coarse_codims = local_normal_bases(
                    unit,
                    searched[:, : max(searched.shape[1] // 3, 1)],
                    self.rank_tol,
                )
            else:
                coarse_bases, coarse_codims = bases, codims
            graphs.insert(
                1,
                normal_affinity_graph(coarse_bases, coarse_codims, searched, power),
            )
        candidates = []
        for each in graphs:
            vectors = leading_eigenvectors(each, n_clusters + 1, random_state)
            split = self._kmeans(vectors, n_clusters + 1, random_state)
            candidates.append(
                self._kmeans(vectors[:, :n_clusters], n_clusters, random_state)
            )
            candidates.append(merge_clusters(each, split, n_clusters))
        return candidates, poly_graph

    def _sine_distances(self, X):
        """Sine of the angle between each point and each fitted subspace."""
        return np.sqrt(sine_residuals(_unit_rows(X), self.subspace_bases_))

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
        fit = np.mean(logsumexp(log_density, axis=1)) - np.log(self.n_clusters_)
        n_params = self.n_clusters_ * (n_features - 1)
        return float(fit - n_params * np.log(n_samples) / (2 * n_samples))
