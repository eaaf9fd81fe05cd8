"""Motion segmentation with missing data: PowerFactorization and GPCA.

scikit-learn compatible estimators implementing and extending Vidal & Hartley,
"Motion Segmentation with Missing Data using PowerFactorization and GPCA"
(CVPR 2004).
"""

# SPDX-License-Identifier: BSD-3-Clause

from sklearn_gpca._gpca import GPCAClustering, gpca
from sklearn_gpca._ksubspaces import k_subspaces
from sklearn_gpca._model_selection import (
    NClustersSearch,
    coding_length_cost,
    distinct_coding_length_cost,
    merge_ratio,
    refined_trajectory_coding_length_cost,
    select_n_clusters,
    sine_likelihood_cost,
    trajectory_coding_length_cost,
)
from sklearn_gpca._motion import estimate_motions
from sklearn_gpca._motion_segmentation import MotionSegmentation
from sklearn_gpca._perspective import PerspectiveClustering
from sklearn_gpca._pipeline import paper_pipeline
from sklearn_gpca._power_factorization import PowerFactorization, power_factorization
from sklearn_gpca._segment import segment_motions
from sklearn_gpca._shape_interaction import (
    ShapeInteractionClustering,
    shape_interaction_matrix,
)

__version__ = "0.1.0.dev0"

__all__ = [
    "GPCAClustering",
    "MotionSegmentation",
    "NClustersSearch",
    "PerspectiveClustering",
    "PowerFactorization",
    "ShapeInteractionClustering",
    "__version__",
    "coding_length_cost",
    "distinct_coding_length_cost",
    "estimate_motions",
    "gpca",
    "k_subspaces",
    "merge_ratio",
    "paper_pipeline",
    "power_factorization",
    "refined_trajectory_coding_length_cost",
    "segment_motions",
    "select_n_clusters",
    "shape_interaction_matrix",
    "sine_likelihood_cost",
    "trajectory_coding_length_cost",
]
