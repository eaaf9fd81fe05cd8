"""Choosing one segmentation among the (refined) candidates.

Two measures of a candidate labelling ``l`` of unit points ``x_i``:

- its *residual*, ``sum_i sin^2(x_i, S_{l_i})``, the squared sine distances of
  the points to the subspaces fitted to their clusters: how well the
  candidate's subspaces fit;
- its *normalised cut* ``sum_k cut(C_k, rest) / vol(C_k)`` on the kNN graph
  weighted by the polynomial's gradients (the paper's normals): how well the
  clusters separate on an affinity the candidates were not all built from.

The cut picks the segmentation; the residual is a gate. The kNN graph sees
only neighbourhoods; with randomized voting (:mod:`sklearn_gpca._voting`)
the normalised cut on the vote graph, whose edges join points that many
K-subspaces runs put together anywhere on the sphere, is added to it: a
candidate merging two subspaces that the kNN graph barely separates cuts
through many votes. The vote cut is weighted (by default) by the vote graph's
confidence (:func:`~sklearn_gpca._voting.vote_confidence`): when the runs
split the points each their own way, no labelling cuts the vote graph much
below chance, and the small differences between the candidates' vote cuts
are weak evidence against a candidate the kNN graph separates cleanly. A
candidate whose
subspaces fit ``fit_gate`` times worse than the best one has merged two
subspaces (and split another): it is not ``n`` subspaces, whatever its cut.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._affinity import normalized_cut
from sklearn_gpca._subspaces import fit_subspaces, residual_energy

# init="multi" drops the candidates whose subspaces fit the points (sum of
# squared sine distances) more than this many times worse than the best one.
FIT_GATE = 3.0


def candidate_residuals(unit, candidates, n_clusters, subspace_dim, subspace_dim_tol):
    """Residual of each candidate: squared sine distances to its own subspaces.

    Parameters
    ----------
    unit : ndarray of shape (n_samples, n_features)
        Unit points.
    candidates : list of ndarray of shape (n_samples,)
        Labellings in ``0 .. n_clusters - 1``.
    n_clusters : int
        Number of clusters.
    subspace_dim, subspace_dim_tol
        Dimension of the fitted subspaces (see
        :func:`~sklearn_gpca._subspaces.fit_subspace`).

    Returns
    -------
    residuals : ndarray of shape (n_candidates,)
    """
    residuals = []
    for labels in candidates:
        bases, _ = fit_subspaces(
            unit, labels, n_clusters, subspace_dim, subspace_dim_tol
        )
        residuals.append(residual_energy(unit, labels, bases))
    return np.array(residuals)


def select_candidate(
    unit,
    candidates,
    n_clusters,
    *,
    graph,
    subspace_dim,
    subspace_dim_tol,
    fit_gate=FIT_GATE,
    vote_cuts=None,
    vote_weight=1.0,
):
    """The candidate with the smallest normalised cut among those that fit.

    Parameters
    ----------
    unit, candidates, n_clusters
        As in :func:`candidate_residuals`.
    graph : scipy.sparse matrix of shape (n_samples, n_samples) or None
        Affinity on which the cuts are measured; None (possible with one
        candidate only) gives NaN cuts.
    subspace_dim, subspace_dim_tol
        As in :func:`candidate_residuals`.
    fit_gate : float, default=3.0
        Candidates whose residual exceeds ``fit_gate`` times the smallest are
        not considered.
    vote_cuts : ndarray of shape (n_candidates,) or None, default=None
        Normalised cut of each candidate on a second affinity, e.g. the vote
        graph of :mod:`sklearn_gpca._voting`; when given, the kept candidate
        minimises ``cuts + vote_weight * vote_cuts`` (among those that fit).
    vote_weight : float, default=1.0
        Weight of ``vote_cuts``, in [0, 1]: the confidence of their graph
        (:func:`~sklearn_gpca._voting.vote_confidence`).

    Returns
    -------
    chosen : int
        Index of the kept candidate.
    cuts : ndarray of shape (n_candidates,)
        Normalised cut of each candidate, between 0 and ``n_clusters``, lower
        is better; ``inf`` for a candidate with an empty cluster.
    residuals : ndarray of shape (n_candidates,)
        Residual of each candidate, lower is better.

    Examples
    --------
    >>> import numpy as np
    >>> import scipy.sparse as sp
    >>> from sklearn_gpca._selection import select_candidate
    >>> unit = np.repeat(np.eye(3)[:2], 3, axis=0)
    >>> graph = sp.csr_matrix(np.kron(np.eye(2), np.ones((3, 3))))
    >>> good, bad = np.repeat([0, 1], 3), np.array([0, 1, 0, 1, 0, 1])
    >>> chosen, cuts, residuals = select_candidate(
    ...     unit, [bad, good], 2, graph=graph, subspace_dim=1, subspace_dim_tol=0.0)
    >>> chosen, cuts.round(2).tolist(), residuals.round(2).tolist()
    (1, [0.89, 0.0], [2.0, 0.0])
    """
    residuals = candidate_residuals(
        unit, candidates, n_clusters, subspace_dim, subspace_dim_tol
    )
    if graph is None:
        return 0, np.full(len(candidates), np.nan), residuals
    cuts = np.array([normalized_cut(graph, c, n_clusters) for c in candidates])
    score = cuts
    if vote_cuts is not None:
        vote_cuts = np.asarray(vote_cuts, dtype=float)
        if vote_cuts.shape != cuts.shape:
            raise ValueError(
                f"vote_cuts has shape {vote_cuts.shape}, expected one value per "
                f"candidate: {cuts.shape}."
            )
        if not (np.isfinite(vote_weight) and 0.0 <= vote_weight <= 1.0):
            raise ValueError(
                f"vote_weight={vote_weight!r} must be a number in [0, 1]: the "
                "confidence of the vote graph (vote_confidence)."
            )
        score = cuts + vote_weight * vote_cuts
    admissible = residuals <= fit_gate * residuals.min()
    chosen = int(np.argmin(np.where(admissible, score, np.inf)))
    return chosen, cuts, residuals
