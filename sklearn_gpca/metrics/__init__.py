"""Evaluation metrics for motion segmentation."""

# SPDX-License-Identifier: BSD-3-Clause

from sklearn_gpca.metrics._misclassification import (
    get_scorer,
    get_scorer_names,
    misclassification_rate,
    misclassification_scorer,
)
from sklearn_gpca.metrics._oracle import oracle_labels

__all__ = [
    "get_scorer",
    "get_scorer_names",
    "misclassification_rate",
    "misclassification_scorer",
    "oracle_labels",
]
