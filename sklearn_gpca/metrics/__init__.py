"""Evaluation metrics for motion segmentation."""

# SPDX-License-Identifier: BSD-3-Clause

from sklearn_gpca.metrics._misclassification import (
    get_scorer,
    get_scorer_names,
    misclassification_rate,
    misclassification_scorer,
)

__all__ = [
    "get_scorer",
    "get_scorer_names",
    "misclassification_rate",
    "misclassification_scorer",
]
