"""Shared pytest fixtures: the read-only real data; a small tracker-like scene."""

# SPDX-License-Identifier: BSD-3-Clause

import os
from pathlib import Path

import pytest
from hypothesis import settings

from sklearn_gpca.datasets import make_tracks

# Property tests draw the same examples on every run, so that a CI run cannot
# fail by chance; `pytest --hypothesis-profile=explore` draws new ones (and
# `--hypothesis-seed=N` replays a run of that profile).
settings.register_profile("deterministic", derandomize=True, print_blob=True)
settings.register_profile("explore", derandomize=False, print_blob=True)
settings.load_profile("deterministic")

#: ``../shared/data`` relative to the project root, unless the environment
#: variable ``SKLEARN_GPCA_DATA`` points elsewhere.
SHARED_DATA_DIR = Path(
    os.environ.get(
        "SKLEARN_GPCA_DATA", Path(__file__).parents[1].parent / "shared" / "data"
    )
)


def _require(path):
    if not path.is_dir():
        pytest.skip(f"real data not found at {path} (set SKLEARN_GPCA_DATA)")
    return path


@pytest.fixture(scope="session")
def shared_data_dir():
    """The shared data folder; skips the test when it is absent."""
    return _require(SHARED_DATA_DIR)


@pytest.fixture(scope="session")
def hopkins155_dir(shared_data_dir):
    """The Hopkins155 folder holding ``<name>/<name>_truth.mat``."""
    return _require(shared_data_dir / "hopkins155")


@pytest.fixture(scope="session")
def lowrank_dir(shared_data_dir):
    """The low-rank matrix folder holding ``<Name>/<name>.mat``."""
    return _require(shared_data_dir / "lowrank")


@pytest.fixture(scope="session")
def lab_scene():
    """150 lab tracks of 20 frames, 40 % missing, with outlier tracks.

    The screening sets some aside, so the candidates drawn from every track
    are judged too (the pooled path of ``segment_motions``).
    """
    X, y = make_tracks(
        scene="lab",
        n_frames=20,
        n_tracks=150,
        missing=0.4,
        outlier_fraction=0.05,
        random_state=0,
    )[:2]
    return X, y
