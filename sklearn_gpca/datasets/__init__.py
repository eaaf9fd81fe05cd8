"""Synthetic motion data and loaders for real benchmarks."""

# SPDX-License-Identifier: BSD-3-Clause

from sklearn_gpca.datasets._motions import make_motions, make_transparent

__all__ = [
    "make_motions",
    "make_transparent",
]
