"""Motion segmentation under a perspective camera: votes for two-view and
subspace hypotheses, fused and clustered spectrally."""

# SPDX-License-Identifier: BSD-3-Clause

import warnings
from functools import partial
from numbers import Integral, Real

import numpy as np
from scipy import sparse
from scipy.cluster.hierarchy import cut_tree, linkage
from scipy.spatial.distance import squareform
from sklearn.base import BaseEstimator, ClusterMixin, _fit_context
from sklearn.utils import check_random_state
from sklearn.utils._param_validation import Interval, StrOptions
from sklearn.utils.extmath import randomized_svd
from sklearn.utils.validation import validate_data

from sklearn_gpca._empty_motions import warn_empty_motions
from sklearn_gpca._magnitude import in_safe_range
from sklearn_gpca._missing import describe_indices, masked_to_nan
from sklearn_gpca._rows import TINY, unit_rows
from sklearn_gpca._short_tracks import label_from_neighbors
from sklearn_gpca._spectral import embedding_kmeans
from sklearn_gpca._validation import Count
from sklearn_gpca._view_hypotheses import (
    SUBSPACE_RANK,
    observed_frames,
    preference_votes,
)

#: Models :class:`PerspectiveClustering` can fuse.
MODELS = ("fundamental", "homography", "subspace")

#: Rules that merge the segments down to ``n_clusters``.
MERGES = ("association", "average")

#: How the kernel is partitioned: one spectral clustering, or the best fit
#: among several (see :func:`best_fit_partition`).
PARTITIONS = ("spectral", "best_fit")

#: Multiples of ``n_clusters`` the kernel is cut into before merging, for
#: ``partition="best_fit"``.
SEGMENT_MULTIPLES = (2, 3)


def _column_sums(votes):
    return np.asarray(votes.sum(axis=0)).ravel()


def fused_votes(
    X,
    models,
    *,
    n_hypotheses,
    top,
    gaps,
    window,
    n_neighbors,
    rng,
    preferences=None,
    seed_weights=None,
):
    """Every model's votes side by side, as one factor of the fused kernel.

    Each hypothesis (column) is divided by the square root of its number of
    voters, the hyperedge normalisation of hypergraph spectral clustering
    (Zhou, Huang & Schoelkopf, NIPS 2006): a background hypothesis that every
    background track votes for links each pair of them less than an object
    hypothesis links its few voters, so the dominant motion does not absorb
    the others. Each model's block is then scaled to the same mean degree, so
    that in the fused kernel ``sum_m w_m^2 V_m V_m^T`` every model weighs the
    same (the kernel addition of Xu, Cheong & Li, CVPR 2018, without their
    co-regularisation). ``preferences`` and ``seed_weights`` guide the
    samples (see :func:`~sklearn_gpca._view_hypotheses.preference_votes`).

    Returns
    -------
    votes : scipy.sparse.csr_array of shape (n_samples, n_columns)
        The factor ``Phi`` of the fused kernel ``Phi Phi^T``. Models without
        any hypothesis are left out.
    """
    blocks = []
    for model in models:
        votes, _ = preference_votes(
            X,
            model,
            n_hypotheses=n_hypotheses,
            top=top,
            gaps=gaps,
            window=window,
            n_neighbors=n_neighbors,
            random_state=rng,
            preferences=preferences,
            seed_weights=seed_weights,
        )
        voters = _column_sums(votes)
        votes = votes.multiply(1.0 / np.sqrt(np.maximum(voters, 1.0))[None, :])
        column_sums = _column_sums(votes)
        mean_degree = column_sums @ column_sums / X.shape[0]
        if mean_degree > 0:
            blocks.append(votes.tocsr() / np.sqrt(mean_degree))
    if not blocks:
        return sparse.csr_array((X.shape[0], 0))
    return sparse.hstack(blocks, format="csr")


def kernel_degrees(votes):
    """Degrees ``K 1 = Phi (Phi^T 1)`` of the kernel ``K = Phi Phi^T``."""
    return votes @ _column_sums(votes)


def spectral_embedding_votes(votes, n_components, random_state):
    """Ng-Jordan-Weiss embedding of the kernel ``votes @ votes.T``, never formed.

    The leading eigenvectors of ``D^{-1/2} K D^{-1/2}`` are the leading left
    singular vectors of ``D^{-1/2} votes`` (randomized SVD on the sparse
    matrix): time linear in the number of tracks. Rows are scaled to unit
    norm. A track without degree has a zero row in ``D^{-1/2} votes``, hence
    in the singular vectors, and keeps it.
    """
    degrees = kernel_degrees(votes)
    scaled = votes.multiply(1.0 / np.sqrt(np.maximum(degrees, TINY))[:, None])
    left, _, _ = randomized_svd(
        scaled.tocsr(),
        n_components,
        n_oversamples=20,
        n_iter=10,
        random_state=random_state,
    )
    return unit_rows(left)


def _indicator(labels, n_clusters):
    Y = np.zeros((labels.shape[0], n_clusters))
    Y[np.arange(labels.shape[0]), labels] = 1.0
    return Y


def refine_normalized_cut(votes, labels, n_clusters, max_iter):
    """Weighted kernel k-means on ``K = votes @ votes.T``: lowers the ncut.

    With weights ``d`` (the degrees) and kernel ``D^{-1} K D^{-1}``, kernel
    k-means decreases the normalised cut at every step (Dhillon, Guan &
    Kulis, KDD 2004): track ``i`` moves to the cluster ``c`` minimising
    ``-2 (K Y)_ic / (d_i s_c) + (Y^T K Y)_cc / s_c^2`` with ``s_c`` the
    cluster's volume. ``K Y = Phi (Phi^T Y)``: linear in the number of tracks.

    Returns
    -------
    labels : ndarray of shape (n_samples,), dtype=intp
    n_iter : int
        Rounds run; stops when no label changes.
    """
    degrees = np.maximum(kernel_degrees(votes), TINY)
    labels = np.asarray(labels, dtype=np.intp)
    n_iter = 0
    while n_iter < max_iter:
        n_iter += 1
        Y = _indicator(labels, n_clusters)
        KY = votes @ (votes.T @ Y)
        volumes = degrees @ Y
        within = np.einsum("pc,pc->c", Y, KY)
        safe = np.maximum(volumes, TINY)
        cost = -2.0 * (KY / degrees[:, None]) / safe + within / safe / safe
        # An emptied cluster stays empty: spectral clustering chose n_clusters.
        cost[:, volumes <= 0] = np.inf
        new = np.argmin(cost, axis=1).astype(np.intp)
        if np.array_equal(new, labels):
            break
        labels = new
    return labels, n_iter


def _segment_weights(votes, labels):
    """``W_AB = 1_A^T K 1_B`` between the segments of ``labels`` (0 .. k-1)."""
    Z = votes.T @ _indicator(labels, labels.max() + 1)
    return np.asarray(Z.T @ Z)


def merge_segments(votes, labels, n_clusters, rule="association"):
    """Merge segments of the kernel ``K = votes @ votes.T`` down to ``n_clusters``.

    Greedy agglomeration: the two segments ``A``, ``B`` with the largest
    normalised association ``W_AB / sqrt(vol_A vol_B)`` merge first, where
    ``W_AB = 1_A^T K 1_B`` and ``vol_A = 1_A^T K 1`` (the edge weight of the
    normalised kernel ``D^{-1/2} K D^{-1/2}`` between the segments taken as
    nodes). Pieces of one motion cut apart by the spectral step (a dominant
    background seen through local hypotheses) share many hypotheses, so
    they merge before two motions do. The association is recomputed after
    every merge, so a growing segment gathers the pieces of a dominant
    background, and also a small motion that borders it.

    With ``rule="average"``, average linkage (UPGMA) of the segments'
    pairwise normalised associations instead: two groups merge when the
    mean association of their original segments is the highest. A group's
    growth does not raise its pull, so small motions stay apart from the
    background, but a background whose pieces share few hypotheses may stay
    cut (``benchmarks/results/perspective_merges.md`` measures both).

    Parameters
    ----------
    votes : sparse array of shape (n_samples, n_columns)
        Factor of the kernel.
    labels : ndarray of shape (n_samples,)
        Segments ``0 .. n_segments - 1``, each non-empty.
    n_clusters : int
        Number of clusters to reach, at most the number of segments.
    rule : {"association", "average"}, default="association"
        Greedy normalised association, recomputed after every merge, or
        average linkage of the segments' normalised associations.

    Returns
    -------
    labels : ndarray of shape (n_samples,), dtype=intp
        Clusters ``0 .. n_clusters - 1``.
    """
    labels = np.unique(labels, return_inverse=True)[1].astype(np.intp)
    n_segments = labels.max() + 1
    weights = _segment_weights(votes, labels)
    volumes = weights.sum(axis=1)
    if rule == "average":
        if n_segments == n_clusters:
            return labels
        association = weights / np.sqrt(np.maximum(np.outer(volumes, volumes), TINY))
        distance = association.max() - association
        np.fill_diagonal(distance, 0.0)
        tree = linkage(squareform(distance, checks=False), method="average")
        merged = cut_tree(tree, n_clusters=n_clusters).ravel()
        return merged[labels].astype(np.intp)
    alive = np.ones(n_segments, dtype=bool)
    merged_into = np.arange(n_segments)
    for _ in range(n_segments - n_clusters):
        scale = np.sqrt(np.maximum(np.outer(volumes, volumes), TINY))
        association = weights / scale
        np.fill_diagonal(association, -np.inf)
        association[~alive] = association[:, ~alive] = -np.inf
        i, j = np.unravel_index(np.argmax(association), association.shape)
        weights[i] += weights[j]
        weights[:, i] += weights[:, j]
        volumes[i] += volumes[j]
        alive[j] = False
        merged_into[merged_into == j] = i
    return np.unique(merged_into[labels], return_inverse=True)[1].astype(np.intp)


def normalized_cut_votes(votes, labels, n_clusters):
    """Normalised cut ``sum_c cut(c) / vol(c)`` of a labelling on ``K``."""
    Z = votes.T @ _indicator(labels, n_clusters)
    weights = Z.T @ Z
    volumes = weights.sum(axis=1)
    if np.any(volumes <= 0):
        return np.inf
    return float(np.sum((volumes - np.diag(weights)) / volumes))


def window_moments(X, window):
    """Coordinates of the tracks on every window of consecutive frames.

    Returns
    -------
    coords : ndarray of shape (n_windows, n_samples, 2 * window)
        The coordinates of each track on each window of ``window``
        consecutive frames, zero where the track is not observed on all of
        them (it then adds nothing to a moment matrix). Memory ``2 window``
        times that of ``X``.
    """
    observed = observed_frames(X)
    n_frames = observed.shape[1]
    starts = np.arange(n_frames - window + 1)
    frames = starts[:, None] + np.arange(window)
    seen = np.all(observed[:, frames], axis=2).T
    columns = np.stack([2 * frames, 2 * frames + 1], axis=2).reshape(len(starts), -1)
    coords = np.nan_to_num(np.swapaxes(X[:, columns], 0, 1))
    return coords * seen[:, :, None]


def windowed_fit_residual(coords, labels, n_clusters):
    """Residual of each cluster's best rank-4 subspace on every window, summed.

    On a window of a few consecutive frames a rigid motion is close to the
    rank-4 subspace of the affine camera even under strong perspective (the
    windowed subspace hypotheses rely on it). For each window and cluster,
    the squared distance of the cluster's tracks observed on the whole
    window to their best rank-4 subspace is the sum of the eigenvalues of
    their second-moment matrix beyond the 4th (Eckart-Young); the sum over
    windows and clusters measures how well a labelling fits the model.

    Parameters
    ----------
    coords : ndarray of shape (n_windows, n_samples, 2 * window)
        From :func:`window_moments`.
    labels : ndarray of shape (n_samples,)
        Clusters ``0 .. n_clusters - 1``.
    n_clusters : int

    Returns
    -------
    residual : float
    """
    residual = 0.0
    for cluster in range(n_clusters):
        part = coords[:, labels == cluster]
        moments = np.einsum("vpi,vpj->vij", part, part)
        eigenvalues = np.linalg.eigvalsh(moments)
        residual += eigenvalues[:, :-SUBSPACE_RANK].clip(min=0.0).sum()
    return float(residual)


def best_fit_partition(votes, coords, n_clusters, *, n_init, max_iter, rng):
    """The partition of the kernel whose clusters fit windowed subspaces best.

    Candidates, all with ``n_clusters`` clusters and refined by kernel
    k-means: the spectral clustering of the kernel into ``n_clusters``; and
    for ``m`` in :data:`SEGMENT_MULTIPLES`, into ``m n_clusters`` segments
    merged back by greedy association and by average linkage
    (:func:`merge_segments`). The normalised cut cannot choose among them:
    with a dominant background it is lower for a background cut in pieces
    than for the true motions. Each candidate is scored instead by the
    model (:func:`windowed_fit_residual`): two motions in one cluster leave
    a large residual, whereas a cut background lowers it less.

    Returns
    -------
    labels : ndarray of shape (n_samples,), dtype=intp
    n_iter : int
        Refinement rounds of the chosen candidate.
    """
    candidates = [
        _cluster_votes(
            votes,
            n_clusters=n_clusters,
            n_segments=None,
            merge="association",
            n_init=n_init,
            max_iter=max_iter,
            rng=rng,
        )
    ]
    for multiple in SEGMENT_MULTIPLES:
        n_segments = multiple * n_clusters
        if n_segments > votes.shape[0]:
            break
        embedding = spectral_embedding_votes(votes, n_segments, rng)
        segments = embedding_kmeans(
            embedding, n_segments, n_init=n_init, random_state=rng
        )
        segments, _ = refine_normalized_cut(votes, segments, n_segments, max_iter)
        for rule in MERGES:
            merged = merge_segments(votes, segments, n_clusters, rule=rule)
            candidates.append(
                refine_normalized_cut(votes, merged, n_clusters, max_iter)
            )
    residuals = [
        windowed_fit_residual(coords, labels, n_clusters) for labels, _ in candidates
    ]
    return candidates[int(np.argmin(residuals))]


def perspective_clustering(
    X,
    n_clusters,
    *,
    models=MODELS,
    n_hypotheses=100,
    top=0.05,
    gaps=(1, 2, 4, 8),
    window=4,
    n_neighbors=10,
    max_iter=30,
    n_init=10,
    n_rounds=1,
    n_segments=None,
    merge="association",
    partition="spectral",
    random_state=None,
):
    """Segment tracks by their votes for perspective and affine hypotheses.

    The function behind :class:`PerspectiveClustering`, which documents the
    parameters; ``X`` must be validated already (float, NaN where missing).

    Returns
    -------
    labels : ndarray of shape (n_samples,), dtype=intp
        Labels in ``0 .. n_clusters - 1``.
    votes : scipy.sparse.csr_array of shape (n_samples, n_columns)
        The factor of the fused kernel.
    n_iter : int
        Rounds of the kernel k-means refinement.
    """
    X, _ = in_safe_range(X)
    rng = check_random_state(random_state)
    kwargs = dict(
        n_hypotheses=n_hypotheses,
        top=top,
        gaps=gaps,
        window=window,
        n_neighbors=n_neighbors,
        rng=rng,
    )
    votes = fused_votes(X, models, **kwargs)
    if votes.shape[1] == 0:
        raise ValueError(
            "No frame pair or window has more co-visible tracks than a "
            "minimal sample (4 for homographies and subspaces, 8 for "
            "fundamental matrices): there is nothing to vote for."
        )
    if n_clusters == 1:
        return np.zeros(X.shape[0], dtype=np.intp), votes, 0
    if partition == "best_fit":
        cluster = partial(
            best_fit_partition,
            coords=window_moments(X, window),
            n_clusters=n_clusters,
            n_init=n_init,
            max_iter=max_iter,
            rng=rng,
        )
    else:
        cluster = partial(
            _cluster_votes,
            n_clusters=n_clusters,
            n_segments=n_segments,
            merge=merge,
            n_init=n_init,
            max_iter=max_iter,
            rng=rng,
        )
    labels, n_iter = cluster(votes)
    for _ in range(n_rounds - 1):
        # Balanced guided sampling: every cluster of the last round seeds
        # about as many hypotheses, each sample drawn among tracks that
        # voted alike (see sklearn_gpca._view_hypotheses).
        sizes = np.bincount(labels, minlength=n_clusters)
        votes = fused_votes(
            X,
            models,
            preferences=votes,
            seed_weights=1.0 / sizes[labels],
            **kwargs,
        )
        labels, n_iter = cluster(votes)
    return labels, votes, n_iter


def _cluster_votes(votes, *, n_clusters, n_segments, merge, n_init, max_iter, rng):
    """Spectral clustering of ``votes @ votes.T``, refined by kernel k-means;
    with ``n_segments``, into that many segments first, merged and refined."""
    n_segments = n_clusters if n_segments is None else n_segments
    embedding = spectral_embedding_votes(votes, n_segments, rng)
    labels = embedding_kmeans(embedding, n_segments, n_init=n_init, random_state=rng)
    if n_segments > n_clusters:
        labels, _ = refine_normalized_cut(votes, labels, n_segments, max_iter)
        labels = merge_segments(votes, labels, n_clusters, rule=merge)
    return refine_normalized_cut(votes, labels, n_clusters, max_iter)


class PerspectiveClustering(ClusterMixin, BaseEstimator):
    """Segment tracks seen by a perspective camera, with missing entries.

    Rigid motions seen by a pinhole camera with strong perspective (a short
    focal length, a large depth range, forward motion) are not the rank-4
    subspaces of the affine model over a whole sequence. This clusterer uses
    models that hold under perspective, or hold locally in time:

    - fundamental matrices (any rigid motion) and homographies (planar
      surfaces, rotations) between the frames ``f`` and ``f + g``;
    - rank-4 subspaces of the tracks on windows of a few consecutive frames,
      where the affine model is still close.

    Each model is estimated on ``n_hypotheses`` random local samples per
    frame pair or window, drawn among the tracks observed there, and each
    track observed there votes for the ``top`` share of the hypotheses with
    the smallest residuals (the ordered residual kernel). The votes of all
    models, normalised so that neither the dominant motion nor any one model
    outweighs the others, define a kernel ``K = Phi Phi^T`` between tracks,
    which is clustered spectrally (Ng, Jordan & Weiss) and refined by
    weighted kernel k-means, which lowers its normalised cut. ``K`` is never
    formed: time and memory are linear in the number of tracks for a bounded
    number of hypotheses.

    Parameters
    ----------
    n_clusters : int, default=2
        Number of motions.
    models : tuple of {"fundamental", "homography", "subspace"}, \
            default=("fundamental", "homography", "subspace")
        Models whose votes are fused (at least one, no repeats).
    n_hypotheses : int, default=100
        Hypotheses drawn per model on each frame pair (two-view models) or
        window (subspace model).
    top : float in (0, 1], default=0.05
        Share of a view's hypotheses each track observed there votes for.
    gaps : tuple of int, default=(1, 2, 4, 8)
        Frame gaps ``g`` of the pairs ``(f, f + g)`` of the two-view models.
        Wider gaps see more perspective; gap 1 lets tracks seen in two frames
        vote.
    window : int, default=4
        Consecutive frames per window of the subspace model (at least 3: a
        rank-4 subspace needs more than 4 coordinates).
    n_neighbors : int, default=10
        Locality of the samples: a random seed track and the others drawn
        among its ``n_neighbors`` nearest co-visible tracks in the image.
    max_iter : int, default=30
        Maximum rounds of the kernel k-means refinement (0: none).
    n_init : int, default=10
        Number of k-means runs on the spectral embedding.
    n_rounds : int, default=1
        Rounds of hypotheses. After the first, the votes are drawn again
        with guided samples: each seed's partners are drawn among the
        co-visible tracks that voted most like it (rather than the nearest
        in the image), and the seeds are drawn in inverse proportion to the
        size of their cluster in the last round, so that small motions get
        as many hypotheses as a dominant background. Each round costs about
        as much as the first. See Notes for when it helps.
    n_segments : int or None, default=None
        If larger than ``n_clusters``, the kernel is first clustered into
        ``n_segments`` segments, which are merged down to ``n_clusters``
        (see ``merge``) before the refinement. The normalised cut prefers to
        cut a dominant background into pieces rather than to separate small
        motions; the pieces share many hypotheses and merge back. None: no
        merging. See Notes for when it helps.
    merge : {"association", "average"}, default="association"
        How the ``n_segments`` segments are merged: "association" greedily,
        the pair sharing the most votes relative to their degrees first,
        recomputed after every merge (a growing segment gathers the pieces of
        a dominant background, and sometimes a small motion beside it);
        "average" by average linkage of the segments' pairwise normalised
        associations (small motions stay apart, but a background whose
        pieces share few votes may stay cut). Unused without ``n_segments``
        and with ``partition="best_fit"``.
    partition : {"spectral", "best_fit"}, default="spectral"
        "spectral": one spectral clustering of the kernel (with
        ``n_segments``, merged). "best_fit": several partitions of the kernel
        (``n_clusters``, ``2 n_clusters`` and ``3 n_clusters`` segments, the
        latter merged by both ``merge`` rules), each refined, and the one
        whose clusters are closest to rank-4 subspaces on windows of
        ``window`` frames kept (the smallest residual; see Notes). Five
        clusterings instead of one: about twice the time of "spectral".
        Requires ``n_segments=None``.
    random_state : int, RandomState instance or None, default=None
        Seeds the samples, the randomized SVD and k-means.

    Attributes
    ----------
    labels_ : ndarray of shape (n_samples,), dtype=intp
        Motion of each track, in ``0 .. n_clusters - 1``.
    n_hypotheses_ : int
        Number of hypotheses (columns of the fused votes) over all models
        and views.
    n_iter_ : int
        Rounds of the kernel k-means refinement run.
    n_features_in_ : int
        ``2 F`` for ``F`` frames.

    Warns
    -----
    UserWarning
        When some of the ``n_clusters`` labels are not used (e.g. identical
        tracks); the labels are returned as found, as
        :class:`~sklearn.cluster.KMeans` does. When some tracks are seen
        only where too few tracks are co-visible to draw hypotheses. When
        some tracks are seen in one frame where no longer track is seen
        (they take the most common label).

    See Also
    --------
    GPCAClustering : The affine route, after PowerFactorization.
    sklearn.cluster.SpectralClustering : Spectral clustering of a given
        affinity.

    Notes
    -----
    A frame counts as observed for a track when both its coordinates are
    finite. Fundamental matrices come from the normalised 8-point algorithm,
    homographies from the normalised 4-point DLT, both with Sampson distances
    as residuals (Hartley & Zisserman, *Multiple View Geometry*, 2nd ed.,
    algorithms 4.2 and 11.1); the subspace residual is a track's distance to
    the span of 4 tracks per residual degree of freedom. Scores are ranks, so
    no noise scale is needed. A track gets no vote in a view with no more
    co-visible tracks than a minimal sample; a track with no vote at all is
    labelled by the refinement alone (with a warning). The settings were
    chosen on ``make_tracks(scene="driving")`` draws; see
    ``benchmarks/bench_perspective.py`` for what was tuned and the results.
    With ``F`` frames, ``P`` tracks and ``G`` gaps, the cost is
    ``O((G + 1) F n_hypotheses P)`` for the votes and ``O(P H)`` per
    refinement round for ``H`` hypotheses.

    A dominant background (two thirds of the tracks, as in driving footage)
    with several small objects defeats the normalised cut: measured against
    the truth, it is lower when the background is cut in pieces and small
    objects are merged with each other than for the true segmentation, which
    the refinement started from the truth keeps. ``n_segments`` (merging the
    pieces back) and ``n_rounds`` (purer hypotheses for small objects) are
    for that case. Cut in ``2 n_clusters`` segments, the motions are nearly
    separated (the best merge of the segments would err 5 % on 3 motions,
    15 % on 5), but no merge rule tried finds that merge on both: greedy
    association does best on 5 motions and worse than the defaults on 3;
    ``merge="average"`` does best on the wide-angle setting, between the
    two on 5 motions, and a few points worse than the defaults on 3.
    ``benchmarks/results/perspective.md`` and
    ``benchmarks/results/perspective_merges.md`` give the figures.
    ``partition="best_fit"`` lets a model choose among those partitions
    instead of the normalised cut (a background piece left as a cluster
    while two motions share another fits windowed subspaces worse). Seeds
    0-4 / 5-9 of ``bench_perspective.py``: 7.0 / 5.2 % on the wide-angle
    setting (default 14.2 / 18.3 %), 12.9 / 7.9 % on driving 3 motions
    (10.4 / 8.6 %), but 46.3 / 44.6 % on 5 motions (44.5 / 41.2 %): on 5
    motions it picks a wrong partition about as often as the default, as
    every rule tried on the fused kernel (see the script for what was
    tuned), and about twice the time of the default.

    References
    ----------
    .. [1] T.-J. Chin, H. Wang and D. Suter, "Robust fitting of multiple
       structures: the statistical learning approach", ICCV 2009.
    .. [2] X. Xu, L.-F. Cheong and Z. Li, "Motion segmentation by exploiting
       complementary geometric models", CVPR 2018.

    Examples
    --------
    >>> from sklearn_gpca.datasets import make_tracks
    >>> from sklearn_gpca.metrics import misclassification_rate
    >>> from sklearn_gpca import PerspectiveClustering
    >>> X, y = make_tracks(3, scene="lab", n_tracks=200, random_state=0)
    >>> model = PerspectiveClustering(3, random_state=0).fit(X)
    >>> model.labels_.shape
    (200,)
    """

    _parameter_constraints: dict = {
        "n_clusters": [Count(1, None, closed="left")],
        "models": [tuple, list],
        "n_hypotheses": [Count(1, None, closed="left")],
        "top": [Interval(Real, 0, 1, closed="right")],
        "gaps": [tuple, list],
        "window": [Count(3, None, closed="left")],
        "n_neighbors": [Count(1, None, closed="left")],
        "max_iter": [Count(0, None, closed="left")],
        "n_init": [Count(1, None, closed="left")],
        "n_rounds": [Count(1, None, closed="left")],
        "n_segments": [Count(1, None, closed="left"), None],
        "merge": [StrOptions(set(MERGES))],
        "partition": [StrOptions(set(PARTITIONS))],
        "random_state": ["random_state"],
    }

    def __init__(
        self,
        n_clusters=2,
        *,
        models=MODELS,
        n_hypotheses=100,
        top=0.05,
        gaps=(1, 2, 4, 8),
        window=4,
        n_neighbors=10,
        max_iter=30,
        n_init=10,
        n_rounds=1,
        n_segments=None,
        merge="association",
        partition="spectral",
        random_state=None,
    ):
        self.n_clusters = n_clusters
        self.models = models
        self.n_hypotheses = n_hypotheses
        self.top = top
        self.gaps = gaps
        self.window = window
        self.n_neighbors = n_neighbors
        self.max_iter = max_iter
        self.n_init = n_init
        self.n_rounds = n_rounds
        self.n_segments = n_segments
        self.merge = merge
        self.partition = partition
        self.random_state = random_state

    def _check_params_vs_input(self, X):
        n_samples, n_features = X.shape
        unknown = [m for m in self.models if m not in MODELS]
        if not self.models or unknown or len(set(self.models)) != len(self.models):
            raise ValueError(
                f"models must be a non-empty tuple of distinct names among "
                f"{MODELS}, got {tuple(self.models)!r}."
            )
        if n_features % 2:
            raise ValueError(
                f"X must have 2 columns (x, y) per frame, got an odd number of "
                f"features, {n_features}."
            )
        n_frames = n_features // 2
        bad_gaps = [
            g for g in self.gaps if not isinstance(g, Integral) or isinstance(g, bool)
        ]
        if not self.gaps or bad_gaps or min(self.gaps) < 1:
            raise ValueError(
                f"gaps must be a non-empty tuple of positive integers, got "
                f"{tuple(self.gaps)!r}."
            )
        if self.n_clusters > n_samples:
            raise ValueError(
                f"n_clusters={self.n_clusters} must be at most n_samples={n_samples}."
            )
        if self.n_segments is not None and not (
            self.n_clusters <= self.n_segments <= n_samples
        ):
            raise ValueError(
                f"n_segments={self.n_segments} must be between n_clusters="
                f"{self.n_clusters} and n_samples={n_samples}, or None."
            )
        if self.partition == "best_fit" and self.n_segments is not None:
            raise ValueError(
                f"partition='best_fit' chooses the segments itself; n_segments "
                f"must be None, got {self.n_segments}."
            )
        n_seen = observed_frames(X).sum(axis=1)
        unseen = np.flatnonzero(n_seen == 0)
        if unseen.size:
            raise ValueError(
                f"Every track needs an observed frame (both coordinates finite); "
                f"{describe_indices(unseen)} rows have none. Remove them."
            )
        n_moving = np.count_nonzero(n_seen >= 2)
        if self.n_clusters > n_moving:
            raise ValueError(
                f"n_clusters={self.n_clusters} must be at most the {n_moving} "
                "tracks observed in two frames or more (a track seen in one "
                "frame shows no motion)."
            )
        if n_frames < 2:
            raise ValueError(f"X must hold at least 2 frames, got {n_frames}.")

    @_fit_context(prefer_skip_nested_validation=True)
    def fit(self, X, y=None):
        """Segment the tracks.

        Parameters
        ----------
        X : array-like of shape (n_samples, 2 * n_frames)
            Tracks ``[x_1, y_1, ..., x_F, y_F]``, NaN (or masked) where
            missing; each track observed in at least one frame. Tracks seen
            in one frame only show no motion: they take the label most common
            among their 5 nearest longer tracks in the frame where they are
            seen.
        y : Ignored
            Not used, present for API consistency.

        Returns
        -------
        self : PerspectiveClustering
            Fitted estimator.
        """
        X = validate_data(
            self, masked_to_nan(X), dtype=np.float64, ensure_all_finite="allow-nan"
        )
        self._check_params_vs_input(X)
        moving = observed_frames(X).sum(axis=1) >= 2
        labels, votes, n_iter = perspective_clustering(
            X[moving],
            self.n_clusters,
            models=tuple(self.models),
            n_hypotheses=self.n_hypotheses,
            top=self.top,
            gaps=tuple(self.gaps),
            window=self.window,
            n_neighbors=self.n_neighbors,
            max_iter=self.max_iter,
            n_init=self.n_init,
            n_rounds=self.n_rounds,
            n_segments=self.n_segments,
            merge=self.merge,
            partition=self.partition,
            random_state=self.random_state,
        )
        silent = np.flatnonzero(moving)[np.diff(votes.indptr) == 0]
        if not moving.all():
            labels, orphans = label_from_neighbors(X, labels, moving)
            if orphans.size:
                warnings.warn(
                    f"{describe_indices(orphans)} tracks are seen in one frame "
                    "only, where no longer track is seen: they take the most "
                    "common label.",
                    UserWarning,
                    stacklevel=2,
                )
        warn_empty_motions(labels, self.n_clusters, X, name="n_clusters")
        if silent.size:
            warnings.warn(
                f"{describe_indices(silent)} tracks are observed only where too "
                "few tracks are co-visible to draw hypotheses; their labels carry "
                "no evidence.",
                UserWarning,
                stacklevel=2,
            )
        self.labels_ = labels
        self.n_hypotheses_ = votes.shape[1]
        self.n_iter_ = n_iter
        return self

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.input_tags.allow_nan = True
        return tags
