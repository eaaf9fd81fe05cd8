"""Coordinate descent on the lossy coding length of a segmentation.

A segmentation that misassigns a few points codes them in a group whose
Gaussian they do not fit, and pays for the directions they add to its code;
comparing coding lengths of such segmentations over the number of groups
then compares segmentation errors as much as numbers of groups. The descent
moves points one group at a time while the coding length
(:func:`sklearn_gpca._coding_length.coding_length`) falls, so that every
candidate number of groups is judged at a local minimum of the criterion
itself. The change of the code when a single point moves is exact and costs
``O(P D^2 n)`` for all points and groups at once: with ``S_k = X_k^T X_k``
and ``a = D / (eps^2 m)``, the matrix determinant lemma gives

    log det(I + a (S_k + x x^T)) = log det(I + a S_k)
                                   + log(1 + a x^T (I + a S_k)^{-1} x),

and the same with ``- x x^T`` for the point that leaves its group.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._coding_length import coding_length


def _group_bits(size, log_det, n_samples, n_features):
    """Bits of a group of ``size`` points whose code has ``log2 det = log_det``
    (its Gaussian plus its memberships); 0 for an empty group."""
    size = np.asarray(size, dtype=np.float64)
    with np.errstate(divide="ignore", invalid="ignore"):
        bits = (size + n_features) / 2 * log_det - size * np.log2(size / n_samples)
    return np.where(size > 0, bits, 0.0)


def coding_length_moves(points, labels, n_groups, distortion):
    """Change of the coding length when each point alone moves to each group.

    Parameters
    ----------
    points : ndarray of shape (n_samples, n_features)
        The coded points (unit vectors for a scale-free distortion).
    labels : ndarray of shape (n_samples,)
        Group of each point, in ``0 .. n_groups - 1`` (groups may be empty).
    n_groups : int
        Number of groups a point may move to.
    distortion : float
        The distortion of :func:`~sklearn_gpca._coding_length.coding_length`.

    Returns
    -------
    moves : ndarray of shape (n_samples, n_groups)
        ``coding_length(points, labels') - coding_length(points, labels)``
        where ``labels'`` moves point ``i`` alone to group ``k``; 0 for its
        own group.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._coding_descent import coding_length_moves
    >>> X = np.array([[1.0, 0], [1, 0.01], [0, 1], [0.01, 1], [1, 0]])
    >>> moves = coding_length_moves(X, np.array([0, 0, 1, 1, 1]), 2, 0.1)
    >>> bool(moves[4, 0] < 0)  # the last point belongs with the first two
    True
    """
    n_samples, n_features = points.shape
    sizes = np.bincount(labels, minlength=n_groups)
    arrive = np.empty((n_samples, n_groups))
    leave = np.zeros(n_samples)
    for k in range(n_groups):
        size, members = sizes[k], labels == k
        gram = points[members].T @ points[members]
        eigvals, eigvecs = np.linalg.eigh(gram)
        eigvals = np.maximum(eigvals, 0.0)
        coords = (points @ eigvecs) ** 2
        scale = n_features / (distortion**2 * max(size, 1))
        now = _group_bits(
            size, np.sum(np.log2(1 + scale * eigvals)), n_samples, n_features
        )
        # one point more: a = D / (eps^2 (m + 1)), the determinant lemma with + x x^T
        scale = n_features / (distortion**2 * (size + 1))
        gain = coords @ (scale / (1 + scale * eigvals))
        log_det = np.sum(np.log2(1 + scale * eigvals)) + np.log2(1 + gain)
        arrive[:, k] = _group_bits(size + 1, log_det, n_samples, n_features) - now
        if size == 1:
            leave[members] = -now
        elif size > 1:
            # one point fewer, with - x x^T: 1 - a x^T (I + a S)^{-1} x > 0
            # because S - x x^T is positive semi-definite
            scale = n_features / (distortion**2 * (size - 1))
            loss = coords[members] @ (scale / (1 + scale * eigvals))
            log_det = np.sum(np.log2(1 + scale * eigvals)) + np.log2(
                np.maximum(1 - loss, np.finfo(np.float64).tiny)
            )
            leave[members] = _group_bits(size - 1, log_det, n_samples, n_features) - now
    moves = arrive + leave[:, None]
    moves[np.arange(n_samples), labels] = 0.0
    return moves


def coding_length_descent(points, labels, distortion, *, max_iter=100):
    """Move points between groups while the coding length falls.

    Each round computes, for every point, the group that lowers the coding
    length most if that point alone moves (:func:`coding_length_moves`), and
    moves all the points that gain at once; when that does not lower the
    coding length (moves of several points interact), it moves the half that
    gain most, then a quarter, and so on down to the single best move, which
    always lowers it. The coding length falls at every round, so the descent
    stops, at the latest after ``max_iter`` rounds, at a segmentation no
    single move improves (a local minimum). Groups keep their names and may
    end empty.

    Parameters
    ----------
    points : ndarray of shape (n_samples, n_features)
        The coded points.
    labels : ndarray of shape (n_samples,)
        Starting group of each point, non-negative integers.
    distortion : float
        The distortion of :func:`~sklearn_gpca._coding_length.coding_length`.
    max_iter : int, default=100
        Largest number of rounds.

    Returns
    -------
    labels : ndarray of shape (n_samples,), dtype=intp
        The segmentation reached (the starting group names).
    bits : float
        Its coding length.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca._coding_descent import coding_length_descent
    >>> X = np.array([[1.0, 0], [1, 0.01], [0, 1], [0.01, 1], [1, 0]])
    >>> labels, bits = coding_length_descent(X, np.array([0, 0, 1, 1, 1]), 0.1)
    >>> labels.tolist()
    [0, 0, 1, 1, 0]
    """
    labels = np.asarray(labels).astype(np.intp, copy=True)
    n_groups = int(labels.max()) + 1
    bits = coding_length(points, labels, distortion)
    for _ in range(max_iter):
        moves = coding_length_moves(points, labels, n_groups, distortion)
        targets = np.argmin(moves, axis=1)
        gains = moves[np.arange(labels.size), targets]
        movers = np.flatnonzero(gains < 0)
        movers = movers[np.argsort(gains[movers], kind="stable")]
        while movers.size:
            moved = labels.copy()
            moved[movers] = targets[movers]
            moved_bits = coding_length(points, moved, distortion)
            if moved_bits < bits:
                labels, bits = moved, moved_bits
                break
            if movers.size == 1:  # rounding: no move gains anything
                movers = movers[:0]
            movers = movers[: movers.size // 2]
        if not movers.size:
            break
    return labels, float(bits)
