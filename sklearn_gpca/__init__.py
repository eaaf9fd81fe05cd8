"""Motion segmentation with missing data: PowerFactorization and GPCA.

scikit-learn compatible estimators implementing and extending Vidal & Hartley,
"Motion Segmentation with Missing Data using PowerFactorization and GPCA"
(CVPR 2004).
"""

# SPDX-License-Identifier: BSD-3-Clause

from sklearn_gpca._gpca import GPCAClustering
from sklearn_gpca._motion import estimate_motions
from sklearn_gpca._perspective import PerspectiveClustering
from sklearn_gpca._pipeline import paper_pipeline
from sklearn_gpca._power_factorization import PowerFactorization
from sklearn_gpca._shape_interaction import (
    ShapeInteractionClustering,
    shape_interaction_matrix,
)

__version__ = "0.1.0.dev0"

__all__ = [
    "GPCAClustering",
    "PerspectiveClustering",
    "PowerFactorization",
    "ShapeInteractionClustering",
    "__version__",
    "estimate_motions",
    "paper_pipeline",
    "shape_interaction_matrix",
]
