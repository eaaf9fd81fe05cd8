"""Shared pytest fixtures: location of the read-only real data."""

# SPDX-License-Identifier: BSD-3-Clause

import os
from pathlib import Path

import pytest

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
