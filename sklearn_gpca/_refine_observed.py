"""Smoothed K-subspaces in the full trajectory space, on observed entries.

Alternates between fitting one linear subspace of ``R^{2F}`` to each cluster
on its tracks' observed entries (:func:`fit_observed_subspace`) and giving
every track the label that minimises

``data_pk + smoothing * #{neighbours of p labelled otherwise}``

where the data term (:func:`assignment_costs`) is the track's residual to
subspace ``k`` per residual degree of freedom, on the coordinates it
observes, relative to the typical misfit of the cluster (a Gaussian
negative log-likelihood, scale-free) and weighted by the track's evidence
(its number of residual degrees of freedom over the median). With complete
tracks and ``per_cluster=False`` this is the library's smoothed K-subspaces
(``_ksubspaces.refine_ksubspaces``) in ``R^{2F}`` with Euclidean
residuals. A track with no residual degree of freedom in any subspace (too
few observed coordinates) is labelled by its neighbours alone; a track that
observes no coordinate of a subspace's support cannot take that label.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._observed_subspaces import (
    fit_observed_subspace,
    subspace_residuals,
)
from sklearn_gpca._outliers import TEST_DIM, outlier_pvalues
from sklearn_gpca._projective_motion import (
    fit_projective_motion,
    projective_residuals,
)
from sklearn_gpca._rows import TINY

#: Most rounds of outlier test and refinement without the flagged tracks.
OUTLIER_ROUNDS = 3
#: Fewest tracks of the cluster modelled by a perspective camera (else all
#: tracks fit it, as a too small subspace cluster is reseeded).
MIN_PROJECTIVE_TRACKS = 12


def neighbor_disagreements(labels, neighbors, n_clusters, weights=None):
    """``D[p, k]``: weight of the neighbours of ``p`` whose label is not ``k``.

    ``neighbors`` holds ``-1`` for no neighbour; ``weights`` (same shape, in
    ``[0, 1]``) weighs each edge, None counts every neighbour once.
    """
    valid = neighbors >= 0
    w = valid.astype(np.float64) if weights is None else np.where(valid, weights, 0.0)
    neighbor_labels = np.where(valid, labels[np.maximum(neighbors, 0)], -1)
    agree = np.einsum(
        "pj,pjk->pk", w, neighbor_labels[:, :, None] == np.arange(n_clusters)
    )
    return w.sum(axis=1)[:, None] - agree


def assignment_costs(
    residuals, dofs, labels, n_clusters=None, *, per_cluster=True, relative=True
):
    """Scale-free data term of the smoothed assignment.

    With ``rho_pk = r_pk / dof_pk`` the residual per degree of freedom,
    ``s_k`` the median of ``rho`` over the tracks labelled ``k`` (its typical
    misfit: noise, and the bend that perspective gives a deep scene), ``s_0``
    the median over all tracks and ``m_p`` a track's largest number of
    degrees of freedom, the cost of label ``k`` is

    ``m_p (rho_pk / s_k + log(s_k / s_0)) / median(m)``

    the negative log-likelihood of the track's residuals under Gaussian noise
    of variance ``s_k`` per coordinate (up to terms shared by all labels),
    per typical track. A loose motion (large ``s_k``) accepts large
    residuals but pays ``log s_k`` for it, so a tight motion keeps the tracks
    it fits well. ``per_cluster=False`` uses ``s_k = s_0`` for all: plain
    K-subspaces with residuals relative to the typical misfit.

    Parameters
    ----------
    residuals, dofs : ndarray of shape (n_samples, n_clusters)
        From :func:`subspace_residuals`.
    labels : ndarray of shape (n_samples,)
        Current labels, which set ``s_k``; tracks labelled ``-1`` (outliers)
        are left out of the scales.
    n_clusters : int, default=None
        Number of labels (``residuals.shape[1]``).
    per_cluster : bool, default=True
        One scale per cluster, or one for all.
    relative : bool, default=True
        Divide the scales by ``s_0`` inside the logarithm. ``False`` gives
        ``m_p (rho_pk / s_k + log s_k) / median(m)``, whose sums compare
        across labellings of the same tracks (:func:`refinement_objective`).

    Returns
    -------
    costs : ndarray of shape (n_samples, n_clusters)
        ``inf`` where the track has no degree of freedom in a subspace but
        some elsewhere; all zero for a track without any.
    """
    n_samples, n_clusters = residuals.shape
    per_dof = np.where(dofs > 0, residuals / np.maximum(dofs, 1), np.inf)
    evidence = dofs.max(axis=1)
    has = evidence > 0
    own = per_dof[np.arange(n_samples), np.maximum(labels, 0)]
    usable = has & np.isfinite(own) & (labels >= 0)
    overall = float(np.median(own[usable])) if usable.any() else 1.0
    overall = max(overall, TINY)
    scales = np.full(n_clusters, overall)
    if per_cluster:
        for k in range(n_clusters):
            mine = own[usable & (labels == k)]
            if mine.size >= 3:
                scales[k] = max(float(np.median(mine)), TINY)
    weight = evidence / max(float(np.median(evidence[has])) if has.any() else 1.0, 1.0)
    costs = np.zeros_like(per_dof)
    log_scales = np.log(scales / overall) if relative else np.log(scales)
    costs[has] = weight[has, None] * (per_dof[has] / scales + log_scales)
    return costs


def refinement_objective(
    X0,
    mask,
    labels,
    n_clusters,
    *,
    neighbors,
    smoothing=3.0,
    subspace_dim=4,
    neighbor_weights=None,
    per_cluster=True,
):
    """Value of the objective that :func:`refine_observed` descends.

    With one subspace per cluster fitted to its tracks' observed entries
    (:func:`fit_observed_subspace`), ``rho_pk``, ``s_k`` and ``m_p`` as in
    :func:`assignment_costs` and ``D`` the weighted neighbour disagreements
    (:func:`neighbor_disagreements`)::

        sum_p m_p (rho_{p l_p} / s_{l_p} + log s_{l_p}) / median(m)
              + smoothing * sum_p D[p, l_p]

    the negative log-likelihood of the tracks under Gaussian noise of
    variance ``s_k`` per coordinate in motion ``k``, plus the smoothing
    penalty. Unlike the assignment costs, the scales are not divided by the
    overall misfit ``s_0`` (which depends on the labels): the values of two
    segmentations of the same tracks, with the same neighbours, compare
    (lower is better; a change of units shifts every value alike).

    Parameters
    ----------
    X0, mask, labels, n_clusters, neighbors, smoothing, subspace_dim
        As in :func:`refine_observed`; ``labels`` in ``0 .. n_clusters - 1``.
    neighbor_weights, per_cluster
        As in :func:`refine_observed`.

    Returns
    -------
    objective : float
    """
    labels = np.asarray(labels, dtype=np.intp)
    if (
        labels.shape != (X0.shape[0],)
        or not np.isin(labels, np.arange(n_clusters)).all()
    ):
        raise ValueError(
            f"labels must hold one label in 0 .. {n_clusters - 1} per track "
            f"({X0.shape[0]}), got shape {labels.shape}."
        )
    dims = np.broadcast_to(np.asarray(subspace_dim, dtype=np.intp), (n_clusters,))
    bases, supports = [], []
    for k in range(n_clusters):
        members = np.flatnonzero(labels == k)
        if members.size <= dims[k]:
            # an (almost) empty motion costs nothing and explains nothing
            members = np.arange(labels.size)
        basis, support = fit_observed_subspace(X0[members], mask[members], int(dims[k]))
        bases.append(basis)
        supports.append(support)
    residuals, dofs = subspace_residuals(X0, mask, bases, supports)
    costs = assignment_costs(
        residuals, dofs, labels, per_cluster=per_cluster, relative=False
    )
    rows = np.arange(labels.size)
    data = costs[rows, labels]
    total = float(np.sum(data[np.isfinite(data)]))
    if smoothing > 0:
        disagree = neighbor_disagreements(
            labels, neighbors, n_clusters, neighbor_weights
        )
        total += smoothing * float(np.sum(disagree[rows, labels]))
    return total


def misfit_ratios(residuals, dofs, labels):
    """Each track's smallest misfit to a motion, relative to the motion's own.

    With ``rho_pk = r_pk / dof_pk`` the residual per degree of freedom of
    track ``p`` to the subspace of motion ``k`` and ``s_k`` its median over
    the tracks of ``k`` (``labels == k``; outliers ``-1`` left out), returns
    ``min_k rho_pk / s_k``: a distribution-free statistic (the misfit of
    real motions is not Gaussian: perspective bends long tracks more), ``0``
    for a track without any residual degree of freedom (it cannot be
    tested).

    Parameters
    ----------
    residuals, dofs : ndarray of shape (n_samples, n_clusters)
        From :func:`subspace_residuals`.
    labels : ndarray of shape (n_samples,)
        Motion of each track, ``-1`` for a track left out of the medians.

    Returns
    -------
    ratios : ndarray of shape (n_samples,)
    """
    n_clusters = residuals.shape[1]
    testable = dofs > 0
    per_dof = np.where(testable, residuals / np.maximum(dofs, 1), np.nan)
    pooled = per_dof[np.arange(labels.size), np.maximum(labels, 0)]
    pooled = pooled[(labels >= 0) & np.isfinite(pooled)]
    fallback = float(np.median(pooled)) if pooled.size else 1.0
    scales = np.empty(n_clusters)
    for k in range(n_clusters):
        mine = per_dof[labels == k, k]
        mine = mine[np.isfinite(mine)]
        scales[k] = float(np.median(mine)) if mine.size >= 3 else fallback
    ratios = np.where(testable, per_dof / np.maximum(scales, TINY), np.inf)
    ratios = ratios.min(axis=1)
    ratios[~testable.any(axis=1)] = 0.0
    return ratios


def _cluster_residuals(X0, mask, labels, excluded, dims, models, random_state):
    """Residuals of every track to every cluster's model, models refitted.

    ``models[k]`` is the previous fit of cluster ``k`` (None at first): a
    ``(basis, support)`` subspace pair, or a ``("projective", cameras,
    supported)`` triple for the cluster modelled by a perspective camera
    (``dims[k] == 0``). Updates ``models`` in place.
    """
    n_samples = X0.shape[0]
    residuals = np.empty((n_samples, len(dims)))
    dofs = np.empty((n_samples, len(dims)), dtype=np.intp)
    for k, dim in enumerate(dims):
        members = np.flatnonzero((labels == k) & ~excluded)
        if dim == 0:
            if members.size < MIN_PROJECTIVE_TRACKS:
                members = np.flatnonzero(~excluded)
            previous = models[k][1] if models[k] is not None else None
            cameras, supported = fit_projective_motion(
                X0[members], mask[members], cameras=previous
            )
            models[k] = ("projective", cameras, supported)
            residuals[:, k], dofs[:, k] = projective_residuals(
                X0, mask, cameras, supported
            )
            continue
        if members.size <= dim:
            members = random_state.choice(
                n_samples, min(dim + 1, n_samples), replace=False
            )
        init = models[k][0] if models[k] is not None else None
        basis, support = fit_observed_subspace(
            X0[members],
            mask[members],
            int(dim),
            init=init,
            max_iter=5 if init is not None else 30,
        )
        models[k] = (basis, support)
        r, d = subspace_residuals(X0, mask, [basis], [support])
        residuals[:, k], dofs[:, k] = r[:, 0], d[:, 0]
    return residuals, dofs


def _refine(
    X0,
    mask,
    labels,
    n_clusters,
    *,
    neighbors,
    smoothing,
    dims,
    neighbor_weights,
    per_cluster,
    max_iter,
    excluded,
    random_state,
    perspective_cameras=None,
):
    """Smoothed K-subspaces; ``excluded`` tracks are labelled but fit nothing.

    A cluster of dimension 0 in ``dims`` is modelled by a perspective camera,
    fitted in the first round from ``perspective_cameras`` (None: from
    scratch).
    """
    labels = np.asarray(labels, dtype=np.intp).copy()
    models = [None] * n_clusters
    if perspective_cameras is not None:
        for k in np.flatnonzero(dims == 0):
            models[k] = ("projective", perspective_cameras, None)
    previous = None
    converged = False
    n_iter = 0
    while n_iter < max_iter:
        n_iter += 1
        residuals, dofs = _cluster_residuals(
            X0, mask, labels, excluded, dims, models, random_state
        )
        marked = np.where(excluded, -1, labels)
        costs = assignment_costs(residuals, dofs, marked, per_cluster=per_cluster)
        if smoothing > 0:
            costs = costs + smoothing * neighbor_disagreements(
                labels, neighbors, n_clusters, neighbor_weights
            )
        new_labels = np.argmin(costs, axis=1).astype(np.intp)
        if np.array_equal(new_labels, labels) or np.array_equal(new_labels, previous):
            converged = True
            break
        previous, labels = labels, new_labels
    perspective = [isinstance(m[0], str) for m in models]
    bases = [m[1] if p else m[0] for m, p in zip(models, perspective, strict=True)]
    supports = [m[2] if p else m[1] for m, p in zip(models, perspective, strict=True)]
    return labels, bases, supports, n_iter, converged


def refine_observed(
    X0,
    mask,
    labels,
    n_clusters,
    *,
    neighbors,
    smoothing=3.0,
    subspace_dim=4,
    neighbor_weights=None,
    per_cluster=True,
    max_iter=30,
    outlier_threshold=None,
    perspective_cluster=None,
    perspective_cameras=None,
    random_state,
):
    """Smoothed K-subspaces on observed entries, from initial labels.

    Parameters
    ----------
    X0 : ndarray of shape (n_samples, n_features)
        Tracks, zero where missing.
    mask : ndarray of shape (n_samples, n_features), dtype=bool
        Observed entries.
    labels : ndarray of shape (n_samples,)
        Initial labels in ``0 .. n_clusters - 1``.
    n_clusters : int
        Number of motions.
    neighbors : ndarray of shape (n_samples, n_neighbors)
        Neighbours of each track (``-1`` for none), e.g. from
        :func:`sklearn_gpca._track_neighbors.track_neighbors`.
    smoothing : float, default=3.0
        Cost of one disagreeing neighbour, in units of the typical misfit of a
        track to its own subspace.
    neighbor_weights : ndarray of shape (n_samples, n_neighbors), default=None
        Weight in ``[0, 1]`` of each neighbour in the smoothing term (e.g.
        how alike the two tracks move); None weighs all 1.
    subspace_dim : int or sequence of int, default=4
        Dimension of every subspace, or one per cluster.
    per_cluster : bool, default=True
        One misfit scale per cluster in the data term (see
        :func:`assignment_costs`).
    max_iter : int, default=30
        Maximum number of fit / assign rounds of each refinement.
    outlier_threshold : float in (0, 1) or None, default=None
        False-alarm probability of the outlier test
        (:func:`sklearn_gpca._outliers.outlier_pvalues`): after the
        refinement, the tracks whose p-value is below it are labelled ``-1``
        and the refinement is run again from its labels with them left out
        of the subspace fits and the scales, until the flagged set settles
        (at most ``OUTLIER_ROUNDS`` times). None labels every track with a
        motion.
    perspective_cluster : int or None, default=None
        Cluster modelled by a perspective camera instead of a subspace
        (:mod:`sklearn_gpca._projective_motion`; typically the background:
        the largest cluster of ``labels``). Its residuals are reprojection
        errors with ``2 m - 4`` degrees of freedom for a track seen in ``m``
        frames, as for a 4-D subspace. Its entries of the returned ``bases``
        and ``supports`` are the cameras ``(n_frames, 3, 4)`` and the
        supported frames.
    perspective_cameras : ndarray of shape (n_frames, 3, 4), default=None
        Start of the perspective cluster's cameras in the first round (a few
        alternations from them, :func:`fit_projective_motion`'s ``cameras``);
        None fits them from scratch, frame by frame.
    random_state : RandomState instance
        Reseeds a cluster too small to fit its subspace.

    Returns
    -------
    labels : ndarray of shape (n_samples,), dtype=intp
        ``-1`` for the outliers (only with ``outlier_threshold``).
    bases : list of ndarray of shape (n_features, d_k)
    supports : list of ndarray of shape (n_features,), dtype=bool
    n_iter : int
        Rounds of all the refinements.
    converged : bool
        Whether the labels of the last refinement settled (or alternated
        between two labellings).
    """
    dims = np.array(
        np.broadcast_to(np.asarray(subspace_dim, dtype=np.intp), (n_clusters,))
    )
    if perspective_cluster is not None:
        dims[perspective_cluster] = 0
    excluded = np.zeros(X0.shape[0], dtype=bool)
    kwargs = dict(
        neighbors=neighbors,
        smoothing=smoothing,
        dims=dims,
        neighbor_weights=neighbor_weights,
        per_cluster=per_cluster,
        max_iter=max_iter,
        random_state=random_state,
        perspective_cameras=perspective_cameras,
    )
    labels, bases, supports, n_iter, converged = _refine(
        X0, mask, labels, n_clusters, excluded=excluded, **kwargs
    )
    if outlier_threshold is None:
        return labels, bases, supports, n_iter, converged
    test_dim = max(TEST_DIM, int(dims.max()))
    for _ in range(OUTLIER_ROUNDS):
        marked = np.where(excluded, -1, labels)
        pvalues = outlier_pvalues(
            X0,
            mask,
            marked,
            n_clusters,
            dim=test_dim,
            min_dim=int(dims[dims > 0].min(initial=test_dim)),
        )
        flagged = pvalues < outlier_threshold
        if np.array_equal(flagged, excluded):
            break
        excluded = flagged
        labels, bases, supports, rounds, converged = _refine(
            X0, mask, labels, n_clusters, excluded=excluded, **kwargs
        )
        n_iter += rounds
    return np.where(excluded, -1, labels), bases, supports, n_iter, converged
