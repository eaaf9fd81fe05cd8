"""Motion hypotheses on frame pairs and windows, ranked per track (votes).

Each model (fundamental matrix, homography, rank-4 subspace) is estimated on
many minimal samples of tracks that are all observed in the same frames: a
frame pair ``(f, f + g)`` for the two-view models, a window of consecutive
frames for the subspace. Every track observed there gets a residual to every
hypothesis, and votes for the ``top`` share of them with the smallest
residuals: the ordered residual kernel (ORK) of Chin, Wang & Suter (ICCV 2009),
as Xu, Cheong & Li (CVPR 2018) use it per frame pair. Ranking, not a threshold,
makes the votes free of the residual's scale, which differs between models,
frame pairs and sequences.

Samples are local (a random seed track and its nearest co-visible tracks in
the image) so that a small object gets pure samples about as often as the
background, in proportion to its tracks rather than to the square or the
eighth power of its share. A track's votes count only among the hypotheses of
frames where it is observed, so partial tracks count wherever they are seen.

Guided samples (a second round, after a first clustering) draw the others
among the seed's co-visible tracks that voted most like it, and seeds in
inverse proportion to the size of their first-round cluster: the guided
sampling of Chin, Yu & Suter (Multi-GS, IEEE TPAMI 2012) with balanced seeds,
so that small motions get as many pure hypotheses as the dominant one.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
from scipy import sparse

from sklearn_gpca._affinity import _kneighbors
from sklearn_gpca._chunks import row_chunks
from sklearn_gpca._memory import chunk_rows
from sklearn_gpca._two_view import (
    MIN_SAMPLE,
    fit_fundamental,
    fit_homography,
    sampson_fundamental,
    sampson_homography,
)

#: Minimal sample of every model: 8 point pairs, 4 point pairs, 4 tracks.
SAMPLE_SIZE = {**MIN_SAMPLE, "subspace": 4}

#: Rank of the subspace hypotheses: a rigid motion under an affine camera.
SUBSPACE_RANK = 4


def observed_frames(X):
    """Which tracks are observed in which frames.

    Parameters
    ----------
    X : ndarray of shape (n_samples, 2 * n_frames)
        Tracks ``[x_1, y_1, ..., x_F, y_F]``, NaN where missing.

    Returns
    -------
    observed : ndarray of shape (n_samples, n_frames), dtype=bool
        True where both coordinates of the frame are finite.
    """
    return np.isfinite(X[:, 0::2]) & np.isfinite(X[:, 1::2])


def frame_pairs(n_frames, gaps):
    """Frame pairs ``(f, f + g)`` for every gap ``g``, as an (n, 2) array."""
    pairs = [(f, f + g) for g in gaps for f in range(n_frames - g)]
    return np.array(pairs, dtype=np.intp).reshape(-1, 2)


def _with_members(seeds, neighbors, size, rng):
    """Each seed and ``size - 1`` of its candidate neighbours, drawn without
    replacement (uniformly, one permutation per row)."""
    picks = np.argsort(rng.random_sample(neighbors.shape), axis=1)[:, : size - 1]
    return np.c_[seeds, np.take_along_axis(neighbors, picks, axis=1)]


def local_samples(positions, size, n_samples, n_neighbors, rng):
    """Random local samples: a seed and ``size - 1`` of its nearest neighbours.

    Parameters
    ----------
    positions : ndarray of shape (n_points, n_dims)
        Where the candidate tracks are (image coordinates).
    size : int
        Points per sample, at most ``n_points``.
    n_samples : int
        Number of samples.
    n_neighbors : int
        The other members are drawn without replacement among the seed's
        ``n_neighbors`` nearest points (clipped to ``[size - 1, n_points -
        1]``).
    rng : RandomState

    Returns
    -------
    samples : ndarray of shape (n_samples, size), dtype=intp
        Indices into ``positions``, distinct within each sample.
    """
    n_points = positions.shape[0]
    n_neighbors = int(np.clip(n_neighbors, size - 1, n_points - 1))
    seeds = rng.randint(n_points, size=n_samples)
    if size == 1:
        return seeds[:, None]
    # The query point is its own first neighbour unless duplicates precede it:
    # drop the seed wherever it appears, keep n_neighbors others.
    neighbors = _kneighbors(positions, positions[seeds], n_neighbors + 1, None)[1]
    not_seed = neighbors != seeds[:, None]
    order = np.argsort(~not_seed, axis=1, kind="stable")[:, :n_neighbors]
    neighbors = np.take_along_axis(neighbors, order, axis=1)
    return _with_members(seeds, neighbors, size, rng)


def guided_samples(preferences, size, n_samples, n_neighbors, rng, seed_weights=None):
    """Samples of tracks that vote alike: a seed and its most alike tracks.

    Parameters
    ----------
    preferences : sparse array of shape (n_points, n_columns)
        Earlier votes of the candidate tracks (rows); the similarity of two
        tracks is the inner product of their rows (their co-votes).
    size : int
        Points per sample, at most ``n_points``.
    n_samples : int
        Number of samples.
    n_neighbors : int
        The other members are drawn without replacement among the seed's
        ``n_neighbors`` most similar points (clipped to ``[size - 1,
        n_points - 1]``); ties are broken at random.
    rng : RandomState
    seed_weights : ndarray of shape (n_points,), default=None
        Probabilities (up to a factor) of drawing each point as a seed;
        None: uniform. Must have a positive sum.

    Returns
    -------
    samples : ndarray of shape (n_samples, size), dtype=intp
        Indices into the rows of ``preferences``, distinct within each sample.
    """
    n_points = preferences.shape[0]
    if seed_weights is None:
        seeds = rng.randint(n_points, size=n_samples)
    else:
        seeds = rng.choice(
            n_points, size=n_samples, p=seed_weights / seed_weights.sum()
        )
    if size == 1:
        return seeds[:, None]
    n_neighbors = int(np.clip(n_neighbors, size - 1, n_points - 1))
    similarity = preferences[seeds] @ preferences.T
    similarity = similarity.toarray() if sparse.issparse(similarity) else similarity
    # random tie-breaking below the smallest non-zero difference of co-votes
    similarity = np.asarray(similarity, dtype=np.float64)
    similarity += 1e-9 * np.abs(similarity).max() * rng.random_sample(similarity.shape)
    similarity[np.arange(n_samples), seeds] = -np.inf
    neighbors = np.argpartition(-similarity, n_neighbors - 1, axis=1)[:, :n_neighbors]
    return _with_members(seeds, neighbors, size, rng)


def _two_view_residuals(model, points1, points2, samples):
    fit, sampson = {
        "fundamental": (fit_fundamental, sampson_fundamental),
        "homography": (fit_homography, sampson_homography),
    }[model]
    M = fit(points1[samples], points2[samples])
    return sampson(M, points1, points2)


def _subspace_residuals(tracks, samples):
    """Distance of every track to the span of every sample's tracks.

    Divided by the square root of the residual's degrees of freedom, as in
    the oracle's per-degree-of-freedom residual. Computed in chunks of tracks
    whose temporaries fit in scikit-learn's ``working_memory``.
    """
    bases = np.linalg.qr(np.swapaxes(tracks[samples], 1, 2))[0]
    n_hyp, n_coords, _ = bases.shape
    distances = np.empty((tracks.shape[0], n_hyp))
    # the three n_hyp x n_coords temporaries of a chunk of tracks (the fit, the
    # residual, its square in the norm) fit in working_memory
    for rows in row_chunks(tracks.shape[0], chunk_rows(3 * 8 * n_hyp * n_coords)):
        part = tracks[rows]
        coords = np.einsum("pd,hdk->phk", part, bases)
        # The residual itself, not ||x||^2 - ||Q^T x||^2, which loses half the
        # digits near 0.
        residual = part[:, None, :] - np.einsum("phk,hdk->phd", coords, bases)
        distances[rows] = np.linalg.norm(residual, axis=2)
    dof = tracks.shape[1] - SUBSPACE_RANK
    return distances / np.sqrt(dof)


def top_votes(residuals, top):
    """Each row's ``top`` share of columns with the smallest residuals.

    Parameters
    ----------
    residuals : ndarray of shape (n_points, n_hypotheses)
    top : float in (0, 1]
        Share of the hypotheses each point votes for; at least one.

    Returns
    -------
    columns : ndarray of shape (n_points, k), dtype=intp
        The ``k = max(1, round(top * n_hypotheses))`` hypotheses each point
        votes for (in no particular order).
    """
    n_hyp = residuals.shape[1]
    k = max(1, round(top * n_hyp))
    if k >= n_hyp:
        return np.broadcast_to(np.arange(n_hyp), (residuals.shape[0], n_hyp))
    return np.argpartition(residuals, k - 1, axis=1)[:, :k]


def _views(model, observed, gaps, window):
    """Frame sets the model's hypotheses are drawn on: pairs or windows."""
    n_frames = observed.shape[1]
    if model == "subspace":
        return [np.arange(s, s + window) for s in range(n_frames - window + 1)]
    return list(frame_pairs(n_frames, gaps))


def preference_votes(
    X,
    model,
    *,
    n_hypotheses,
    top,
    gaps,
    window,
    n_neighbors,
    random_state,
    preferences=None,
    seed_weights=None,
):
    """Sparse votes of every track for the hypotheses of one model.

    Parameters
    ----------
    X : ndarray of shape (n_samples, 2 * n_frames)
        Tracks, NaN where missing.
    model : {"fundamental", "homography", "subspace"}
        Fundamental matrices and homographies are drawn on the frame pairs
        ``(f, f + g)``, ``g`` in ``gaps``, with Sampson distances as
        residuals; rank-4 subspaces on every window of ``window`` consecutive
        frames, with the distance to the span per degree of freedom.
    n_hypotheses : int
        Hypotheses drawn on each frame pair or window.
    top : float in (0, 1]
        Share of a view's hypotheses each track observed there votes for.
    gaps : sequence of int
        Frame gaps of the pairs.
    window : int
        Frames per window of the subspace model, at least 3.
    n_neighbors : int
        Locality of the samples (see :func:`local_samples` and
        :func:`guided_samples`).
    random_state : RandomState
    preferences : sparse array of shape (n_samples, n_columns), default=None
        Earlier votes: if given, samples are guided by them
        (:func:`guided_samples`) instead of local in the image.
    seed_weights : ndarray of shape (n_samples,), default=None
        With ``preferences``, how likely each track is drawn as a seed
        (positive; None: uniform).

    Returns
    -------
    votes : scipy.sparse.csr_array of shape (n_samples, n_columns)
        1 where a track votes for a hypothesis. Views with fewer co-visible
        tracks than a minimal sample plus one give no column.
    n_views : int
        Number of views (frame pairs or windows) that gave hypotheses.

    Notes
    -----
    Time ``O(n_views * n_hypotheses * n_samples)``: linear in the number of
    tracks for a bounded number of hypotheses; one Python loop over the views
    (frame pairs or windows), none over samples or hypotheses.
    """
    size = SAMPLE_SIZE[model]
    observed = observed_frames(X)
    rows, cols = [], []
    offset = n_views = 0
    for frames in _views(model, observed, gaps, window):
        members = np.flatnonzero(observed[:, frames].all(axis=1))
        if members.size <= size:
            continue
        coords = X[np.ix_(members, np.c_[2 * frames, 2 * frames + 1].ravel())]
        if preferences is None:
            samples = local_samples(
                coords[:, :2], size, n_hypotheses, n_neighbors, random_state
            )
        else:
            samples = guided_samples(
                preferences[members],
                size,
                n_hypotheses,
                n_neighbors,
                random_state,
                None if seed_weights is None else seed_weights[members],
            )
        if model == "subspace":
            residuals = _subspace_residuals(coords, samples)
        else:
            residuals = _two_view_residuals(
                model, coords[:, :2], coords[:, 2:], samples
            )
        # Non-finite residuals (degenerate samples) rank last.
        residuals = np.where(np.isfinite(residuals), residuals, np.inf)
        chosen = top_votes(residuals, top)
        rows.append(np.repeat(members, chosen.shape[1]))
        cols.append(chosen.ravel() + offset)
        offset += n_hypotheses
        n_views += 1
    if not rows:
        return sparse.csr_array((X.shape[0], 0)), 0
    rows, cols = np.concatenate(rows), np.concatenate(cols)
    votes = sparse.csr_array(
        (np.ones(rows.size), (rows, cols)), shape=(X.shape[0], offset)
    )
    return votes, n_views
