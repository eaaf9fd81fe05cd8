"""The Costeira-Kanade shape interaction matrix, a classical baseline."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
from sklearn.base import BaseEstimator, ClusterMixin, _fit_context
from sklearn.cluster import SpectralClustering
from sklearn.utils import check_array
from sklearn.utils.validation import validate_data

from sklearn_gpca._validation import Count


def shape_interaction_matrix(X, rank):
    """Costeira and Kanade's shape interaction matrix ``Q = V V^T``.

    With ``W = X^T = U S V^T`` the SVD of the measurement matrix truncated to
    ``rank``, ``Q_ij = 0`` when trajectories ``i`` and ``j`` belong to
    different, linearly independent motions (equations (2) and (3) of Vidal &
    Hartley, 2004). Dependent or degenerate motions break that property.

    Parameters
    ----------
    X : array-like of shape (n_samples, n_features)
        Complete trajectories, one per row.

    rank : int
        Rank of the truncated SVD, ``4 n`` for ``n`` independent full motions.

    Returns
    -------
    Q : ndarray of shape (n_samples, n_samples)

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca import shape_interaction_matrix
    >>> X = np.kron(np.eye(2), np.ones((2, 1)))  # two 1-D motions
    >>> shape_interaction_matrix(X, rank=2).round(2)
    array([[0.5, 0.5, 0. , 0. ],
           [0.5, 0.5, 0. , 0. ],
           [0. , 0. , 0.5, 0.5],
           [0. , 0. , 0.5, 0.5]])
    """
    X = check_array(X, dtype=np.float64)
    if not 1 <= rank <= min(X.shape):
        raise ValueError(
            f"rank={rank} must be between 1 and min(n_samples, n_features)="
            f"{min(X.shape)}."
        )
    V = np.linalg.svd(X, full_matrices=False)[0][:, :rank]
    return V @ V.T


class ShapeInteractionClustering(ClusterMixin, BaseEstimator):
    """Spectral clustering of the Costeira-Kanade shape interaction matrix.

    The classical baseline of multibody factorisation: the affinity is
    ``|Q_ij|`` from :func:`shape_interaction_matrix`, clustered by
    :class:`sklearn.cluster.SpectralClustering`. Provably correct only for
    linearly independent motions and complete data; it forms a dense
    ``n_samples x n_samples`` matrix.

    Parameters
    ----------
    n_clusters : int, default=2
        Number of motions.

    rank : int or None, default=None
        Rank of the measurement matrix; None uses ``4 * n_clusters`` capped at
        ``min(n_samples, n_features)``.

    random_state : int, RandomState instance or None, default=None
        Seed of the spectral clustering.

    Attributes
    ----------
    labels_ : ndarray of shape (n_samples,)
        Motion of each trajectory.

    affinity_matrix_ : ndarray of shape (n_samples, n_samples)
        The absolute shape interaction matrix.

    n_features_in_ : int
        Number of features seen during :term:`fit`.

    See Also
    --------
    GPCAClustering : Subspace clustering that handles dependent motions.

    References
    ----------
    J. Costeira and T. Kanade, "A multibody factorization method for
    independently moving objects", IJCV 29(3), 1998.

    Examples
    --------
    >>> from sklearn_gpca import ShapeInteractionClustering
    >>> from sklearn_gpca.datasets import make_motions
    >>> from sklearn_gpca.metrics import misclassification_rate
    >>> X, y = make_motions(2, n_points=[40, 40], n_frames=8, noise=0.0,
    ...                     random_state=0)
    >>> labels = ShapeInteractionClustering(2, random_state=0).fit_predict(X)
    >>> misclassification_rate(y, labels) < 0.1
    True
    """

    _parameter_constraints: dict = {
        "n_clusters": [Count(1, None, closed="left")],
        "rank": [Count(1, None, closed="left"), None],
        "random_state": ["random_state"],
    }

    def __init__(self, n_clusters=2, *, rank=None, random_state=None):
        self.n_clusters = n_clusters
        self.rank = rank
        self.random_state = random_state

    @_fit_context(prefer_skip_nested_validation=True)
    def fit(self, X, y=None):
        """Cluster the trajectories ``X``.

        Parameters
        ----------
        X : array-like of shape (n_samples, n_features)
            Complete trajectories, one per row.

        y : Ignored
            Not used, present for API consistency by convention.

        Returns
        -------
        self : object
            Fitted estimator.
        """
        X = validate_data(self, X, dtype=np.float64, ensure_min_samples=2)
        if self.n_clusters > X.shape[0]:
            raise ValueError(
                f"n_clusters={self.n_clusters} must be at most n_samples={X.shape[0]}."
            )
        rank = self.rank or min(4 * self.n_clusters, *X.shape)
        self.affinity_matrix_ = np.abs(shape_interaction_matrix(X, rank))
        spectral = SpectralClustering(
            self.n_clusters, affinity="precomputed", random_state=self.random_state
        )
        self.labels_ = spectral.fit_predict(self.affinity_matrix_)
        return self
