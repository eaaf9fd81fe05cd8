"""Choosing the number of subspaces (motions) by a stated criterion.

A criterion is a cost of a segmentation, lower is better: a function
``criterion(points, labels) -> float`` of the points a clusterer segmented and
the labels it gave them. :func:`select_n_clusters` fits one segmentation per
candidate number and keeps the cheapest; :class:`NClustersSearch` does the
same around any clusterer (or pipeline ending in one), in the spirit of
:class:`~sklearn.model_selection.GridSearchCV`, and exposes the winner as
``best_estimator_``. ``GPCAClustering(n_clusters="auto")`` and
``GPCAClustering.score`` use :func:`distinct_coding_length_cost` on the
points they segment (the coding length of the segmentations whose groups are
distinct subspaces), and :func:`trajectory_coding_length_cost` on wider,
unwhitened inputs that ``GPCAClustering(segmentation_dim=5)`` projects itself
(the coding length of the trajectories in up to ``4 * max_clusters``
dimensions, where distinct motions are distinct subspaces).
"""

# SPDX-License-Identifier: BSD-3-Clause

import warnings

import numpy as np
from scipy.special import logsumexp
from sklearn.base import (
    BaseEstimator,
    ClusterMixin,
    MetaEstimatorMixin,
    _fit_context,
    clone,
)
from sklearn.exceptions import FitFailedWarning
from sklearn.pipeline import Pipeline
from sklearn.utils._param_validation import HasMethods, StrOptions
from sklearn.utils.validation import check_is_fitted

from sklearn_gpca._coding_descent import coding_length_descent
from sklearn_gpca._coding_length import coding_length
from sklearn_gpca._rows import unit_rows
from sklearn_gpca._subspaces import fit_subspaces, sine_residuals

# Distortion (root mean squared error per unit point) of the coding length.
CODING_DISTORTION = 0.03

# Smallest merge ratio (see merge_ratio) of two groups that count as distinct
# subspaces. Chosen on Hopkins155 (155 sequences) and on synthetic draws of 1-5
# motions: benchmarks/results/n_motions.md gives the figures at 3, 5 and 8.
MIN_MERGE_RATIO = 5.0

# Distortion of the coding length of unit trajectories in a wide, unwhitened
# projection (trajectory_coding_length_cost), and the fewest points per
# dimension it codes. Chosen on the even-indexed Hopkins155 sequences (0.005,
# 0.007, 0.01, 0.015 and 3, 4, 6 tried); benchmarks/results/n_motions.md gives
# the odd-indexed ones as held out, and the synthetic draws.
TRAJECTORY_DISTORTION = 0.007
POINTS_PER_DIMENSION = 4

# Fewest trajectories of a motion for refined_trajectory_coding_length_cost:
# 4 points per dimension (POINTS_PER_DIMENSION) of a rigid motion's subspace of
# dimension at most 4 (Vidal & Hartley, section 2.1). Derived, not tuned: on
# the even-indexed Hopkins155 sequences 9 to 16 count alike
# (benchmarks/results/n_motions.md).
MOTION_DIMENSION = 4
MIN_MOTION_POINTS = POINTS_PER_DIMENSION * MOTION_DIMENSION

# Most trajectories refined_trajectory_coding_length_cost codes (evenly spaced
# in the given order, the bits scaled to all of them). With a fixed distortion
# the coding length is not consistent as the number of points grows: the
# trajectories of one rigid motion are not Gaussian inside its subspace, and
# with tens of thousands of them the descent finds a split of the motion that
# codes in fewer bits (a 10^4-trajectory motion of a make_motions draw, 251
# bits). Above the largest Hopkins155 sequence (556 trajectories), where the
# criterion was measured; not tuned.
MAX_CODED_TRAJECTORIES = 1000


def coding_length_cost(points, labels):
    """Lossy coding length, in bits, of the unit points segmented by ``labels``.

    The number of bits needed to code the points scaled to unit norm up to a
    distortion of 0.03 per point, each group by its own zero-mean Gaussian,
    plus the bits of the group memberships (Ma, Derksen, Hong & Wright, PAMI
    2007). Splitting a subspace in two costs more bits than it saves, and so
    does merging two subspaces into one of higher dimension: the minimum over
    the number of groups is a model-selection criterion with no further
    penalty.

    Parameters
    ----------
    points : ndarray of shape (n_samples, n_features)
        The points that were segmented (e.g. trajectories projected to
        :math:`R^5`).
    labels : ndarray of shape (n_samples,)
        Non-negative group of each point.

    Returns
    -------
    bits : float
        Lower is better.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca import coding_length_cost
    >>> rng = np.random.RandomState(0)
    >>> X = np.vstack([np.c_[rng.randn(50, 2), np.zeros(50)],
    ...                np.c_[np.zeros(50), rng.randn(50, 2)]])
    >>> y = np.repeat([0, 1], 50)
    >>> bool(coding_length_cost(X, y) < coding_length_cost(X, 0 * y))
    True
    """
    return coding_length(unit_rows(points), labels, CODING_DISTORTION)


def sine_likelihood_cost(points, labels):
    """Minus a penalised likelihood of the sine distances to the groups' hyperplanes.

    With ``d_ik`` the sine of the angle between point ``x_i`` and the
    hyperplane fitted to group ``k`` (``n`` groups of ``P`` points in
    :math:`R^K`), the cost is ``P`` times ::

        - mean_i log( (1 / n) sum_k 1 / (d_ik + 1e-6) )
            + n (K - 1) log(P) / (2 P)

    the negative log-likelihood, up to a constant, of an equal-weight mixture
    of scale-free (``1 / d``) densities of the sine distance, plus the BIC
    penalty of the ``n`` unit normals. Hyperplanes that contain their points
    exactly make the first term small whatever ``K``, and the penalty grows
    with ``K``: on noise-free unions of hyperplanes it is smallest at the true
    number of groups and at the rank that makes the subspaces hyperplanes, so
    it can compare ranks, which :func:`coding_length_cost` cannot (fewer
    dimensions always code in fewer bits). With noise it tends to prefer
    more groups than there are.

    Parameters
    ----------
    points : ndarray of shape (n_samples, n_features)
        The points that were segmented.
    labels : ndarray of shape (n_samples,)
        Non-negative group of each point.

    Returns
    -------
    cost : float
        Lower is better.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca import sine_likelihood_cost
    >>> rng = np.random.RandomState(0)
    >>> X = np.vstack([np.c_[rng.randn(50, 2), np.zeros(50)],
    ...                np.c_[np.zeros(50), rng.randn(50, 2)]])
    >>> y = np.repeat([0, 1], 50)
    >>> bool(sine_likelihood_cost(X, y) < sine_likelihood_cost(X, 0 * y))
    True
    """
    unit = unit_rows(points)
    n_samples, n_features = unit.shape
    groups = np.unique(labels, return_inverse=True)[1].reshape(-1)
    n_groups = groups.max() + 1
    bases, _ = fit_subspaces(unit, groups, n_groups, n_features - 1, 0.0)
    sines = np.sqrt(sine_residuals(unit, bases))
    fit = np.mean(logsumexp(-np.log(sines + _SINE_FLOOR), axis=1)) - np.log(n_groups)
    penalty = n_groups * (n_features - 1) * np.log(n_samples) / (2 * n_samples)
    return float(n_samples * (penalty - fit))


# Share of a set's points whose squared sines make its hyperplane energy.
_KEPT_SHARE = 0.9


def _hyperplane_energy(unit):
    """Sum of the smallest 90 % squared sines of unit points to a hyperplane.

    The hyperplane through the origin fitted to all the points (least
    eigenvector of their Gram matrix) is refitted once to the 90 % it fits
    best: a few points misassigned to a group do not make it look curved.
    """
    n_kept = max(int(np.ceil(_KEPT_SHARE * unit.shape[0])), unit.shape[1])
    normal = np.linalg.eigh(unit.T @ unit)[1][:, 0]
    kept = np.argsort((unit @ normal) ** 2)[:n_kept]
    normal = np.linalg.eigh(unit[kept].T @ unit[kept])[1][:, 0]
    return float(np.sort((unit @ normal) ** 2)[:n_kept].sum())


def merge_ratio(points, labels):
    """How much worse two groups fit one hyperplane than one each, at the worst pair.

    With ``E(S)`` the sum of squared sines between the unit points of a set
    ``S`` and the hyperplane through the origin that fits them best, the
    merge ratio of groups ``a`` and ``b`` is ``E(a | b) / (E(a) + E(b))``:
    about 1 when both lie on one hyperplane (one subspace split in two),
    large when they lie on two. The smallest ratio over the pairs of groups
    says whether every group is a subspace of its own. ``E`` is trimmed: the
    hyperplane fitted to all the points of ``S`` (least eigenvector of their
    Gram matrix) is refitted to the 90 % it fits best, and ``E`` sums their
    squared sines, so that a few misassigned points (e.g. held-out points
    labelled by ``predict``) do not make a group look like two.

    Parameters
    ----------
    points : ndarray of shape (n_samples, n_features)
        The points that were segmented.
    labels : ndarray of shape (n_samples,)
        Non-negative group of each point.

    Returns
    -------
    ratio : float
        The smallest merge ratio over the pairs of non-empty groups; ``inf``
        with a single group; 0 when a group has fewer points than
        ``n_features`` (any such group lies on a hyperplane, so it cannot be
        told apart). Two groups that both fit a hyperplane exactly have
        ratio 0 if they fit one together, ``inf`` otherwise.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca import merge_ratio
    >>> rng = np.random.RandomState(0)
    >>> X = np.vstack([np.c_[rng.randn(50, 2), np.zeros(50)],
    ...                np.c_[np.zeros(50), rng.randn(50, 2)]])
    >>> X += 0.01 * rng.randn(*X.shape)
    >>> y = np.repeat([0, 1], 50)
    >>> bool(merge_ratio(X, y) > 100)
    True
    >>> bool(merge_ratio(X, np.arange(100) % 2) < 2)  # each plane split in two
    True
    """
    unit = unit_rows(points)
    groups = np.unique(labels, return_inverse=True)[1].reshape(-1)
    n_groups, n_features = groups.max() + 1, unit.shape[1]
    if n_groups == 1:
        return np.inf
    if np.bincount(groups).min() < n_features:
        return 0.0
    members = [unit[groups == k] for k in range(n_groups)]
    energies = np.array([_hyperplane_energy(group) for group in members])
    first, second = np.triu_indices(n_groups, 1)
    merged = np.array(
        [
            _hyperplane_energy(np.vstack([members[a], members[b]]))
            for a, b in zip(first, second, strict=True)
        ]
    )
    separate = energies[first] + energies[second]
    with np.errstate(divide="ignore", invalid="ignore"):
        ratios = np.where(
            separate > 0, merged / separate, np.where(merged > 0, np.inf, 0.0)
        )
    return float(ratios.min())


def distinct_coding_length_cost(points, labels):
    """The coding length of a segmentation into distinct subspaces, else ``inf``.

    :func:`coding_length_cost` when every pair of groups has a
    :func:`merge_ratio` of at least 5 (``MIN_MERGE_RATIO``): the hyperplane
    fitted to any two groups together leaves at least five times the squared
    sines of their own two hyperplanes. Otherwise ``inf``: some group is a
    piece of another's subspace. A single group always qualifies.

    The coding length alone prefers more groups than there are motions on
    real trajectories: a motion that is not exactly a subspace of
    :math:`R^5` (perspective, tracking noise, points on planar faces) codes
    in fewer bits as several Gaussians, and on Hopkins155 it finds the
    number of motions on a quarter of the sequences. The pieces of one
    motion still lie near one hyperplane, which this cost checks.

    Parameters
    ----------
    points : ndarray of shape (n_samples, n_features)
        The points that were segmented.
    labels : ndarray of shape (n_samples,)
        Non-negative group of each point.

    Returns
    -------
    bits : float
        Lower is better; ``inf`` when two groups are not distinct subspaces.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca import distinct_coding_length_cost
    >>> rng = np.random.RandomState(0)
    >>> X = np.vstack([np.c_[rng.randn(50, 2), np.zeros(50)],
    ...                np.c_[np.zeros(50), rng.randn(50, 2)]])
    >>> X += 0.01 * rng.randn(*X.shape)
    >>> y = np.repeat([0, 1], 50)
    >>> bool(distinct_coding_length_cost(X, y) < distinct_coding_length_cost(X, 0 * y))
    True
    >>> distinct_coding_length_cost(X, np.arange(100) % 2)  # each plane split
    inf
    """
    if merge_ratio(points, labels) < MIN_MERGE_RATIO:
        return np.inf
    return coding_length_cost(points, labels)


def coded_trajectories(points):
    """The unit trajectories the trajectory coding length codes.

    Unit rows, projected on their ``n_samples // 4`` leading (uncentred)
    principal directions and scaled back to unit length when there are fewer
    than 4 points per dimension.
    """
    unit = unit_rows(points)
    n_samples, n_features = unit.shape
    width = min(n_features, max(n_samples // POINTS_PER_DIMENSION, 1))
    if width < n_features:
        # leading principal directions of the unit trajectories, not centred:
        # the subspaces are linear
        _, _, components = np.linalg.svd(unit, full_matrices=False)
        unit = unit_rows(unit @ components[:width].T)
    return unit


def trajectory_coding_length(points, labels):
    """:func:`trajectory_coding_length_cost` without the input checks."""
    return coding_length(coded_trajectories(points), labels, TRAJECTORY_DISTORTION)


def trajectory_coding_length_cost(points, labels):
    """Coding length, in bits, of unit trajectories in a wide projection.

    The lossy coding length of :func:`coding_length_cost` with a distortion
    of 0.007 (``TRAJECTORY_DISTORTION``), for points that keep the geometry
    of the trajectories: the *unwhitened* projection of rank ``4 *
    max_clusters`` (``PowerFactorization(n_components=20, whiten=False)``),
    where each rigid motion is a subspace of dimension at most 4 (Vidal &
    Hartley, section 2.1) and distinct motions are distinct subspaces. Each
    group is coded by its own zero-mean Gaussian, so a group's dimension is
    estimated by the code itself: a planar or translating motion of
    dimension 2 or 3 costs fewer bits, and is not split.

    In the whitened :math:`R^5` of the segmentation, every direction has unit
    variance, so perspective and tracking errors weigh as much as the
    motions, and two of three motions often lie near one hyperplane; in the
    wider unwhitened projection they keep their small weight. With few
    points the code of each group's Gaussian dominates: the unit points are
    first projected on their ``n_samples // 4`` leading principal directions
    (not centred) and scaled back to unit length when there are fewer than 4
    points per dimension (``POINTS_PER_DIMENSION``). The cost depends only on
    the directions of the trajectories and on the partition: not on their
    lengths, an orthogonal change of coordinates or the names of the groups.

    Parameters
    ----------
    points : ndarray of shape (n_samples, n_features)
        The trajectories, projected without whitening (e.g. the unwhitened
        output of :class:`PowerFactorization` of rank 20).
    labels : ndarray of shape (n_samples,)
        Non-negative group of each point.

    Returns
    -------
    bits : float
        Lower is better.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca import PowerFactorization
    >>> from sklearn_gpca import trajectory_coding_length_cost as cost
    >>> from sklearn_gpca.datasets import make_motions
    >>> X, y = make_motions(3, n_points=300, min_angle=30, random_state=0)
    >>> Z = PowerFactorization(20, whiten=False, random_state=0).fit_transform(X)
    >>> split = np.where(np.arange(300) % 2, y, y + 3)  # each motion in two
    >>> bool(cost(Z, y) < min(cost(Z, 0 * y), cost(Z, split)))
    True
    """
    points = np.asarray(points, dtype=np.float64)
    return trajectory_coding_length(points, np.asarray(labels))


def _checked_points_labels(points, labels):
    """``points`` as a finite 2-D float array and ``labels`` as non-negative
    integers, one per point, else a ``ValueError`` naming the problem."""
    points = np.asarray(points, dtype=np.float64)
    labels = np.asarray(labels)
    if points.ndim != 2:
        raise ValueError(f"points must be a 2-D array, got shape {points.shape}.")
    if labels.shape != (points.shape[0],):
        raise ValueError(
            f"labels must give one group per point: {points.shape[0]} points "
            f"but {labels.size} labels of shape {labels.shape}."
        )
    if not np.all(np.isfinite(points)):
        raise ValueError("points must be finite (no NaN or infinity).")
    if labels.size and (not np.all(np.mod(labels, 1) == 0) or labels.min() < 0):
        raise ValueError("labels must be non-negative integers.")
    return points, labels.astype(np.intp)


def refine_trajectory_segmentation(points, labels):
    """The segmentation and bits that the coding-length descent reaches.

    :func:`~sklearn_gpca._coding_descent.coding_length_descent` on the coded
    trajectories of :func:`trajectory_coding_length_cost`, started from
    ``labels``.

    Parameters
    ----------
    points : ndarray of shape (n_samples, n_features)
        The trajectories, projected without whitening.
    labels : ndarray of shape (n_samples,)
        Non-negative group of each point.

    Returns
    -------
    labels : ndarray of shape (n_samples,), dtype=intp
        The refined groups, numbered ``0 .. n - 1`` in the order of the
        starting ones (``n`` starting groups, some possibly left empty).
    bits : float
        Their trajectory coding length.
    """
    groups = np.unique(np.asarray(labels), return_inverse=True)[1].reshape(-1)
    unit = coded_trajectories(np.asarray(points, dtype=np.float64))
    return coding_length_descent(unit, groups, TRAJECTORY_DISTORTION)


def refined_trajectory_coding_length_cost(points, labels):
    """Trajectory coding length of a segmentation refined by coordinate descent.

    The segmentation is first refined on the criterion itself: trajectories
    move one group at a time while :func:`trajectory_coding_length_cost`
    falls (:func:`~sklearn_gpca._coding_descent.coding_length_descent`), so
    that a few misassigned trajectories, which cost the code of their group
    a direction each, do not make a segmentation with one motion more look
    cheaper. The cost is the coding length reached, or ``inf`` when the
    refined segmentation has two groups or more and one of them holds fewer
    than 16 trajectories (``MIN_MOTION_POINTS``: 4 points per dimension of a
    rigid motion's subspace of dimension at most 4; an emptied group counts
    too): a handful of outlying trajectories the descent gathers into a
    group of their own is not a motion. A single group always qualifies.
    Of more than 1000 trajectories (``MAX_CODED_TRAJECTORIES``), 1000
    evenly spaced in the given order are coded and the bits scaled to all:
    with a fixed distortion the coding length of tens of thousands of
    trajectories prefers to split a rigid motion, whose trajectories are not
    Gaussian inside its subspace.

    On Hopkins155, choosing the cheapest of the segmentations into 1 to 5
    motions finds the number of motions on 92 % of the sequences (88 %
    without the descent); ``benchmarks/results/n_motions.md`` gives the
    figures, with synthetic draws where it does worse.

    Parameters
    ----------
    points : ndarray of shape (n_samples, n_features)
        The trajectories, projected without whitening (e.g. the unwhitened
        output of :class:`PowerFactorization` of rank 20).
    labels : ndarray of shape (n_samples,)
        Non-negative group of each point: the segmentation to refine.

    Returns
    -------
    bits : float
        Lower is better; ``inf`` when a refined group of two or more is too
        small to be a motion.

    See Also
    --------
    trajectory_coding_length_cost : The same code without the descent.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca import PowerFactorization
    >>> from sklearn_gpca import refined_trajectory_coding_length_cost as cost
    >>> from sklearn_gpca.datasets import make_motions
    >>> X, y = make_motions(2, n_points=200, min_angle=30, random_state=0)
    >>> Z = PowerFactorization(20, whiten=False, random_state=0).fit_transform(X)
    >>> wrong = y.copy()
    >>> wrong[:10] = 1 - wrong[:10]  # ten trajectories misassigned
    >>> bool(np.isclose(cost(Z, wrong), cost(Z, y)))  # refined back
    True
    >>> outliers = np.where(np.arange(200) < 5, 2, y)  # 5 make no motion
    >>> cost(Z, outliers)
    inf
    """
    points, labels = _checked_points_labels(points, labels)
    n_samples = points.shape[0]
    if n_samples > MAX_CODED_TRAJECTORIES:
        kept = np.linspace(0, n_samples - 1, MAX_CODED_TRAJECTORIES).round()
        points, labels = points[kept.astype(np.intp)], labels[kept.astype(np.intp)]
    refined, bits = refine_trajectory_segmentation(points, labels)
    bits *= n_samples / points.shape[0]
    n_groups = np.unique(labels).size
    if n_groups > 1:
        sizes = np.bincount(refined, minlength=n_groups)
        if sizes.min() < MIN_MOTION_POINTS:
            return np.inf
    return bits


# Sine distances below this floor count as a perfect fit.
_SINE_FLOOR = 1e-6

CRITERIA = {
    "distinct_coding_length": distinct_coding_length_cost,
    "refined_trajectory_coding_length": refined_trajectory_coding_length_cost,
    "trajectory_coding_length": trajectory_coding_length_cost,
    "coding_length": coding_length_cost,
    "sine_likelihood": sine_likelihood_cost,
}


def criterion_function(criterion):
    """The function of a criterion given by name or as a callable."""
    return CRITERIA[criterion] if isinstance(criterion, str) else criterion


def select_n_clusters(segment, n_clusters, *, criterion="distinct_coding_length"):
    """The segmentation, among one per candidate number, that costs least.

    Parameters
    ----------
    segment : callable
        ``segment(n) -> (points, labels, fitted)``: segments into ``n``
        clusters and returns the points it segmented, their labels and the
        fitted object (an estimator, or the result of a function).
    n_clusters : sequence of int
        The candidate numbers, each passed to ``segment``.
    criterion : {"distinct_coding_length", "coding_length", "sine_likelihood"} \
or callable, default="distinct_coding_length"
        ``criterion(points, labels) -> float``, lower is better;
        ``"distinct_coding_length"`` is :func:`distinct_coding_length_cost`,
        ``"coding_length"`` :func:`coding_length_cost` (the former default,
        which over-counts real motions), ``"sine_likelihood"``
        :func:`sine_likelihood_cost`.

    Returns
    -------
    best : int
        Index in ``n_clusters`` of the cheapest segmentation (the first one on
        ties).
    costs : ndarray of shape (len(n_clusters),)
        The criterion of each segmentation.
    fitted : list
        What ``segment`` returned third, for each candidate.

    Notes
    -----
    The warnings of the kept fit are raised, each distinct one once; those of
    the other candidates are dropped (e.g. the empty clusters of a number of
    subspaces that the criterion rejects).

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca import gpca, select_n_clusters
    >>> rng = np.random.RandomState(0)
    >>> X = np.vstack([np.c_[rng.randn(40, 2), np.zeros(40)],
    ...                np.c_[np.zeros(40), rng.randn(40, 2)]])
    >>> def segment(n):
    ...     result = gpca(X, n, random_state=0)
    ...     return X, result.labels, result
    >>> best, costs, results = select_n_clusters(segment, [1, 2, 3])
    >>> [1, 2, 3][best]
    2
    """
    criterion = criterion_function(criterion)
    costs, fitted, caught = [], [], []
    for n in n_clusters:
        with warnings.catch_warnings(record=True) as records:
            warnings.simplefilter("always")
            points, labels, result = segment(n)
        caught.append(dict.fromkeys((r.category, str(r.message)) for r in records))
        costs.append(criterion(points, labels))
        fitted.append(result)
    costs = np.asarray(costs, dtype=np.float64)
    best = int(np.argmin(costs))
    for category, message in caught[best]:
        warnings.warn(message, category, stacklevel=2)
    return best, costs, fitted


def _final_step(estimator):
    return estimator.steps[-1][1] if isinstance(estimator, Pipeline) else estimator


class NClustersSearch(MetaEstimatorMixin, ClusterMixin, BaseEstimator):
    """Choose a clusterer's number of clusters by a stated criterion.

    Fits a clone of ``estimator`` for every candidate ``n_clusters`` and keeps
    the one whose segmentation the criterion prefers: by default the lossy
    coding length of the points the clusterer segmented, among the
    segmentations whose groups are distinct subspaces
    (:func:`distinct_coding_length_cost`). Works around a clusterer or a
    :class:`~sklearn.pipeline.Pipeline` ending in one, e.g.
    ``make_pipeline(PowerFactorization(), GPCAClustering())``, whose final
    step's ``n_clusters`` is searched and whose last input is scored.

    Parameters
    ----------
    estimator : estimator object
        A clusterer with an ``n_clusters`` parameter and a ``labels_``
        attribute, or a pipeline ending in one.
    n_clusters_grid : sequence of int, default=(1, 2, 3, 4, 5)
        The candidate numbers of clusters.
    criterion : {"distinct_coding_length", "coding_length", "sine_likelihood"} \
or callable, default="distinct_coding_length"
        ``criterion(points, labels) -> float``, lower is better (see
        :func:`select_n_clusters`).

    Attributes
    ----------
    best_estimator_ : estimator object
        The fitted clone with the cheapest segmentation.
    best_n_clusters_ : int
        Its number of clusters.
    costs_ : ndarray of shape (len(n_clusters_grid),)
        The criterion of each candidate; ``inf`` where the fit failed (a
        :class:`~sklearn.exceptions.FitFailedWarning` says why).
    labels_ : ndarray of shape (n_samples,)
        The labels of ``best_estimator_``.
    n_features_in_ : int
        Number of features seen during :term:`fit`.

    See Also
    --------
    select_n_clusters : The same choice over any segmenting function.
    sklearn.model_selection.GridSearchCV : Cross-validated search over any
        parameter, by the estimator's ``score``.

    Notes
    -----
    The criterion is measured on the clusterer's own input, so it compares
    numbers of clusters at a fixed representation. Comparing ranks of a
    preceding projection needs a criterion measured in a common space.

    Examples
    --------
    >>> from sklearn.pipeline import make_pipeline
    >>> from sklearn_gpca import GPCAClustering, NClustersSearch, PowerFactorization
    >>> from sklearn_gpca.datasets import make_motions
    >>> X, y = make_motions(2, n_points=200, random_state=0)
    >>> pipe = make_pipeline(PowerFactorization(random_state=0),
    ...                      GPCAClustering(random_state=0))
    >>> search = NClustersSearch(pipe, n_clusters_grid=[1, 2, 3]).fit(X)
    >>> search.best_n_clusters_
    2
    """

    _parameter_constraints: dict = {
        "estimator": [HasMethods(["fit"])],
        "n_clusters_grid": ["array-like"],
        "criterion": [StrOptions(set(CRITERIA)), callable],
    }

    def __init__(
        self,
        estimator,
        *,
        n_clusters_grid=(1, 2, 3, 4, 5),
        criterion="distinct_coding_length",
    ):
        self.estimator = estimator
        self.n_clusters_grid = n_clusters_grid
        self.criterion = criterion

    def _segment(self, X, n):
        model = clone(self.estimator)
        if isinstance(model, Pipeline):
            model.set_params(**{f"{model.steps[-1][0]}__n_clusters": n})
            points = model[:-1].fit_transform(X)
            model.steps[-1][1].fit(points)
        else:
            model.set_params(n_clusters=n)
            points = X
            model.fit(points)
        return points, _final_step(model).labels_, model

    @_fit_context(prefer_skip_nested_validation=False)
    def fit(self, X, y=None):
        """Fit one clone per candidate number of clusters and keep the best.

        Parameters
        ----------
        X : array-like of shape (n_samples, n_features)
            Training data, as ``estimator`` takes it.
        y : Ignored
            Not used, present for API consistency by convention.

        Returns
        -------
        self : object
            Fitted search.
        """
        candidates = [int(n) for n in self.n_clusters_grid]
        failures = {}

        def segment(n):
            try:
                return self._segment(X, n)
            except ValueError as exc:
                failures[n] = exc
                return None, None, None

        def cost(points, labels):
            if points is None:
                return np.inf
            return criterion_function(self.criterion)(np.asarray(points), labels)

        best, self.costs_, fitted = select_n_clusters(
            segment, candidates, criterion=cost
        )
        if len(failures) == len(candidates):
            raise next(iter(failures.values()))
        for n, exc in failures.items():
            warnings.warn(
                f"n_clusters={n} was skipped: its fit failed with {exc}",
                FitFailedWarning,
                stacklevel=2,
            )
        self.best_estimator_ = fitted[best]
        self.best_n_clusters_ = candidates[best]
        self.labels_ = _final_step(self.best_estimator_).labels_
        self.n_features_in_ = self.best_estimator_.n_features_in_
        if hasattr(self.best_estimator_, "feature_names_in_"):
            self.feature_names_in_ = self.best_estimator_.feature_names_in_
        return self

    def predict(self, X):
        """Labels of ``X`` by the best estimator.

        Parameters
        ----------
        X : array-like of shape (n_samples, n_features)
            New data.

        Returns
        -------
        labels : ndarray of shape (n_samples,)
        """
        check_is_fitted(self)
        return self.best_estimator_.predict(X)

    def score(self, X, y=None):
        """Minus the criterion per sample of ``X`` segmented by ``predict``.

        Parameters
        ----------
        X : array-like of shape (n_samples, n_features)
            Data, e.g. held out.
        y : Ignored
            Not used, present for API consistency by convention.

        Returns
        -------
        score : float
            Higher is better.
        """
        check_is_fitted(self)
        best = self.best_estimator_
        points = best[:-1].transform(X) if isinstance(best, Pipeline) else X
        labels = best.predict(X)
        points = np.asarray(points)
        return -criterion_function(self.criterion)(points, labels) / points.shape[0]

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        inner = self.estimator.__sklearn_tags__()
        tags.input_tags = inner.input_tags
        return tags
