"""Labels of all points from the segmentation of a subsample.

Above ``max_spectral_samples`` points the graph route of
:class:`~sklearn_gpca.GPCAClustering` segments a random subsample. Every other
point then gets as neighbours its nearest subsample points (sign invariant),
and is assigned by the smoothed cost of K-subspaces: its squared sine distance
to each subspace of the subsample's segmentation, plus the Potts penalty for
disagreeing with those neighbours. The same rule labels new points in
``predict``. Time and memory are ``O(P (k + K^2 n))``.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np

from sklearn_gpca._affinity import sign_invariant_neighbors
from sklearn_gpca._ksubspaces import smoothed_assignment
from sklearn_gpca._subspaces import own_residuals


def _outside(n_points, sample):
    """Mask of the points outside the subsample."""
    others = np.ones(n_points, dtype=bool)
    others[sample] = False
    return others


def extension_neighbors(unit, sample, sample_neighbors, *, n_jobs=None):
    """Neighbours of every point among the subsample points.

    Parameters
    ----------
    unit : ndarray of shape (n_samples, n_features)
        All the unit points.
    sample : ndarray of shape (n_sample,), dtype=intp
        Sorted indices of the subsample.
    sample_neighbors : ndarray of shape (n_sample, n_local)
        Neighbours of each subsample point within the subsample (subsample
        indices); they keep them.
    n_jobs : int or None, default=None
        Parallel jobs of the neighbour search.

    Returns
    -------
    neighbors : ndarray of shape (n_samples, n_local), dtype=intp
        Indices into ``unit``, all of subsample points.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca.stages import (
    ...     unit_rows, sign_invariant_neighbors, extension_neighbors)
    >>> rng = np.random.RandomState(0)
    >>> # two planes of R^3: z = 0 and x = 0
    >>> unit = unit_rows(np.vstack([rng.randn(20, 3) * [1, 1, 0],
    ...                             rng.randn(20, 3) * [0, 1, 1]]))
    >>> sample = np.arange(0, 40, 2)
    >>> sample_neighbors = sign_invariant_neighbors(unit[sample], 3)
    >>> neighbors = extension_neighbors(unit, sample, sample_neighbors)
    >>> neighbors.shape, bool(np.isin(neighbors, sample).all())
    ((40, 3), True)
    """
    n_points = unit.shape[0]
    others = _outside(n_points, sample)
    neighbors = np.empty((n_points, sample_neighbors.shape[1]), dtype=np.intp)
    neighbors[sample] = sample[sample_neighbors]
    neighbors[others] = sample[
        sign_invariant_neighbors(
            unit[sample],
            sample_neighbors.shape[1],
            queries=unit[others],
            n_jobs=n_jobs,
        )
    ]
    return neighbors


def reference_neighbors(reference, n_local, queries, *, n_jobs=None):
    """Nearest reference points of each query, the query's own line excluded.

    A query on the line of a reference point (a training point) gets the
    ``n_local`` nearest *other* reference points, the neighbourhood it had in
    the fit; any other query its ``n_local`` nearest reference points.

    Parameters
    ----------
    reference : ndarray of shape (n_reference, n_features)
        Unit points with known labels.
    n_local : int
        Number of neighbours, at most ``n_reference - 1``.
    queries : ndarray of shape (n_queries, n_features)
        Unit points.
    n_jobs : int or None, default=None
        Parallel jobs of the neighbour search.

    Returns
    -------
    neighbors : ndarray of shape (n_queries, n_local), dtype=intp
        Indices into ``reference``.
    """
    distances, found = sign_invariant_neighbors(
        reference, n_local + 1, queries=queries, n_jobs=n_jobs, return_distance=True
    )
    # lines that agree to 12 decimals are one line (as in the fit's dedupe)
    own_line = distances[:, 0] <= 1e-12
    return np.where(own_line[:, None], found[:, 1:], found[:, :-1])


def extend_labels(unit, sample, sample_labels, neighbors, bases, *, smoothing):
    """Labels of all points from those of the subsample.

    Parameters
    ----------
    unit, sample
        As in :func:`extension_neighbors`.
    sample_labels : ndarray of shape (n_sample,)
        The subsample's segmentation.
    neighbors : ndarray of shape (n_samples, n_local)
        From :func:`extension_neighbors`.
    bases : list of ndarray of shape (n_features, d_k)
        The subspaces of the subsample's clusters.
    smoothing : float
        Weight of the Potts term (0: nearest subspace).

    Returns
    -------
    labels : ndarray of shape (n_samples,), dtype=intp
        ``sample_labels`` on the subsample; the smoothed assignment elsewhere.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca.stages import (
    ...     unit_rows, sign_invariant_neighbors, extension_neighbors,
    ...     extend_labels, fit_subspaces)
    >>> rng = np.random.RandomState(0)
    >>> # two planes of R^3: z = 0 and x = 0
    >>> unit = unit_rows(np.vstack([rng.randn(20, 3) * [1, 1, 0],
    ...                             rng.randn(20, 3) * [0, 1, 1]]))
    >>> y = np.repeat([0, 1], 20)
    >>> sample = np.arange(0, 40, 2)
    >>> bases, _ = fit_subspaces(unit[sample], y[sample], 2, 2, 0.05)
    >>> neighbors = extension_neighbors(
    ...     unit, sample, sign_invariant_neighbors(unit[sample], 3))
    >>> labels = extend_labels(unit, sample, y[sample], neighbors, bases, smoothing=5.0)
    >>> bool((labels == y).all())
    True
    """
    n_points = unit.shape[0]
    others = _outside(n_points, sample)
    labels = np.empty(n_points, dtype=np.intp)
    labels[sample] = sample_labels
    own = own_residuals(unit[sample], sample_labels, bases)
    neighbor_labels = labels[neighbors[others]] if smoothing > 0 else None
    labels[others] = smoothed_assignment(
        unit[others], bases, np.median(own), neighbor_labels, smoothing
    )
    return labels
