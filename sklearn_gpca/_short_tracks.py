"""Labels of tracks too short to show a motion, from their neighbours in the image.

A track seen in a single frame is one point: no motion model can test it.
Tracks of one rigid object stay together in the image, so such a track takes
the label most common among its ``n_neighbors`` nearest labelled tracks in
the frames they share (distances of :func:`coobserved_sq_distances` over
co-observed coordinates; ties go to the nearest).
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._chunks import row_chunks
from sklearn_gpca._magnitude import in_safe_range
from sklearn_gpca._track_neighbors import coobserved_sq_distances

# Query rows per chunk (chunk x n_labelled distances in memory).
_CHUNK = 1024


def label_from_neighbors(X, labels, labelled, *, n_neighbors=5):
    """Labels of the tracks not ``labelled``, from the labelled tracks near them.

    Parameters
    ----------
    X : ndarray of shape (n_samples, n_features)
        Tracks, NaN where missing.
    labels : ndarray of shape (n_labelled,)
        Non-negative labels of the rows ``labelled`` of ``X``.
    labelled : ndarray of shape (n_samples,), dtype=bool
        Rows that have a label; at least one.
    n_neighbors : int, default=5
        Labelled tracks that vote for each unlabelled one.

    Returns
    -------
    full : ndarray of shape (n_samples,), dtype=intp
        Labels of all rows; the labelled rows keep theirs.
    orphans : ndarray of int
        Unlabelled rows that share no observed coordinate with any labelled
        track; they take the most common label.
    """
    X, _ = in_safe_range(X)
    mask = np.isfinite(X)
    X0 = np.where(mask, X, 0.0)
    labels = np.asarray(labels, dtype=np.intp)
    full = np.empty(X.shape[0], dtype=np.intp)
    full[labelled] = labels
    queries = np.flatnonzero(~labelled)
    if queries.size == 0:
        return full, queries
    n_labels = labels.max() + 1
    k = min(n_neighbors, labels.size)
    scores = np.zeros((queries.size, n_labels))
    seen_with = np.zeros(queries.size, dtype=bool)
    for rows in row_chunks(queries.size, _CHUNK):
        distances = coobserved_sq_distances(
            X0, mask, queries[rows], X0[labelled], mask[labelled], min_overlap=2
        )
        order = np.argpartition(distances, k - 1, axis=1)[:, :k]
        near = np.take_along_axis(distances, order, axis=1)
        # one vote per finite neighbour, and a fraction of one for ties: the
        # nearer the neighbour, the larger its share
        rank = np.argsort(np.argsort(near, axis=1), axis=1)
        weight = np.isfinite(near) * (1.0 + (k - rank) / (k * (k + 1.0)))
        chunk = np.zeros((near.shape[0], n_labels))
        np.add.at(chunk, (np.arange(near.shape[0])[:, None], labels[order]), weight)
        scores[rows] = chunk
        seen_with[rows] = np.isfinite(near).any(axis=1)
    orphans = queries[~seen_with]
    full[queries] = np.argmax(scores, axis=1)
    full[orphans] = np.argmax(np.bincount(labels, minlength=n_labels))
    return full, orphans
