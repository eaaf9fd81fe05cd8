"""Generalized PCA clustering of points on a union of linear subspaces.

Steps 2 and 3 of Algorithm 1 in Vidal & Hartley, "Motion Segmentation with
Missing Data using PowerFactorization and GPCA" (CVPR 2004), and the library's
extensions, as the function :func:`gpca` and the estimator
:class:`GPCAClustering`. The function chains the stages, each a pure function
of its own module:

1. the vanishing polynomials (:mod:`sklearn_gpca._polynomials`);
2. the normals at each point (:mod:`sklearn_gpca._normals`);
3. the affinity candidates (:mod:`sklearn_gpca._candidates`);
4. the refinement (:mod:`sklearn_gpca._ksubspaces`);
5. the selection (:mod:`sklearn_gpca._selection`, with the votes of
   :mod:`sklearn_gpca._voting`);
6. the extension from a subsample (:mod:`sklearn_gpca._extension`);

and the estimator validates, calls it, and stores what it returns.
"""

# SPDX-License-Identifier: BSD-3-Clause

import warnings
from numbers import Integral, Real

import numpy as np
from sklearn.base import BaseEstimator, ClusterMixin, _fit_context
from sklearn.exceptions import ConvergenceWarning
from sklearn.utils import Bunch, check_array, check_random_state
from sklearn.utils._param_validation import Interval, StrOptions, validate_params
from sklearn.utils.validation import check_is_fitted, validate_data

from sklearn_gpca._affinity import sign_invariant_neighbors
from sklearn_gpca._candidates import (
    candidate_graphs,
    coarse_n_neighbors,
    spectral_candidates,
)
from sklearn_gpca._extension import (
    extend_labels,
    extension_neighbors,
    reference_neighbors,
)
from sklearn_gpca._input_reassignment import (
    fit_input_reassignment,
    input_reassignment,
)
from sklearn_gpca._ksubspaces import k_subspaces, smoothed_assignment
from sklearn_gpca._memory import check_gpca_memory
from sklearn_gpca._missing import describe_indices
from sklearn_gpca._model_selection import (
    CRITERIA,
    criterion_function,
    select_n_clusters,
)
from sklearn_gpca._normals import POINT_NORMALS, point_normal_bases
from sklearn_gpca._polynomials import unit_gradients, vanishing_polynomials
from sklearn_gpca._power_factorization import PowerFactorization
from sklearn_gpca._rows import canonical_sign, power_of_two_scale, unit_rows
from sklearn_gpca._segmentation_space import (
    fit_segmentation_space,
    to_segmentation_space,
)
from sklearn_gpca._selection import select_candidate
from sklearn_gpca._spectral import (
    normal_subspace_features,
    spectral_clustering_lowrank,
)
from sklearn_gpca._subspaces import (
    fit_subspaces,
    hyperplanes_from_normals,
    own_residuals,
)
from sklearn_gpca._validation import Count
from sklearn_gpca._veronese import n_monomials, veronese_exponents
from sklearn_gpca._voting import (
    VOTING_ROUNDS,
    vote_confidence,
    vote_cut,
    vote_features,
    voting_runs,
)

_PARAMETER_CONSTRAINTS = {
    "normalize": ["boolean"],
    "point_normals": [StrOptions(set(POINT_NORMALS))],
    "affinity": [StrOptions({"nearest_neighbors", "all_pairs"})],
    "n_neighbors": [Count(1, None, closed="left")],
    "affinity_power": [Count(1, None, closed="left")],
    "init": [StrOptions({"multi", "spectral"})],
    "n_init": [Count(1, None, closed="left")],
    "n_votes": [Count(0, None, closed="left")],
    "vote_weighting": [StrOptions({"equal", "confidence"})],
    "refine": ["boolean"],
    "smoothing": [Interval(Real, 0, None, closed="left")],
    "subspace_dim": [
        Count(1, None, closed="left"),
        StrOptions({"auto"}),
        None,
    ],
    "normal_tol": [Interval(Real, 0, 1, closed="both")],
    "subspace_dim_tol": [Interval(Real, 0, 1, closed="both")],
    "max_iter": [Count(1, None, closed="left")],
    "max_spectral_samples": [Count(2, None, closed="left"), None],
    "n_jobs": [Integral, None],
    "random_state": ["random_state"],
}

_PARAMETERS_DOC = """normalize : bool, default=True
        Scale every point to unit norm first. Subspaces are linear, so this
        changes no subspace; it equalises the weight of the points in the
        polynomial fit. The paper uses ``False`` (the points are then only
        multiplied by one power of two, which changes no digit, so that the
        polynomial neither underflows nor overflows).
    point_normals : {"local", "one_polynomial", "all_polynomials"}, \
default="local"
        Estimator of the normal subspace at each point (stage 2).
        ``"one_polynomial"``: the unit gradient of the fitted polynomial
        (paper, section 2.2.3). ``"all_polynomials"``: the span of the
        gradients of all the vanishing polynomials, ``n_polynomials_`` of
        them (paper, section 2.2.4, for subspaces of lower dimension).
        ``"local"``: the least singular directions of the point and its
        ``n_neighbors // 3`` nearest neighbours (sign-invariant angular
        distance). The last two estimate the dimension of the normal
        subspace with ``normal_tol``.
    affinity : {"nearest_neighbors", "all_pairs"}, default="nearest_neighbors"
        Which pairs of points the affinity ``(tr(P_i P_j) / max(c_i,
        c_j))^affinity_power`` between their normal projectors compares
        (stage 3). ``"nearest_neighbors"``: each point and its
        ``n_neighbors`` nearest, a sparse graph (``O(n_samples *
        n_neighbors)`` memory). ``"all_pairs"``: every pair, through the
        rank-``K(K+1)/2`` factor of the kernel (paper); it needs
        ``affinity_power=1`` and makes one candidate.
    n_neighbors : int, default=30
        Size of the neighbourhoods, clipped to ``n_samples - 1``: the edges
        of the nearest-neighbour graph, and, by its third (``n_neighbors //
        3``), the neighbourhoods of ``point_normals="local"`` and of the
        smoothing. Unused by the paper's settings.
    affinity_power : int, default=4
        Exponent ``q`` of the affinity, ``cos^(2q)`` of the angle between
        normals for hyperplanes. The paper uses ``q = 1``.
    init : {"multi", "spectral"}, default="multi"
        The candidate segmentations of the nearest-neighbour route (stage 3).
        ``"spectral"``: spectral clustering of the affinity graph.
        ``"multi"`` (beyond the paper): six candidates from three graphs --
        the affinity graph, the same at the coarser scale of ``1.5 *
        n_neighbors`` neighbours, and its entrywise product with the graph
        of the polynomial's gradients -- each split into ``n_clusters``
        clusters and into ``n_clusters + 1`` clusters greedily merged back;
        the selection (stage 5) keeps one. Six refinements instead of one:
        the time column of ``benchmarks/results/ablation.md`` compares them.
    n_init : int, default=10
        Number of k-means runs on each spectral embedding.
    n_votes : int, default=100
        Number ``R`` of randomized-voting runs (beyond the paper; Jung, Ju &
        Kim, CVPR 2014) behind the selection of ``init="multi"`` (stage 5):
        each run is plain K-subspaces from ``n_clusters`` subspaces spanned
        by a random point and its nearest neighbours, and votes for the pairs
        of points it puts together. The kept candidate minimises the
        normalised cut on the polynomial-normal graph plus the normalised cut
        on this vote graph (weighted as ``vote_weighting`` says). 0 selects
        by the first cut alone. Time and memory ``O(n R n_clusters)`` on the
        ``n`` segmented points, plus ``O(m^2 max(n, R n_clusters))`` with
        ``m = min(n, R n_clusters)`` for the graph's confidence with
        ``vote_weighting="confidence"``.
    vote_weighting : {"confidence", "equal"}, default="confidence"
        Weight of the vote cut in the selection. ``"confidence"``: the vote
        cut times the vote graph's confidence ``vote_confidence_`` in [0, 1],
        so that votes of runs that each split the points their own way do not
        outweigh a clean cut of the first graph. ``"equal"``: cut plus vote
        cut. ``benchmarks/results/selection.md`` compares them: equal on
        complete Hopkins155 and on ``make_motions`` draws, ``"confidence"``
        better under occlusion and on tracker-like draws with missing
        entries, worse on the 3x10^5 scaling draw (see Notes).
    refine : bool, default=True
        Refine each candidate by smoothed K-subspaces (stage 4): alternately
        fit one subspace per cluster and reassign the points. The paper uses
        ``False``.
    smoothing : float, default=5.0
        Weight ``lambda`` of the neighbourhood term of the refinement and of
        the extension (0: plain nearest subspace). See Notes.
    subspace_dim : int, "auto" or None, default=None
        Dimension of the subspaces fitted by the refinement. ``None`` fits
        hyperplanes (``n_features - 1``); ``"auto"`` estimates each
        cluster's dimension with ``subspace_dim_tol``; an int is clipped to
        ``n_features - 1``.
    normal_tol : float, default=0.05
        Relative singular-value threshold of the dimension of the normal
        subspace at a point (stage 2): with ``point_normals="local"`` the
        directions ``l >= 3`` of a neighbourhood with ``s_l <= normal_tol *
        s_2`` are normal (the last one always is); with
        ``"all_polynomials"`` the gradient directions with ``s_l >
        normal_tol * s_1`` are kept. 0 keeps one normal (hyperplanes).
    subspace_dim_tol : float, default=0.05
        With ``subspace_dim="auto"``: a cluster keeps the directions with
        ``s_l > subspace_dim_tol * s_1``.
    max_iter : int, default=50
        Maximum number of K-subspaces rounds.
    max_spectral_samples : int or None, default=5000
        Largest number of points segmented by the nearest-neighbour route.
        Beyond it (beyond the paper) that route runs on a uniform random
        subsample of this size, and its segmentation is extended to all
        points (stage 6): time and memory linear in ``n_samples``. None
        always uses all points. Unused with ``affinity="all_pairs"``, whose
        route is exact and linear.
    n_jobs : int or None, default=None
        Number of parallel jobs of the neighbour searches (joblib threads;
        ``None`` means 1 unless in a :func:`joblib.parallel_config` context,
        -1 all processors).
    random_state : int, RandomState instance or None, default=None
        Seeds the subsample, the Lanczos start vectors and k-means. Pass an
        int for reproducible results."""


# Fields of the selection (stage 5) kept as fitted attributes (name + "_").
_SELECTION_FIELDS = (
    "candidate_ncuts",
    "candidate_vote_cuts",
    "vote_confidence",
    "candidate_residuals",
    "chosen_candidate",
)


def _fill_parameters(function):
    function.__doc__ = function.__doc__.replace("{parameters}", _PARAMETERS_DOC)
    return function


def _check_complete(X):
    n_missing = np.count_nonzero(np.isnan(X))
    if n_missing:
        raise ValueError(
            f"Input X contains NaN ({n_missing} missing entries). "
            "GPCAClustering needs complete data: put "
            "sklearn_gpca.PowerFactorization in front of it, e.g. "
            "make_pipeline(PowerFactorization(n_components=5), "
            "GPCAClustering(...))."
        )


def _distinct_lines(X):
    """The rows of ``X`` the fit uses: one per line through the origin.

    A linear subspace holds a point's whole line, so an all-zero row (on every
    subspace) carries no information, and a row on the same line as an
    earlier row (a duplicate, a multiple, its opposite) carries none beyond
    it: the fit uses the first row of each line, and every row gets its
    line's label. Lines are compared by their unit direction to 12 decimals.

    Returns
    -------
    rows : ndarray of int
        Increasing indices of the rows used.
    owner : ndarray of shape (n_samples,), dtype=intp
        Index into ``rows`` of each row's line; -1 for all-zero rows.
    """
    nonzero = np.flatnonzero(np.any(X, axis=1))
    directions = np.round(canonical_sign(unit_rows(X[nonzero])), 12) + 0.0
    _, first, line = np.unique(
        directions, axis=0, return_index=True, return_inverse=True
    )
    order = np.argsort(first)
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    owner = np.full(X.shape[0], -1, dtype=np.intp)
    owner[nonzero] = rank[line.reshape(-1)]
    return nonzero[first[order]], owner


def _check_rows(X, rows, owner, n_clusters):
    """Enough rows for the Veronese embedding; a warning for all-zero rows."""
    n_samples, n_features = X.shape
    zero = np.flatnonzero(owner < 0)
    n_mono = n_monomials(n_features, n_clusters)
    if rows.size < n_mono - 1:
        repeated = n_samples - zero.size - rows.size
        details = [f"{zero.size} of them all-zero"] if zero.size else []
        if repeated:
            details.append(f"{repeated} on the line of an earlier row")
        details = f" ({', '.join(details)})" if details else ""
        raise ValueError(
            f"n_samples={n_samples}{details} is too few for the Veronese "
            f"embedding of degree n_clusters={n_clusters} in "
            f"n_features={n_features} dimensions: it has {n_mono} monomials, "
            f"so at least {n_mono - 1} non-zero samples on distinct lines "
            "through the origin are needed."
        )
    if zero.size:
        warnings.warn(
            f"X has {describe_indices(zero)} all-zero "
            "rows. The origin lies on every linear subspace: these rows are "
            "left out of the fit, get label 0 and a zero point normal.",
            UserWarning,
            stacklevel=4,
        )


def _warn_empty_clusters(labels, n_clusters, unit):
    """Say why the segmentation has fewer than ``n_clusters`` groups."""
    empty = np.flatnonzero(np.bincount(labels, minlength=n_clusters) == 0)
    if empty.size == 0:
        return
    n_distinct = np.unique(unit, axis=0).shape[0]
    if n_distinct < n_clusters:
        reason = f"X has only {n_distinct} distinct non-zero points"
    else:
        reason = (
            "the refinement could not keep a subspace for them: the points "
            f"support fewer subspaces; fit n_clusters={n_clusters - empty.size}, "
            "or choose it with n_clusters='auto'"
        )
    warnings.warn(
        f"{empty.size} of the n_clusters={n_clusters} clusters are empty "
        f"(labels {describe_indices(empty)}): {reason}.",
        UserWarning,
        stacklevel=4,
    )


def _neighborhoods(unit, p):
    """Sorted sign-invariant neighbours, the graph's edges and the local ones.

    Returns ``(searched, neighbors, local)``: ``searched`` at the largest scale
    needed (the coarse scale of ``init="multi"``), ``neighbors`` its first
    ``n_neighbors`` columns, ``local`` their first third. All None when no
    stage needs neighbours.
    """
    n_points = unit.shape[0]
    graph = p["affinity"] == "nearest_neighbors"
    smoothing = p["refine"] and p["smoothing"] > 0
    if not (graph or smoothing or p["point_normals"] == "local"):
        return None, None, None
    n_neighbors = min(p["n_neighbors"], n_points - 1)
    n_search = n_neighbors
    if graph and p["init"] == "multi":
        n_search = min(coarse_n_neighbors(n_neighbors), n_points - 1)
    searched = sign_invariant_neighbors(unit, n_search, n_jobs=p["n_jobs"])
    neighbors = searched[:, :n_neighbors]
    return searched, neighbors, neighbors[:, : max(n_neighbors // 3, 1)]


def _candidates(points, unit, polynomials, n_clusters, p, random_state):
    """Stages 2 and 3: point normals, then candidate labellings and the
    selection graph."""
    searched, neighbors, local = _neighborhoods(unit, p)
    normals = dict(
        points=points, polynomials=polynomials, degree=n_clusters, tol=p["normal_tol"]
    )
    bases, codims = point_normal_bases(
        p["point_normals"], unit, neighbors=local, **normals
    )
    if n_clusters == 1:
        return bases, local, [np.zeros(unit.shape[0], dtype=np.intp)], None
    if p["affinity"] == "all_pairs":
        labels = spectral_clustering_lowrank(
            normal_subspace_features(bases),
            n_clusters,
            n_init=p["n_init"],
            random_state=random_state,
        )
        return bases, local, [labels], None
    multi = p["init"] == "multi" and unit.shape[0] > n_clusters + 2
    coarse = gradients = None
    if multi and searched.shape[1] > neighbors.shape[1]:
        coarse = (bases, codims)
        if p["point_normals"] == "local":
            coarse_local = searched[:, : max(searched.shape[1] // 3, 1)]
            coarse = point_normal_bases(
                "local", unit, neighbors=coarse_local, **normals
            )
        coarse = (*coarse, searched)
    if multi and p["point_normals"] != "one_polynomial":
        gradients = unit_gradients(unit, polynomials[0], n_clusters)
    graphs, selection_graph = candidate_graphs(
        (bases, codims),
        neighbors,
        p["affinity_power"],
        coarse=coarse,
        gradients=gradients,
        multi=multi,
    )
    candidates = spectral_candidates(
        graphs,
        n_clusters,
        over_segment=multi,
        n_init=p["n_init"],
        random_state=random_state,
    )
    return bases, local, candidates, selection_graph


def _subspace_dim(p, unit):
    """``subspace_dim``, None meaning hyperplanes."""
    return unit.shape[1] - 1 if p["subspace_dim"] is None else p["subspace_dim"]


def _voting_dim(p, unit):
    """Dimension of the voting runs' subspaces: ``subspace_dim`` if an int,
    else hyperplanes."""
    dim = p["subspace_dim"]
    if dim is None or dim == "auto":
        return unit.shape[1] - 1
    return min(dim, unit.shape[1] - 1)


def _refinement(p):
    """Keyword arguments of :func:`k_subspaces` from the parameters."""
    return dict(
        smoothing=p["smoothing"],
        subspace_dim=p["subspace_dim"],
        subspace_dim_tol=p["subspace_dim_tol"],
        max_iter=p["max_iter"],
    )


def _segment(points, unit, polynomials, n_clusters, p, random_state):
    """Stages 2 to 5 on the points of the graph route (all, or a subsample)."""
    bases, local, candidates, graph = _candidates(
        points, unit, polynomials, n_clusters, p, random_state
    )
    n_iter, converged = 0, True
    if p["refine"]:
        refined = []
        for labels in candidates:
            labels, _, iterations, settled = k_subspaces(
                unit,
                labels,
                n_clusters,
                neighbors=local,
                **_refinement(p),
            )
            refined.append(labels)
            n_iter, converged = max(n_iter, iterations), converged and settled
        candidates = refined
    vote_cuts, confidence = None, np.nan
    if graph is not None and p["n_votes"] > 0:
        votes = vote_features(
            voting_runs(
                unit,
                n_clusters,
                local,
                n_runs=p["n_votes"],
                dim=_voting_dim(p, unit),
                n_iter=VOTING_ROUNDS,
                random_state=random_state,
            ),
            n_clusters,
        )
        vote_cuts = np.array([vote_cut(votes, c, n_clusters) for c in candidates])
        if p["vote_weighting"] == "confidence":
            confidence = vote_confidence(votes, n_clusters)
    chosen, cuts, residuals = select_candidate(
        unit,
        candidates,
        n_clusters,
        graph=graph,
        subspace_dim=_subspace_dim(p, unit),
        subspace_dim_tol=p["subspace_dim_tol"],
        vote_cuts=vote_cuts,
        vote_weight=1.0 if np.isnan(confidence) else confidence,
    )
    if vote_cuts is None:
        vote_cuts = np.full(len(candidates), np.nan)
    return Bunch(
        labels=candidates[chosen],
        point_normals=bases[:, :, 0],
        local_neighbors=local,
        candidate_labels=np.array(candidates),
        candidate_ncuts=cuts,
        candidate_vote_cuts=vote_cuts,
        vote_confidence=confidence,
        candidate_residuals=residuals,
        chosen_candidate=chosen,
        selection_graph=graph,
        n_iter=n_iter,
        converged=converged,
    )


def _extend(points, unit, polynomials, sample, segmented, bases, p):
    """Stage 6: labels and point normals of all points from the subsample's."""
    n_clusters = len(bases)
    neighbors = extension_neighbors(
        unit, sample, segmented.local_neighbors, n_jobs=p["n_jobs"]
    )
    labels = extend_labels(
        unit, sample, segmented.labels, neighbors, bases, smoothing=p["smoothing"]
    )
    n_iter, converged = 0, True
    if p["refine"]:
        labels, _, n_iter, converged = k_subspaces(
            unit,
            labels,
            n_clusters,
            neighbors=neighbors,
            **_refinement(p),
        )
    point_normals = unit_gradients(points, polynomials[0], n_clusters)
    point_normals[sample] = segmented.point_normals
    return labels, point_normals, n_iter, converged


@validate_params(
    {
        "X": ["array-like"],
        "n_clusters": [Count(1, None, closed="left")],
        **_PARAMETER_CONSTRAINTS,
    },
    prefer_skip_nested_validation=True,
)
@_fill_parameters
def gpca(
    X,
    n_clusters=2,
    *,
    normalize=True,
    point_normals="local",
    affinity="nearest_neighbors",
    n_neighbors=30,
    affinity_power=4,
    init="multi",
    n_init=10,
    n_votes=100,
    vote_weighting="confidence",
    refine=True,
    smoothing=5.0,
    subspace_dim=None,
    normal_tol=0.05,
    subspace_dim_tol=0.05,
    max_iter=50,
    max_spectral_samples=5000,
    n_jobs=None,
    random_state=None,
):
    """Segment points on a union of linear subspaces with GPCA.

    The function behind :class:`GPCAClustering`: arrays in, arrays out. See
    the estimator for the algorithm; ``docs/user_guide/code_organisation.rst``
    for the stages.

    Parameters
    ----------
    X : array-like of shape (n_samples, n_features)
        Complete points, e.g. trajectories projected to :math:`R^5`; all-zero rows
        are left out with a warning.
    n_clusters : int, default=2
        Number of subspaces, the degree of the polynomials.
    {parameters}

    Returns
    -------
    result : :class:`~sklearn.utils.Bunch`
        With the fields (``P = n_samples``, ``n = n_clusters``, ``K =
        n_features``; candidates are on the segmented points):

        - ``labels``, ndarray of shape (P,): the segmentation;
        - ``normals``, ndarray of shape (n, K): unit normal of each cluster;
        - ``subspace_bases``, list of n ndarray of shape (K, d_k);
        - ``point_normals``, ndarray of shape (P, K);
        - ``polynomials``, ndarray of shape (n_polynomials, n_monomials);
        - ``segmented``, ndarray of int: the rows of ``X`` segmented by the
          graph route (all non-zero rows on distinct lines, or a subsample);
        - ``reference``, ndarray of int: the rows whose labels smooth the
          labelling of new points (``segmented`` with a smoothed refinement,
          none otherwise);
        - ``candidate_labels``, ndarray of shape (n_candidates,
          len(segmented)): the refined candidates;
        - ``candidate_ncuts``, ``candidate_vote_cuts``,
          ``candidate_residuals``, ndarray of shape (n_candidates,),
          ``vote_confidence``, float (NaN without votes or with
          ``vote_weighting="equal"``), and
          ``chosen_candidate``, int: the selection;
        - ``selection_graph``: the sparse graph of the cuts, or None;
        - ``local_neighbors``, ndarray of shape (len(segmented), n_local):
          the neighbourhoods of the smoothing, or None;
        - ``n_iter``, int, and ``converged``, bool: of the refinement;
        - ``residual_scale``, float: the median squared sine distance of the
          points to their own subspace, the unit of the smoothing (NaN without
          refinement).

    See Also
    --------
    GPCAClustering : The estimator.
    select_n_clusters : Choose ``n_clusters``.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca import gpca
    >>> rng = np.random.RandomState(0)
    >>> X = np.vstack([rng.randn(20, 3) * [1, 1, 0], rng.randn(20, 3) * [0, 1, 1]])
    >>> result = gpca(X, 2, random_state=0)
    >>> np.bincount(result.labels)
    array([20, 20])
    >>> np.abs(result.normals).round(3)
    array([[0., 0., 1.],
           [1., 0., 0.]])
    """
    p = dict(locals())
    del p["X"], p["n_clusters"]
    X = check_array(
        X, dtype=np.float64, ensure_min_features=2, ensure_all_finite="allow-nan"
    )
    return _gpca(X, n_clusters, p)


def _gpca(X, n_clusters, p):
    """:func:`gpca` on validated input; ``p`` holds its keyword arguments."""
    if p["affinity_power"] != 1 and p["affinity"] == "all_pairs":
        raise ValueError(
            f"affinity_power={p['affinity_power']} needs affinity="
            "'nearest_neighbors': powers of the all-pairs kernel are not low "
            "rank. Set affinity_power=1."
        )
    _check_complete(X)
    check_gpca_memory(*X.shape, n_clusters, p)
    rows, owner = _distinct_lines(X)
    _check_rows(X, rows, owner, n_clusters)
    random_state = check_random_state(p["random_state"])
    points = X[rows]
    points = unit_rows(points) if p["normalize"] else power_of_two_scale(points)
    polynomials = vanishing_polynomials(points, n_clusters)
    unit = unit_rows(points)
    n_points, limit = points.shape[0], p["max_spectral_samples"]
    sample = None
    if p["affinity"] == "nearest_neighbors" and limit and n_points > limit:
        sample = np.sort(random_state.choice(n_points, limit, replace=False))
    segmented = np.arange(n_points) if sample is None else sample
    result = _segment(
        points[segmented], unit[segmented], polynomials, n_clusters, p, random_state
    )
    labels, point_normals = result.labels, result.point_normals
    fit = (n_clusters, _subspace_dim(p, X), p["subspace_dim_tol"])
    if not p["refine"]:
        bases, normals = hyperplanes_from_normals(point_normals, labels, n_clusters)
    if sample is not None:
        if p["refine"]:
            bases, _ = fit_subspaces(unit[sample], labels, *fit)
        labels, point_normals, n_iter, converged = _extend(
            points, unit, polynomials, sample, result, bases, p
        )
        result.n_iter = max(result.n_iter, n_iter)
        result.converged = result.converged and converged
    result.residual_scale = np.nan
    if p["refine"]:
        bases, normals = fit_subspaces(unit, labels, *fit)
        result.residual_scale = float(np.median(own_residuals(unit, labels, bases)))
    _warn_empty_clusters(labels, n_clusters, unit)
    if not result.converged:
        warnings.warn(
            f"K-subspaces refinement stopped at max_iter={p['max_iter']} "
            "before the labels settled; increase max_iter.",
            ConvergenceWarning,
            stacklevel=3,
        )
    fitted = owner >= 0
    result.labels = np.zeros(X.shape[0], dtype=np.intp)
    result.labels[fitted] = labels[owner[fitted]]
    result.point_normals = np.zeros_like(X)
    result.point_normals[fitted] = point_normals[owner[fitted]]
    smooths = p["refine"] and p["smoothing"] > 0
    result.update(
        normals=normals,
        subspace_bases=bases,
        polynomials=polynomials,
        segmented=rows[segmented],
        reference=rows[segmented] if smooths else rows[:0],
    )
    return result


@_fill_parameters
class GPCAClustering(ClusterMixin, BaseEstimator):
    """Segment points lying on a union of linear subspaces with GPCA.

    By default (beyond the paper) the points are scaled to the unit sphere,
    a hyperplane (or lower-dimensional subspace) is fitted to the nearest
    neighbours of every point, the points are clustered spectrally on the
    sparse nearest-neighbour graph weighted by a power of the squared cosine
    between these local normals, and the segmentation is refined by K-subspaces
    with a neighbourhood smoothing term. With ``normalize=False,
    point_normals="one_polynomial", affinity="all_pairs", affinity_power=1,
    refine=False`` it is the paper's algorithm: one homogeneous polynomial of
    degree ``n_clusters`` fitted to the Veronese-embedded points, its
    gradients as normals, and spectral clustering of ``S_ij = cos^2(theta_ij)``
    (see :func:`sklearn_gpca.paper_pipeline`). The subspaces pass through the
    origin: do not centre or standardise the data first. The work is done by
    :func:`gpca`; ``docs/user_guide/code_organisation.rst`` shows its stages.

    Parameters
    ----------
    n_clusters : int or "auto", default=2
        Number of subspaces ``n``, which is also the degree of the fitted
        polynomial. ``"auto"`` (beyond the paper) fits every ``n`` from 1 to
        ``max_clusters`` and keeps the segmentation with the lowest
        ``criterion`` (:func:`select_n_clusters`); see ``n_clusters_`` and
        ``n_clusters_costs_``. To count motions, give it the unwhitened
        trajectories of rank ``4 * max_clusters`` and segment them in
        :math:`R^5` with ``segmentation_dim=5``::

            make_pipeline(PowerFactorization(20, whiten=False),
                          GPCAClustering("auto", segmentation_dim=5))

        The default criterion is then the coding length of the trajectories
        in that wide projection after each segmentation is refined by
        coordinate descent on it, with groups of fewer than 16 trajectories
        rejected (:func:`refined_trajectory_coding_length_cost`; the
        refinement only judges: ``labels_`` stay the chosen fit's); without
        ``segmentation_dim`` it is the coding length of the segmented
        points among the segmentations whose groups are distinct
        hyperplanes (:func:`distinct_coding_length_cost`). On Hopkins155 the
        first finds the number of motions on 92 % of the sequences, the
        second on 72 % (it merges two of three motions); both under-count
        synthetic motions that differ only in directions of little energy,
        and the first expects image coordinates centred near the image
        (calibrated, or the principal point subtracted). Its misses are a
        rigid body whose planar parts are counted as motions, two motions
        near one low-dimensional subspace, and articulated motions.
        ``benchmarks/results/n_motions.md`` measures both and lists the
        misses.
    max_clusters : int, default=5
        Largest number of subspaces tried by ``n_clusters="auto"``; ignored
        otherwise. Values whose Veronese embedding needs more points than
        there are are skipped.
    segmentation_dim : int or None, default=None
        Segment the points in their ``segmentation_dim`` leading principal
        directions (not centred), whitened: for complete trajectories, the
        coordinates of ``PowerFactorization(segmentation_dim)``. The polynomial,
        the normals, the subspaces, the reference points and ``predict``
        work there; ``n_clusters="auto"`` and ``score`` judge the
        segmentation on the input points. With ``segmentation_dim`` the input
        may have missing entries (NaN): the points are then segmented at the
        coordinates of ``PowerFactorization(segmentation_dim)`` fitted to
        their observed entries (``segmentation_projection_``), and
        ``input_subspace_dim`` reassigns them on their observed entries
        (``n_clusters="auto"`` and ``score`` need complete points). None
        segments the input as it is. At least 2, at most ``min(n_samples,
        n_features)``.
    input_subspace_dim : int or None, default=None
        With ``segmentation_dim`` (beyond the paper): after the segmentation
        in the leading directions, reassign every point once in the input's
        own width, anchored to its label there: a subspace of this dimension
        is fitted to each group and a point moves to another group only when
        that subspace fits it better, per residual degree of freedom, by more
        than one typical misfit (:mod:`sklearn_gpca._input_reassignment`).
        Subspaces that meet in the leading directions can be apart in the
        full width: 4 for rigid motions, given as the raw trajectories
        (``GPCAClustering(3, segmentation_dim=5, input_subspace_dim=4)``, NaN
        where missing) or as unwhitened trajectories of a rank above 5
        (``make_pipeline(PowerFactorization(8, whiten=False),
        GPCAClustering(3, segmentation_dim=5, input_subspace_dim=4))``);
        ``benchmarks/results/scaling.md`` measures both. None (default) keeps
        the labels of the segmentation space. Less than ``n_features``.
    criterion : {"auto", "refined_trajectory_coding_length", \
"trajectory_coding_length", "distinct_coding_length", "coding_length", \
"sine_likelihood"} or callable, default="auto"
        The model-selection criterion of ``n_clusters="auto"`` and ``score``:
        ``criterion(points, labels) -> cost`` on the input points, lower is
        better (see :func:`select_n_clusters`). ``"auto"``:
        ``"refined_trajectory_coding_length"`` with ``segmentation_dim``,
        ``"distinct_coding_length"`` without.
        ``"refined_trajectory_coding_length"``:
        :func:`refined_trajectory_coding_length_cost`, the coding length of
        unit trajectories in a wide unwhitened projection at the local
        minimum that coordinate descent reaches from the labels, ``inf``
        when a group of it holds fewer than 16 trajectories;
        ``"trajectory_coding_length"``: :func:`trajectory_coding_length_cost`,
        the same code of the labels as they are.
        ``"distinct_coding_length"``:
        :func:`distinct_coding_length_cost`, the coding length, ``inf`` when
        two groups are not distinct subspaces (:func:`merge_ratio` below 5);
        ``"coding_length"``: :func:`coding_length_cost` alone, which prefers
        too many groups on real motions; ``"sine_likelihood"``:
        :func:`sine_likelihood_cost`, which can also compare the ranks of a
        preceding projection on noise-free data.
    {parameters}

    Attributes
    ----------
    n_clusters_ : int
        Number of subspaces fitted: ``n_clusters``, or the one chosen by
        ``n_clusters="auto"``.
    n_clusters_costs_ : ndarray of shape (max_clusters,)
        With ``n_clusters="auto"`` only: the ``criterion`` (lower is better;
        bits for the coding length) of the segmentation into ``n = 1 ..
        max_clusters`` subspaces; ``inf`` where skipped for lack of points,
        and, with the default criteria, where two groups are not distinct
        (without ``segmentation_dim``) or where the refined segmentation has
        a group of fewer than 16 trajectories (with it).
    labels_ : ndarray of shape (n_samples,), dtype=intp
        Subspace label of each training point, in ``0 .. n_clusters_ - 1``;
        all-zero rows get 0.
    normals_ : ndarray of shape (n_clusters, n_features)
        Unit normal of each cluster, signed so that its largest-magnitude entry
        is positive. With ``refine=True`` the least singular direction of the
        cluster's (unit) points, i.e. the leading normal of a lower-dimensional
        subspace; otherwise the leading eigenvector of ``sum_i n_i n_i^T`` over
        the point normals of its members (paper).
    subspace_bases_ : list of ndarray of shape (n_features, d_k)
        Orthonormal basis (columns) of each fitted subspace: ``d_k =
        n_features - 1`` for hyperplanes, ``d_k = 0`` for a cluster left
        without points. ``predict`` and ``score`` use them.
    reference_points_ : ndarray of shape (n_reference, n_features)
        The unit points whose labels smooth ``predict``: the points segmented
        by the graph route (at most ``max_spectral_samples``); none without
        refinement or smoothing.
    reference_labels_ : ndarray of shape (n_reference,), dtype=intp
        Their labels.
    residual_scale_ : float
        Median squared sine distance of the training points to their own
        subspace, the unit of ``smoothing``; NaN without refinement.
    point_normals_ : ndarray of shape (n_samples, n_features)
        Unit normal at each training point, by the ``point_normals``
        estimator (its strongest direction); zero for all-zero rows. Points
        outside the subsample of ``max_spectral_samples`` get the unit
        gradient of the polynomial.
    n_spectral_samples_ : int
        Number of points segmented by the graph route: ``n_samples`` (less
        all-zero rows) or ``max_spectral_samples``.
    n_iter_ : int
        Number of K-subspaces rounds run (0 without refinement); the largest
        over the candidates and the extension.
    candidate_ncuts_ : ndarray of shape (n_candidates,)
        Normalised cut of each (refined) candidate segmentation on the graph
        of the polynomial's gradients, lower is better; NaN with a single
        candidate, which is not selected.
    candidate_vote_cuts_ : ndarray of shape (n_candidates,)
        Normalised cut of each (refined) candidate on the vote graph of the
        ``n_votes`` randomized-voting runs, between 0 and ``n_clusters``,
        lower is better; NaN with ``n_votes=0`` or a single candidate.
    vote_confidence_ : float
        Confidence of the vote graph, in [0, 1]: the mean of the eigenvalues
        ``2 .. n_clusters`` of the normalised vote matrix (1 when all runs
        agree; see Notes), computed with ``vote_weighting="confidence"``
        (the default) only; NaN with ``vote_weighting="equal"``, with
        ``n_votes=0`` or with a single candidate.
    candidate_residuals_ : ndarray of shape (n_candidates,)
        Sum of squared sine distances of the (unit) points to their cluster's
        fitted subspace, for each candidate, lower is better. The kept
        candidate has the smallest ``candidate_ncuts_ + w *
        candidate_vote_cuts_`` (``w = vote_confidence_``, or 1 with
        ``vote_weighting="equal"``; ``candidate_ncuts_`` alone with
        ``n_votes=0``) among those within a factor 3 of the smallest residual
        (see Notes).
    chosen_candidate_ : int
        Index of the kept candidate: ``2 g + s`` with graph ``g`` (0: the
        affinity graph, 1: its coarse scale, 2: the product graph; the coarse
        graph is skipped, and the product graph is 1, when there are too few
        points for a coarser neighbourhood) and ``s`` (0: plain split, 1:
        over-segmented and merged).
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
        Exponents of the monomials of degree ``n_clusters_``; ``n_monomials =
        C(n_clusters_ + n_features - 1, n_clusters_)``. The polynomial at ``w``
        is ``coef_ @ np.prod(w ** exponents_, axis=1)``.
    segmentation_components_ : ndarray of shape (segmentation_dim, \
n_features_in_) or None
        With ``segmentation_dim``: the leading principal directions of the
        training points (not centred), in which they are segmented; the
        other attributes' ``n_features`` is then ``segmentation_dim``. None
        otherwise.
    segmentation_scale_ : ndarray of shape (segmentation_dim,) or None
        The singular values of the training points along
        ``segmentation_components_``: a point ``x`` is segmented at
        ``segmentation_components_ @ x / segmentation_scale_``.
    segmentation_projection_ : PowerFactorization or None
        With ``segmentation_dim`` and training points with missing entries:
        the fitted projection to the segmentation space (its
        ``components_`` and ``singular_values_`` are
        ``segmentation_components_`` and ``segmentation_scale_``; its
        ``transform`` projects the points ``predict`` is given). None
        otherwise.
    input_bases_ : list of ndarray of shape (n_features_in_, \
input_subspace_dim) or None
        With ``input_subspace_dim``: orthonormal bases of the subspaces of
        the reassignment in the input width, one per cluster (None for a
        cluster too small to fit, which keeps its points and takes no
        other). None without ``input_subspace_dim``.
    input_residual_scale_ : float or None
        The typical misfit of that reassignment: the median squared residual
        per degree of freedom of the training points to their own group's
        subspace in the input width. None without ``input_subspace_dim``.
    n_features_in_ : int
        Number of features seen during :term:`fit`.
    feature_names_in_ : ndarray of shape (n_features_in_,)
        Names of features seen during :term:`fit`. Defined only when `X`
        has feature names that are all strings.

    See Also
    --------
    gpca : The function this estimator calls.
    NClustersSearch : Choose ``n_clusters`` around any clusterer or pipeline.
    sklearn.cluster.SpectralClustering : Spectral clustering of a dense
        affinity matrix.
    sklearn.decomposition.PCA : Single linear subspace, fitted after centring.
    sklearn_gpca.PowerFactorization : Projection onto a low-dimensional space
        with missing entries; put it in front of this estimator.

    Notes
    -----
    With ``P`` points ``w_i`` in :math:`R^K` and ``n = n_clusters``, the Veronese
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
    2-D planes in :math:`R^5`); several polynomials are needed then (section 2.2.4,
    "Modelling low-dimension subspaces"): ``point_normals="all_polynomials"``
    takes the ``n_polynomials_`` least singular vectors of ``W~`` (their number
    from the largest gap of its log singular values) and, at each point, the
    span of their gradients as the normal subspace ``N_i``, compared through
    ``tr(P_i P_j)`` as below. Points whose gradient vanishes, e.g. on the
    intersection of two subspaces, carry no normal information and are
    labelled arbitrarily.

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
    polynomial gradients (the paper's normals, power ``q``) plus the
    normalised cut on the vote graph of randomized voting (Jung, Ju & Kim,
    CVPR 2014), among the candidates whose residual is at most 3 times the
    smallest: where two motions overlap in :math:`R^5` the kNN cut alone can
    prefer merging them and splitting a third one in two, a segmentation
    whose hyperplanes fit several times worse. The vote graph is global:
    ``R = n_votes`` runs of plain K-subspaces (five rounds), each from
    ``n`` hyperplanes spanned by a random point and ``K - 2`` of its
    ``k / 3`` nearest neighbours, and ``V_ij`` the number of runs that put
    ``i`` and ``j`` together. ``V = B B^T`` with ``B`` the ``P x R n``
    one-hot matrix of the runs' labels, so its cut costs ``O(P R n)``.
    The vote graph's confidence ``c`` is the mean of the eigenvalues
    ``2 .. n`` of ``D^{-1/2} V D^{-1/2}``: every labelling cuts ``V`` by at
    least ``(n - 1)(1 - c)`` (the spectral relaxation), so when the runs
    disagree (``c`` small) no candidate separates well on ``V``: by default
    (``vote_weighting="confidence"``) the vote cut is weighted by ``c``.
    ``benchmarks/results/selection.md`` measures how the cuts and the
    residual agree with the error on Hopkins155. Where the vote graph is
    uncertain the kNN cut decides, and its graph favours the candidates
    split from the product graph it is a factor of: on the 3x10^5 draw of
    ``benchmarks/results/scaling.md`` (``c = 0.24``) it keeps a candidate
    merging two motions (residual 1.9 times the smallest, inside the fit
    gate) that the equal-weight vote cut rejects. The same kNN-against-votes
    conflict, with the votes wrong, is the common case on tracks with
    missing entries and occlusions, hence the default.

    Large ``n_samples`` (beyond the paper). The Lanczos iterations on the
    kNN graph grow faster than linearly with ``P`` and the exact neighbour
    search costs ``O(P log P)`` with a large constant. Above
    ``max_spectral_samples`` points the graph route therefore runs on a random
    subsample of ``m`` points. Every other point gets as neighbours its ``k /
    3`` nearest subsample points (a KD-tree on the ``2 m`` points ``+-x_j``,
    ``O(P log m)``) and the subsample points keep theirs; on this graph the
    points are assigned by the smoothed cost above with the subspaces of the
    subsample's segments (without the smoothing term the extension fails near
    intersections), and the smoothed K-subspaces iterations (``O(P K^2 n + P
    k)`` each) run on all points. The polynomial is fitted to all points
    through the chunked ``M_n x M_n`` Gram matrix of the embedding, exactly.
    Time and memory are ``O(m k + P K^2 n)``; ``benchmarks/results/scaling.md``
    measures them. The all-pairs route is linear and exact at any size and
    never subsamples.

    References
    ----------
    .. [1] R. Vidal and R. Hartley, "Motion Segmentation with Missing Data
       using PowerFactorization and GPCA", CVPR 2004.
    .. [2] A. Ng, M. Jordan and Y. Weiss, "On Spectral Clustering: Analysis
       and an algorithm", NIPS 2001.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca import GPCAClustering
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
            Count(1, None, closed="left"),
            StrOptions({"auto"}),
        ],
        "max_clusters": [Count(1, None, closed="left")],
        "segmentation_dim": [Count(2, None, closed="left"), None],
        "input_subspace_dim": [Count(1, None, closed="left"), None],
        "criterion": [StrOptions({"auto", *CRITERIA}), callable],
        **_PARAMETER_CONSTRAINTS,
    }

    def __init__(
        self,
        n_clusters=2,
        *,
        max_clusters=5,
        segmentation_dim=None,
        input_subspace_dim=None,
        criterion="auto",
        normalize=True,
        point_normals="local",
        affinity="nearest_neighbors",
        n_neighbors=30,
        affinity_power=4,
        init="multi",
        n_init=10,
        n_votes=100,
        vote_weighting="confidence",
        refine=True,
        smoothing=5.0,
        subspace_dim=None,
        normal_tol=0.05,
        subspace_dim_tol=0.05,
        max_iter=50,
        max_spectral_samples=5000,
        n_jobs=None,
        random_state=None,
    ):
        self.n_clusters = n_clusters
        self.max_clusters = max_clusters
        self.segmentation_dim = segmentation_dim
        self.input_subspace_dim = input_subspace_dim
        self.criterion = criterion
        self.normalize = normalize
        self.point_normals = point_normals
        self.affinity = affinity
        self.n_neighbors = n_neighbors
        self.affinity_power = affinity_power
        self.init = init
        self.n_init = n_init
        self.n_votes = n_votes
        self.vote_weighting = vote_weighting
        self.refine = refine
        self.smoothing = smoothing
        self.subspace_dim = subspace_dim
        self.normal_tol = normal_tol
        self.subspace_dim_tol = subspace_dim_tol
        self.max_iter = max_iter
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
        if self.segmentation_dim is None:
            _check_complete(X)
        return X

    def _gpca_params(self):
        params = self.get_params()
        for name in (
            "n_clusters",
            "max_clusters",
            "segmentation_dim",
            "input_subspace_dim",
            "criterion",
        ):
            del params[name]
        return params

    def _criterion(self):
        if self.criterion != "auto":
            return criterion_function(self.criterion)
        wide = self.segmentation_dim is not None
        return CRITERIA[
            "refined_trajectory_coding_length" if wide else "distinct_coding_length"
        ]

    def _segment(self, X, Z):
        """The fit of ``n_clusters`` on ``Z``, and the criterion of each n
        judged on ``X`` with ``n_clusters="auto"`` (else None)."""
        if self.n_clusters == "auto":
            return self._select_n_clusters(X, Z)
        return _gpca(Z, self.n_clusters, self._gpca_params()), None

    def _fit_segmentation_space(self, X):
        """Directions, scales and projection of the segmentation space (None
        without ``segmentation_dim``; the projection None for complete
        points) and the points to segment."""
        if self.segmentation_dim is None:
            if self.input_subspace_dim is not None:
                raise ValueError(
                    f"input_subspace_dim={self.input_subspace_dim} needs "
                    "segmentation_dim: the reassignment runs in the input's "
                    "width after the segmentation in its leading directions."
                )
            return None, None, None, X
        if self.segmentation_dim > min(X.shape):
            raise ValueError(
                f"segmentation_dim={self.segmentation_dim} exceeds the "
                f"n_samples={X.shape[0]} or n_features={X.shape[1]} of X: "
                "X has at most min(n_samples, n_features) principal directions."
            )
        if self.input_subspace_dim is not None and not (
            self.input_subspace_dim < X.shape[1] > self.segmentation_dim
        ):
            raise ValueError(
                f"input_subspace_dim={self.input_subspace_dim} needs an input "
                f"wider than it and than segmentation_dim="
                f"{self.segmentation_dim}; X has n_features={X.shape[1]}."
            )
        if np.isnan(X).any():
            if self.n_clusters == "auto":
                raise ValueError(
                    "n_clusters='auto' needs complete X: its criterion judges "
                    "the trajectories themselves. Put PowerFactorization in "
                    "front, e.g. make_pipeline(PowerFactorization(20, "
                    "whiten=False), GPCAClustering('auto', segmentation_dim=5))."
                )
            # the coordinates of PowerFactorization(segmentation_dim), fitted
            # to the observed entries (the default pipeline's projection)
            projection = PowerFactorization(
                self.segmentation_dim, random_state=self.random_state
            )
            Z = projection.fit_transform(X)
            return projection.components_, projection.singular_values_, projection, Z
        components, scale = fit_segmentation_space(X, self.segmentation_dim)
        return components, scale, None, to_segmentation_space(X, components, scale)

    def _reassign_in_input(self, X, labels):
        """The anchored reassignment in the input width (input_subspace_dim):
        labels, bases, scale and typical residual degrees of freedom."""
        if self.input_subspace_dim is None:
            return labels, None, None, None
        return fit_input_reassignment(
            X,
            labels,
            self.n_clusters_,
            self.input_subspace_dim,
            check_random_state(self.random_state),
        )

    def _to_segmentation_space(self, X):
        if self.segmentation_components_ is None:
            return X
        if self.segmentation_projection_ is not None:
            return self.segmentation_projection_.transform(X)
        return to_segmentation_space(
            X, self.segmentation_components_, self.segmentation_scale_
        )

    def _feasible_n_clusters(self, X):
        """``1 .. max_clusters`` while the Veronese embedding has enough points.

        Degree ``n`` needs ``n_monomials - 1`` non-zero points on distinct
        lines; ``n = 1`` is always tried, so that too few points raise the
        error of the fit.
        """
        n_nonzero = _distinct_lines(X)[0].size
        feasible = [1]
        for n in range(2, self.max_clusters + 1):
            if n_monomials(X.shape[1], n) - 1 > n_nonzero:
                break
            feasible.append(n)
        return feasible

    def _select_n_clusters(self, X, Z):
        """``n_clusters="auto"``: :func:`select_n_clusters` over the feasible n,
        segmenting ``Z`` and judging the labels on ``X``."""
        feasible = self._feasible_n_clusters(Z)
        params = self._gpca_params()

        def segment(n):
            result = _gpca(Z, n, params)
            return X, result.labels, result

        best, costs, results = select_n_clusters(
            segment, feasible, criterion=self._criterion()
        )
        all_costs = np.full(self.max_clusters, np.inf)
        all_costs[: len(feasible)] = costs
        return results[best], all_costs

    @_fit_context(prefer_skip_nested_validation=True)
    def fit(self, X, y=None):
        """Fit the polynomials and segment the points of `X`.

        Parameters
        ----------
        X : array-like of shape (n_samples, n_features)
            Points, e.g. tracks in R^5; NaN (missing) only with segmentation_dim.
        y : Ignored
            Not used, present for API consistency by convention.

        Returns
        -------
        self : object
            Fitted estimator.
        """
        X = self._validate_X(X, reset=True)
        *space, Z = self._fit_segmentation_space(X)
        self.segmentation_components_, self.segmentation_scale_ = space[:2]
        self.segmentation_projection_ = space[2]
        result, costs = self._segment(X, Z)
        if costs is not None:
            self.n_clusters_costs_ = costs
        self.n_clusters_ = len(result.subspace_bases)
        self.labels_, *reassignment = self._reassign_in_input(X, result.labels)
        self.input_bases_, self.input_residual_scale_, self._input_dof = reassignment
        self.normals_ = result.normals
        self.subspace_bases_ = result.subspace_bases
        self.point_normals_ = result.point_normals
        self.polynomials_ = polynomials = result.polynomials
        self.coef_, self.n_polynomials_ = polynomials[0], polynomials.shape[0]
        self.exponents_ = veronese_exponents(Z.shape[1], self.n_clusters_)
        self.n_spectral_samples_ = result.segmented.size
        self.n_iter_ = result.n_iter
        for name in _SELECTION_FIELDS:
            setattr(self, f"{name}_", result[name])
        self.reference_points_ = unit_rows(Z[result.reference])
        self.reference_labels_ = result.labels[result.reference]
        self.residual_scale_ = result.residual_scale
        return self

    def predict(self, X):
        """Label each point by the rule of the refinement.

        With ``refine=True`` and ``smoothing > 0``, the label minimising the
        smoothed cost of K-subspaces (see Notes): the squared sine distance to
        each fitted subspace over ``residual_scale_``, plus ``smoothing`` for
        each of its ``n_neighbors // 3`` nearest ``reference_points_`` (its own
        line excluded) with another label. A training point gets the
        neighbours it had in the fit, so ``predict`` on the training data
        gives ``labels_`` (the fit's fixed point) except where the refinement
        stopped on a 2-cycle or at ``max_iter``. Otherwise (and for
        ``refine=False``, whose ``labels_`` are the spectral clustering's) the
        nearest subspace, ``argmin_k sin(x, S_k)``. With
        ``input_subspace_dim``, that label is then the anchor of the
        reassignment in the input width, with the fitted ``input_bases_`` and
        ``input_residual_scale_``.

        Parameters
        ----------
        X : array-like of shape (n_samples, n_features)
            Points, new or not.

        Returns
        -------
        labels : ndarray of shape (n_samples,), dtype=intp
            The origin, which lies on every subspace, gets label 0.
        """
        check_is_fitted(self)
        X_input = self._validate_X(X, reset=False)
        X = self._to_segmentation_space(X_input)
        unit = unit_rows(X)
        n_reference = self.reference_points_.shape[0]
        neighbor_labels, smoothing = None, 0.0
        if n_reference > 1 and self.smoothing > 0:
            n_local = max(min(self.n_neighbors, n_reference - 1) // 3, 1)
            neighbors = reference_neighbors(
                self.reference_points_, n_local, unit, n_jobs=self.n_jobs
            )
            neighbor_labels, smoothing = (
                self.reference_labels_[neighbors],
                self.smoothing,
            )
        scale = 1.0 if np.isnan(self.residual_scale_) else self.residual_scale_
        labels = smoothed_assignment(
            unit, self.subspace_bases_, scale, neighbor_labels, smoothing
        )
        labels[~np.any(X, axis=1)] = 0
        if self.input_bases_ is not None:
            labels = input_reassignment(
                X_input,
                labels,
                self.input_bases_,
                self.input_residual_scale_,
                self._input_dof,
            )
        return labels

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        # missing entries are projected by PowerFactorization(segmentation_dim)
        tags.input_tags.allow_nan = self.segmentation_dim is not None
        return tags

    def score(self, X, y=None):
        """Minus the ``criterion`` per point of `X` segmented by ``predict``.

        Higher is better. The criterion of ``n_clusters="auto"``, divided by
        the number of points; by default :func:`distinct_coding_length_cost`,
        the bits needed to code the unit points of `X` up to a distortion of
        0.03 when each group that ``predict`` forms is coded by its own
        Gaussian, plus the group memberships, and ``-inf`` when two of these
        groups lie on one hyperplane (:func:`merge_ratio` below 5). Too few
        subspaces merge groups into a costlier one; too many split a group
        into pieces that are not distinct subspaces: on a union of ``n``
        subspaces the score peaks at ``n_clusters = n``, and ``GridSearchCV``
        over ``n_clusters`` chooses by the same criterion as
        ``n_clusters="auto"`` (it warns that some test scores are
        non-finite). The coding length of a few points per group favours
        fewer groups: held-out folds need tens of points per subspace.

        Parameters
        ----------
        X : array-like of shape (n_samples, n_features)
            Points to score, e.g. held-out data.
        y : Ignored
            Not used, present for API consistency by convention.

        Returns
        -------
        score : float
            Minus the criterion per point (bits per point by default).
        """
        check_is_fitted(self)
        X = self._validate_X(X, reset=False)
        _check_complete(X)
        cost = self._criterion()(X, self.predict(X))
        return -cost / X.shape[0]
