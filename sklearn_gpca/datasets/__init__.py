"""Synthetic motion data and loaders for real benchmarks."""

# SPDX-License-Identifier: BSD-3-Clause

from sklearn_gpca.datasets._files import load_trajectories
from sklearn_gpca.datasets._hopkins155 import (
    fetch_hopkins155,
    hopkins155_category,
    load_hopkins155,
)
from sklearn_gpca.datasets._lowrank import load_lowrank
from sklearn_gpca.datasets._missing import make_missing
from sklearn_gpca.datasets._motions import make_motions, make_transparent
from sklearn_gpca.datasets._tracks import make_tracks

__all__ = [
    "fetch_hopkins155",
    "hopkins155_category",
    "load_hopkins155",
    "load_lowrank",
    "load_trajectories",
    "make_missing",
    "make_motions",
    "make_tracks",
    "make_transparent",
]
