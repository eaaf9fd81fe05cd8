"""scikit-learn's k-means on a few hundred points, without its fixed costs.

The spectral stage runs ``KMeans(n_clusters, n_init=10)`` several times per
fit on the unit rows of two or three eigenvectors of a few hundred points.
There, the validation, thread-pool and dispatch overheads of
``KMeans.fit`` cost several times the arithmetic. :func:`kmeans_labels`
repeats the same computation in numpy, with the same random draws in the same
order: k-means++ seeding (``n_local_trials = 2 + log(n_clusters)``), Lloyd
iterations on the centred data to strict convergence or a centre shift
within ``tol`` times the mean variance, and the run of lowest inertia; so it
returns the labels of ``KMeans(...).fit_predict`` (up to round-off in exact
ties). Whenever scikit-learn would do something this does not repeat (an
empty cluster to relocate, fewer distinct points than clusters), the
generator is put back and ``KMeans`` itself runs.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
from sklearn.cluster import KMeans
from sklearn.utils import check_random_state

# KMeans's defaults, which the spectral stage uses.
_MAX_ITER = 300
_TOL = 1e-4


class _Fallback(Exception):
    """A case that scikit-learn's KMeans handles in a way not repeated here."""


def kmeans_labels(X, n_clusters, *, n_init, random_state):
    """Labels of ``KMeans(n_clusters, n_init=n_init,
    random_state=random_state).fit_predict(X)``.

    Parameters
    ----------
    X : ndarray of shape (n_samples, n_features), float64
    n_clusters : int
    n_init : int
    random_state : int, RandomState instance or None
        Advanced exactly as ``KMeans`` advances it.

    Returns
    -------
    labels : ndarray of shape (n_samples,), dtype=intp
    """
    X = np.ascontiguousarray(X, dtype=np.float64)
    generator = check_random_state(random_state)
    saved = generator.get_state()
    try:
        if X.shape[0] < n_clusters or not np.all(np.isfinite(X)):
            raise _Fallback
        return _kmeans(X, n_clusters, n_init, generator)
    except _Fallback:
        generator.set_state(saved)
        kmeans = KMeans(n_clusters=n_clusters, n_init=n_init, random_state=generator)
        return kmeans.fit_predict(X).astype(np.intp)


def _kmeans(X, n_clusters, n_init, generator):
    tol = np.mean(np.var(X, axis=0)) * _TOL
    X = X - X.mean(axis=0)
    centers = _kmeans_plusplus(X, n_clusters, n_init, generator)
    labels, inertia = _lloyd(X, centers, tol)
    best = 0
    for run in range(1, n_init):
        if inertia[run] < inertia[best] and not _same_clustering(
            labels[run], labels[best], n_clusters
        ):
            best = run
    if np.unique(labels[best]).size < n_clusters:
        raise _Fallback  # KMeans warns about duplicate points
    return labels[best]


def _squared_distances(centers, X, norms):
    """scikit-learn's ``_euclidean_distances(centers, X, squared=True)``, for
    a stack of sets of centres."""
    distances = -2 * (centers @ X.T)
    distances += np.einsum("...ij,...ij->...i", centers, centers)[..., None]
    distances += norms
    np.maximum(distances, 0, out=distances)
    return distances


def _kmeans_plusplus(X, n_clusters, n_init, generator):
    """k-means++ centres of ``n_init`` runs, shape ``(n_init, n_clusters,
    n_features)``.

    scikit-learn draws, run after run, the first centre by
    ``choice(n_samples, p=weights / weights.sum())`` (one uniform number)
    and then ``n_local_trials`` uniform numbers per further centre: the same
    numbers in the same order are drawn here at once.
    """
    n_samples = X.shape[0]
    norms = np.einsum("ij,ij->i", X, X)
    weights = np.ones(n_samples)
    n_local_trials = 2 + int(np.log(n_clusters))
    per_run = 1 + (n_clusters - 1) * n_local_trials
    draws = generator.random_sample(n_init * per_run).reshape(n_init, per_run)
    cdf = (weights / weights.sum()).cumsum()
    cdf /= cdf[-1]
    first = np.searchsorted(cdf, draws[:, 0], side="right")
    centers = np.empty((n_init, n_clusters, X.shape[1]))
    centers[:, 0] = X[first]
    closest = _squared_distances(centers[:, :1], X, norms)[:, 0]
    potential = closest @ weights
    runs = np.arange(n_init)
    for c in range(1, n_clusters):
        trials = draws[:, 1 + (c - 1) * n_local_trials : 1 + c * n_local_trials]
        trials = trials * potential[:, None]
        cumulative = np.cumsum(weights * closest, axis=1)
        # searchsorted(cumulative[run], trials[run]) for every run
        candidates = np.sum(cumulative[:, :, None] < trials[:, None, :], axis=1)
        np.clip(candidates, None, n_samples - 1, out=candidates)
        distances = _squared_distances(X[candidates], X, norms)
        np.minimum(closest[:, None, :], distances, out=distances)
        potentials = distances @ weights
        best = np.argmin(potentials, axis=1)
        potential = potentials[runs, best]
        closest = distances[runs, best]
        centers[:, c] = X[candidates[runs, best]]
    return centers


def _assign(X, centers):
    """Nearest centre of every point, as scikit-learn's Lloyd step finds it."""
    distances = np.einsum("...ij,...ij->...i", centers, centers)[..., None, :]
    distances = distances - 2 * (X @ centers.transpose(0, 2, 1))
    return np.argmin(distances, axis=-1)


def _lloyd(X, centers, tol):
    """Lloyd iterations of every run, each until it converges as in
    scikit-learn (labels unchanged, or centres moved by at most ``tol`` in
    squared norm, or ``_MAX_ITER``)."""
    n_init, n_clusters, _ = centers.shape
    labels = np.empty((n_init, X.shape[0]), dtype=np.intp)
    final = np.empty_like(centers)
    active = np.arange(n_init)
    labels_old = np.full((n_init, X.shape[0]), -1)
    for _ in range(_MAX_ITER):
        current = _assign(X, centers)
        one_hot = current[:, :, None] == np.arange(n_clusters)
        counts = one_hot.sum(axis=1)
        if np.any(counts == 0):
            raise _Fallback  # KMeans relocates empty clusters
        new = (one_hot.transpose(0, 2, 1) @ X) * (1.0 / counts)[:, :, None]
        shift = np.sum((new - centers) ** 2, axis=(1, 2))
        strict = np.all(current == labels_old, axis=1)
        loose = ~strict & (shift <= tol)
        # converged with unchanged labels: the labels of this step
        labels[active[strict]] = current[strict]
        final[active[strict]] = new[strict]
        # converged on the shift: the labels of the final centres
        if loose.any():
            labels[active[loose]] = _assign(X, new[loose])
            final[active[loose]] = new[loose]
        going = ~(strict | loose)
        active, centers, labels_old = active[going], new[going], current[going]
        if not active.size:
            break
    else:
        labels[active] = _assign(X, centers)
        final[active] = centers
    residual = X - np.take_along_axis(final, labels[:, :, None], axis=1)
    inertia = np.einsum("rij,rij->r", residual, residual)
    return labels, inertia


def _same_clustering(labels1, labels2, n_clusters):
    """Whether two labellings are the same partition (up to a permutation)."""
    # scikit-learn's _is_same_clustering: labels1 determines labels2
    pairs = np.unique(labels1 * n_clusters + labels2)
    return np.unique(pairs // n_clusters).size == pairs.size
