"""K-subspaces in the full trajectory space after a segmentation, in linear time.

The paper segments the trajectories after projecting them to :math:`R^5`
(Vidal & Hartley, CVPR 2004, section 2.1). ``n`` generic rigid motions span
``n`` subspaces of dimension 4 of :math:`R^{2F}` (eq. (6)), ``4 n`` dimensions
in all: projected to :math:`R^5` they become hyperplanes that meet in 3-D
subspaces, and every track close to an intersection is ambiguous there while
it is not in :math:`R^{2F}`. This module starts from a segmentation (e.g. that of
``make_pipeline(PowerFactorization(), GPCAClustering(n))``) and runs smoothed
K-subspaces on the raw tracks, each track scored on its own observed entries
(:func:`refine_observed`), with neighbours searched in the projected space:

1. the rounds run on a uniform random subsample of at most
   ``max_fit_samples`` tracks (a 4-D subspace of :math:`R^{2F}` is
   determined to the noise level by a few thousand tracks);
2. every other track is then assigned once by the same smoothed cost, with
   its nearest subsample tracks as neighbours (as stage 6 of :func:`gpca`).

Measured on ``make_motions(3, ..., n_frames=10, missing=0.1)`` draws
(``benchmarks/results/scaling.md`` and its notes) it is not a uniform gain:
it lowers the error of the default pipeline on some draws and raises it on
others, so no estimator applies it by default. Without the smoothing term
K-subspaces drifts from good starts where the motions are close.

:func:`reassign_full_space` is the step that helps after the default
pipeline: one assignment in :math:`R^{2F}`, anchored to the starting labels,
without the :math:`R^5` neighbours (``benchmarks/results/scaling_stages.md``);
``GPCAClustering(n, segmentation_dim=5, input_subspace_dim=4)`` on the raw
tracks runs it after segmenting them as the default pipeline does
(:func:`fit_full_space` and :func:`assign_full_space` are its two halves).

Time and memory are ``O(m D d^2 t + P D d^2 n)`` for ``m`` fitted tracks,
``t`` rounds, ``P`` tracks of ``D = 2F`` coordinates and ``n`` subspaces of
dimension ``d``: linear in ``P``.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
from sklearn.utils import check_array, check_random_state

from sklearn_gpca._affinity import sign_invariant_neighbors
from sklearn_gpca._extension import extension_neighbors
from sklearn_gpca._missing import masked_to_nan
from sklearn_gpca._observed_subspaces import (
    fit_observed_subspace,
    observed_entries,
    subspace_residuals,
)
from sklearn_gpca._refine_observed import (
    assignment_costs,
    neighbor_disagreements,
    refine_observed,
)
from sklearn_gpca._rows import TINY, unit_rows


def _check_labels(labels, n_samples):
    labels = np.asarray(labels)
    if labels.shape != (n_samples,) or not np.issubdtype(labels.dtype, np.integer):
        raise ValueError(
            f"labels must be integers of shape ({n_samples},), one per row of "
            f"X; got dtype {labels.dtype} and shape {labels.shape}."
        )
    if labels.size and labels.min() < -1:
        raise ValueError(
            f"labels must be 0 .. n_clusters - 1, or -1 for a track left "
            f"out; got {labels.min()}."
        )
    return labels.astype(np.intp)


def refine_full_space(
    X,
    labels,
    points,
    *,
    subspace_dim=4,
    smoothing=1.0,
    n_neighbors=10,
    max_iter=30,
    max_fit_samples=5000,
    random_state=None,
):
    """Smoothed K-subspaces on the observed entries of the tracks, from labels.

    Parameters
    ----------
    X : ndarray of shape (n_samples, n_features)
        Tracks ``[x_1, y_1, ..., x_F, y_F]``, NaN where missing.
    labels : ndarray of shape (n_samples,)
        Starting segmentation, ``0 .. n_clusters - 1``; ``-1`` marks tracks
        left out (outliers), which keep ``-1``.
    points : ndarray of shape (n_samples, n_components)
        Complete points in which the neighbours of the smoothing term are
        searched (sign-invariant angles, as :class:`GPCAClustering`), e.g. the
        tracks projected to :math:`R^5` by ``PowerFactorization``.
    subspace_dim : int, default=4
        Dimension of every motion subspace (4 for a generic rigid motion seen
        by an affine camera), clipped to ``n_features - 1``.
    smoothing : float, default=1.0
        Cost of one neighbour with another label, in units of the typical
        misfit of a track (see :func:`refine_observed`); 0 is plain
        K-subspaces.
    n_neighbors : int, default=10
        Neighbours of the smoothing term.
    max_iter : int, default=30
        Maximum number of K-subspaces rounds on the subsample.
    max_fit_samples : int or None, default=5000
        Largest number of tracks the rounds run on (a uniform random
        subsample); the others are then assigned once, with their nearest
        subsample tracks as neighbours. None uses all tracks.
    random_state : int, RandomState instance or None, default=None
        Seeds the subsample and the reseeding of an emptied cluster.

    Returns
    -------
    labels : ndarray of shape (n_samples,), dtype=intp
        The refined segmentation.
    bases : list of ndarray of shape (n_features, d)
        Orthonormal bases of the fitted subspaces, one per label (zero rows on
        coordinates too few tracks observe).
    n_iter : int
        Rounds run.
    converged : bool
        Whether the subsample's labels settled before ``max_iter``.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca import PowerFactorization
    >>> from sklearn_gpca.datasets import make_motions
    >>> from sklearn_gpca.metrics import misclassification_rate
    >>> from sklearn_gpca.stages import refine_full_space
    >>> X, y = make_motions(3, n_points=600, n_frames=10, missing=0.1,
    ...                     random_state=0)
    >>> Z = PowerFactorization(random_state=0).fit_transform(X)
    >>> start = np.where(np.arange(600) % 10 == 0, (y + 1) % 3, y)  # 10 % wrong
    >>> labels, bases, n_iter, converged = refine_full_space(
    ...     X, start, Z, random_state=0)
    >>> float(misclassification_rate(y, labels)) < 0.02, converged
    (True, True)
    """
    rng = check_random_state(random_state)
    X0, mask = observed_entries(X)
    n_samples, n_features = X0.shape
    labels = _check_labels(labels, n_samples)
    points = np.asarray(points, dtype=np.float64)
    if points.shape[0] != n_samples:
        raise ValueError(
            f"points has {points.shape[0]} rows and X {n_samples}: they must "
            "describe the same tracks."
        )
    n_clusters = int(labels.max()) + 1 if labels.size else 0
    if n_clusters == 0:
        return labels, [], 0, True
    dim = max(min(subspace_dim, n_features - 1), 1)
    unit = unit_rows(points)
    kept = np.flatnonzero(labels >= 0)
    sample = kept
    if max_fit_samples is not None and kept.size > max_fit_samples:
        sample = np.sort(rng.choice(kept, max_fit_samples, replace=False))
    k = max(min(n_neighbors, sample.size - 1), 1)
    sample_neighbors = sign_invariant_neighbors(unit[sample], k)
    sample_labels, bases, supports, n_iter, converged = refine_observed(
        X0[sample],
        mask[sample],
        labels[sample],
        n_clusters,
        neighbors=sample_neighbors,
        smoothing=smoothing,
        subspace_dim=dim,
        per_cluster=False,
        max_iter=max_iter,
        random_state=rng,
    )
    refined = labels.copy()
    refined[sample] = sample_labels
    if sample.size < kept.size:
        # one smoothed assignment of the other tracks, with their nearest
        # subsample tracks as neighbours (stage 6 of gpca, in the full space)
        local = np.searchsorted(kept, sample)
        neighbors = extension_neighbors(unit[kept], local, sample_neighbors)
        residuals, dofs = subspace_residuals(X0[kept], mask[kept], bases, supports)
        scales_from = np.full(kept.size, -1)
        scales_from[local] = sample_labels
        costs = assignment_costs(residuals, dofs, scales_from, per_cluster=False)
        costs += smoothing * neighbor_disagreements(
            refined[kept], neighbors, n_clusters
        )
        others = np.ones(kept.size, dtype=bool)
        others[local] = False
        refined[kept[others]] = np.argmin(costs[others], axis=1)
    return refined, bases, n_iter, converged


def _fit_groups(X0, mask, labels, n_clusters, dim):
    """Subspace of each group on its observed entries; None for a group too
    small to fit."""
    bases, supports = [], []
    for k in range(n_clusters):
        members = np.flatnonzero(labels == k)
        if members.size <= dim:
            bases.append(None)
            supports.append(None)
            continue
        basis, support = fit_observed_subspace(X0[members], mask[members], dim)
        bases.append(basis)
        supports.append(support)
    return bases, supports


def _data_costs(X0, mask, labels, bases, supports, scale=None, typical=None):
    """Data term of the anchored assignment, its scale and typical evidence.

    ``weight_p * rho_pk / s``: ``rho_pk`` the residual per degree of freedom
    of row ``p`` to subspace ``k`` on its observed entries, ``s`` the given
    ``scale`` or, if None, the median of ``rho`` over the rows' own labels,
    and ``weight_p`` the row's number of degrees of freedom over the median
    (:func:`assignment_costs` with one scale), or over ``typical`` if given.
    ``inf`` for the groups without a subspace.
    """
    fitted = [k for k, basis in enumerate(bases) if basis is not None]
    residuals = np.full((X0.shape[0], len(bases)), np.inf)
    dofs = np.zeros((X0.shape[0], len(bases)), dtype=np.intp)
    residuals[:, fitted], dofs[:, fitted] = subspace_residuals(
        X0, mask, [bases[k] for k in fitted], [supports[k] for k in fitted]
    )
    per_dof = np.where(dofs > 0, residuals / np.maximum(dofs, 1), np.inf)
    if scale is None:
        own = per_dof[np.arange(labels.size), np.maximum(labels, 0)]
        usable = np.isfinite(own) & (labels >= 0)
        scale = float(np.median(own[usable])) if usable.any() else 1.0
    scale = max(scale, TINY)
    evidence = dofs.max(axis=1)
    has = evidence > 0
    if typical is None:
        typical = float(np.median(evidence[has])) if has.any() else 1.0
    typical = max(typical, 1.0)
    costs = np.zeros_like(per_dof)
    costs[has] = (evidence[has, None] / typical) * per_dof[has] / scale
    costs[:, [k for k, basis in enumerate(bases) if basis is None]] = np.inf
    return costs, scale, typical


def fit_full_space(
    X0,
    mask,
    labels,
    n_clusters,
    subspace_dim,
    *,
    max_fit_samples=20000,
    n_trim=2,
    trim_fraction=0.2,
    random_state=None,
):
    """The subspaces of :func:`reassign_full_space`, one per group of labels.

    Parameters
    ----------
    X0, mask : ndarray of shape (n_samples, n_features)
        Data zero where missing, and the observed entries.
    labels : ndarray of shape (n_samples,)
        ``0 .. n_clusters - 1``, ``-1`` for rows left out.
    n_clusters : int
    subspace_dim : int
        Dimension of every subspace, less than ``n_features``.
    max_fit_samples, n_trim, trim_fraction, random_state
        As in :func:`reassign_full_space`.

    Returns
    -------
    bases : list of ndarray of shape (n_features, subspace_dim) or None
        None for a group with at most ``subspace_dim`` rows in the subsample.
    supports : list of ndarray of shape (n_features,), dtype=bool, or None
    """
    rng = check_random_state(random_state)
    kept = np.flatnonzero(labels >= 0)
    sample = kept
    if max_fit_samples is not None and kept.size > max_fit_samples:
        sample = np.sort(rng.choice(kept, max_fit_samples, replace=False))
    members = labels[sample]
    for trim in range(1 + n_trim):
        bases, supports = _fit_groups(
            X0[sample], mask[sample], members, n_clusters, subspace_dim
        )
        if trim == n_trim or sum(basis is not None for basis in bases) < 2:
            break
        # refit on the rows whose own label is their nearest subspace: a row
        # of another motion pulls a least-squares fit towards it
        costs, *_ = _data_costs(
            X0[sample], mask[sample], labels[sample], bases, supports
        )
        nearest = np.argmin(costs, axis=1)
        members = np.where(nearest == labels[sample], labels[sample], -1)
        # and without the worst-fitted rows of each group: a few rows of
        # another motion can bend the fit so far towards them (turning its
        # weakest direction) that they become its nearest
        own = costs[np.arange(sample.size), labels[sample]]
        for k in range(n_clusters):
            mine = labels[sample] == k
            if trim_fraction > 0 and mine.any():
                cut = np.quantile(own[mine], 1.0 - trim_fraction)
                members[mine & (own > cut)] = -1
    return bases, supports


def assign_full_space(
    X0, mask, labels, bases, supports, *, anchor=1.0, scale=None, typical=None
):
    """Each row's label minimising ``rho_pk / s + anchor * [k != labels_p]``.

    Parameters
    ----------
    X0, mask : ndarray of shape (n_samples, n_features)
        Data zero where missing, and the observed entries.
    labels : ndarray of shape (n_samples,)
        The anchor labels; ``-1`` rows keep ``-1``.
    bases, supports : list
        From :func:`fit_full_space`. A row whose own label has no subspace
        keeps it; no row takes such a label.
    anchor : float, default=1.0
        Cost of leaving the anchor label, in units of ``s``.
    scale : float or None, default=None
        The typical misfit ``s``; None takes the median of the rows' residual
        per degree of freedom to their own label's subspace.
    typical : float or None, default=None
        The typical number of residual degrees of freedom of a row, by which
        a row's evidence is divided; None takes the median over the rows.

    Returns
    -------
    labels : ndarray of shape (n_samples,), dtype=intp
    scale, typical : float
        The ``s`` and the typical evidence used.
    """
    refined = np.array(labels, dtype=np.intp)
    if sum(basis is not None for basis in bases) < 2:
        return refined, 1.0 if scale is None else scale, typical or 1.0
    kept = np.flatnonzero(labels >= 0)
    costs, scale, typical = _data_costs(
        X0[kept], mask[kept], refined[kept], bases, supports, scale, typical
    )
    costs += anchor * (np.arange(len(bases)) != refined[kept][:, None])
    unfitted = np.array([basis is None for basis in bases])
    moves = ~unfitted[refined[kept]]
    refined[kept[moves]] = np.argmin(costs[moves], axis=1)
    return refined, scale, typical


def reassign_full_space(
    X,
    labels,
    *,
    subspace_dim=4,
    anchor=1.0,
    max_fit_samples=20000,
    n_trim=2,
    trim_fraction=0.2,
    random_state=None,
):
    """One full-space assignment of every track, anchored to a segmentation.

    One ``subspace_dim``-dimensional subspace of :math:`R^{2F}` is fitted to
    the observed entries of each group of ``labels`` (on a uniform subsample
    of at most ``max_fit_samples`` tracks), and every track takes the label
    minimising

    ``rho_pk / s + anchor * [k != labels_p]``

    with ``rho_pk`` its residual to subspace ``k`` per residual degree of
    freedom on its own observed entries, ``s`` the median of ``rho`` over the
    tracks' own labels and the data term weighted by the track's evidence
    (:func:`~sklearn_gpca._refine_observed.assignment_costs` with one scale).
    A track leaves its starting label only when another motion fits it better
    by more than ``anchor`` typical misfits.

    Why one anchored pass, and not K-subspaces to convergence or a smoothing
    term: the starting labels of the default pipeline were smoothed in
    :math:`R^5`, where the motions overlap (three 4-D subspaces in 5
    dimensions), so neighbours found there mix motions exactly where the
    full space could separate them, and a smoothing term over them pins
    their errors. Without the anchor the pass is the nearest fitted subspace,
    no better than the nearest *true* subspace (``oracle_labels``), which the
    smoothed start often beats; repeated rounds of hard assignment drift away
    from the truth (each subspace tilts towards the tracks it wrongly
    takes). ``benchmarks/results/scaling.md`` measures it.

    It is meant for a start whose errors lie near the boundaries between
    motions, as the default pipeline's at scale. From labels with gross
    errors (a tenth of the tracks moved to a random other motion) the
    least-squares subspaces are pulled towards the wrong tracks and the
    anchor keeps many of them: :func:`refine_full_space` iterates instead.

    Parameters
    ----------
    X : ndarray of shape (n_samples, n_features)
        Tracks ``[x_1, y_1, ..., x_F, y_F]``, NaN where missing.
    labels : ndarray of shape (n_samples,)
        Starting segmentation, ``0 .. n_clusters - 1``; ``-1`` marks tracks
        left out (outliers), which keep ``-1``.
    subspace_dim : int, default=4
        Dimension of every motion subspace (4 for a generic rigid motion seen
        by an affine camera), clipped to ``n_features - 1``.
    anchor : float, default=1.0
        Cost of leaving the starting label, in typical misfits (the median
        residual per degree of freedom); 0 is the nearest fitted subspace.
        1.0 was chosen on the ``make_motions`` draws of
        ``benchmarks/bench_scaling.py`` (draw 0 at 10^3 to 10^6 tracks, draws
        1 and 2 at 10^4 to 10^5; ``benchmarks/results/scaling_stages.md``):
        0.5 is better on some of them and worse on others (0.40 -> 0.49 % at
        10^6), 2 gains less.
    max_fit_samples : int or None, default=20000
        Most tracks the subspaces are fitted to (a uniform random subsample);
        None fits all. Every track is assigned.
    n_trim : int, default=2
        Refits of each subspace on only the subsample tracks whose own label
        is their nearest subspace and that are not among the
        ``trim_fraction`` worst fitted of their group (a track of another
        motion pulls a least-squares fit towards it); 0 fits the groups as
        labelled.
    trim_fraction : float in [0, 1), default=0.2
        Share of each group's worst-fitted tracks left out of each refit.
        Without it (and one refit, the earlier default) three tracks of
        another motion among 200 bent a fit by 58 degrees on a
        ``make_motions`` draw of 600 tracks (draw 2: 1.0 -> 8.5 % error);
        0.2 with two refits was chosen on draws 0-5 of 600 tracks (0.1 did
        not fix draw 2) and leaves the 10^5-track draws 0-2 of
        ``benchmarks/results/scaling_stages.md`` within 0.01 point.
    random_state : int, RandomState instance or None, default=None
        Seeds the subsample.

    Returns
    -------
    labels : ndarray of shape (n_samples,), dtype=intp
        The reassigned segmentation.
    bases : list of ndarray of shape (n_features, d) or None
        Orthonormal bases of the fitted subspaces, one per label; None for a
        label with at most ``d`` tracks in the subsample (it keeps its
        tracks and takes no other).

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca.datasets import make_motions
    >>> from sklearn_gpca.metrics import misclassification_rate
    >>> from sklearn_gpca.stages import reassign_full_space
    >>> X, y = make_motions(3, n_points=600, n_frames=10, missing=0.1,
    ...                     random_state=0)
    >>> labels, bases = reassign_full_space(X, y, random_state=0)
    >>> float(misclassification_rate(y, labels)) < 0.01, bases[0].shape
    (True, (20, 4))
    """
    if not anchor >= 0:
        raise ValueError(f"anchor must be a non-negative number, got {anchor!r}.")
    if int(n_trim) != n_trim or n_trim < 0:
        raise ValueError(f"n_trim must be a non-negative integer, got {n_trim!r}.")
    if not 0 <= trim_fraction < 1:
        raise ValueError(f"trim_fraction must be in [0, 1), got {trim_fraction!r}.")
    X = check_array(masked_to_nan(X), dtype=np.float64, ensure_all_finite="allow-nan")
    X0, mask = observed_entries(X)
    n_samples, n_features = X0.shape
    labels = _check_labels(labels, n_samples)
    n_clusters = int(labels.max()) + 1 if labels.size else 0
    if n_clusters == 0:
        return labels, []
    dim = max(min(subspace_dim, n_features - 1), 1)
    bases, supports = fit_full_space(
        X0,
        mask,
        labels,
        n_clusters,
        dim,
        max_fit_samples=max_fit_samples,
        n_trim=n_trim,
        trim_fraction=trim_fraction,
        random_state=random_state,
    )
    refined, *_ = assign_full_space(X0, mask, labels, bases, supports, anchor=anchor)
    return refined, bases
