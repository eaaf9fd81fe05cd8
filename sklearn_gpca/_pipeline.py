"""The paper's Algorithm 1 as a scikit-learn pipeline."""

# SPDX-License-Identifier: BSD-3-Clause

from sklearn.pipeline import make_pipeline

from sklearn_gpca._gpca import GPCAClustering
from sklearn_gpca._power_factorization import PowerFactorization


def paper_pipeline(n_clusters, *, random_state=None):
    """Algorithm 1 of Vidal & Hartley (CVPR 2004), exactly as published.

    Steps 1-3: project the trajectories to :math:`R^5` with PowerFactorization
    (the rows of ``V`` of the SVD for complete data), fit one homogeneous
    polynomial of degree ``n_clusters`` to the projected points, and cluster
    them spectrally with the similarity ``cos^2`` of the angles between the
    polynomial's gradients. No pre- or post-processing. This function keeps
    the paper's algorithm even when the library's defaults improve on it;
    step 4 is :func:`estimate_motions`.

    Parameters
    ----------
    n_clusters : int
        Number of motions.

    random_state : int, RandomState instance or None, default=None
        Seed of the factorisation and of the spectral clustering.

    Returns
    -------
    pipeline : sklearn.pipeline.Pipeline
        ``make_pipeline(PowerFactorization(5, ...), GPCAClustering(...))`` with
        the paper's PowerFactorization pinned (alternating least squares from
        one random start, at rank 5, on all rows: ``solver="als",
        completion_rank=None, n_init=1, max_init_samples=None``) and the
        paper's GPCA pinned: raw (not normalised) points, one polynomial's
        gradients, the ``cos^2`` kernel on all pairs and no refinement
        (``normalize=False, point_normals="one_polynomial",
        affinity="all_pairs", affinity_power=1, refine=False``).

    Examples
    --------
    >>> from sklearn_gpca import paper_pipeline
    >>> from sklearn_gpca.datasets import make_motions
    >>> X, y = make_motions(2, n_points=100, n_frames=8, random_state=0)
    >>> labels = paper_pipeline(2, random_state=0).fit_predict(X)
    >>> labels.shape
    (100,)
    """
    return make_pipeline(
        PowerFactorization(
            5,
            whiten=True,
            solver="als",
            completion_rank=None,
            n_init=1,
            max_init_samples=None,
            random_state=random_state,
        ),
        GPCAClustering(
            n_clusters,
            normalize=False,
            point_normals="one_polynomial",
            affinity="all_pairs",
            affinity_power=1,
            refine=False,
            random_state=random_state,
        ),
    )
