"""Plots of trajectories, similarity matrices and error curves.

Display objects in the style of scikit-learn's (``from_estimator``,
``from_predictions``, ``plot(ax=...)``, ``figure_``, ``ax_``). They need
matplotlib, the ``plot`` extra (``pip install 'sklearn_gpca[plot]'``), which is
imported only when something is drawn.
"""

# SPDX-License-Identifier: BSD-3-Clause

from sklearn_gpca.plotting._error_curve import ErrorCurveDisplay
from sklearn_gpca.plotting._similarity import SimilarityMatrixDisplay
from sklearn_gpca.plotting._trajectories import TrajectoryDisplay

__all__ = [
    "ErrorCurveDisplay",
    "SimilarityMatrixDisplay",
    "TrajectoryDisplay",
]
