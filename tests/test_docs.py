"""The documentation covers the public API and its build inputs exist."""

# SPDX-License-Identifier: BSD-3-Clause

import importlib
from pathlib import Path

import pytest

DOCS = Path(__file__).parents[1] / "docs"


@pytest.mark.parametrize(
    "module",
    [
        "sklearn_gpca",
        "sklearn_gpca.datasets",
        "sklearn_gpca.metrics",
        "sklearn_gpca.plotting",
    ],
)
def test_api_reference_lists_every_public_name(module):
    api = (DOCS / "api.rst").read_text()
    section = api.split(f".. currentmodule:: {module}\n", 1)[1].split("currentmodule")[
        0
    ]
    listed = {line.strip() for line in section.splitlines() if line.startswith("   ")}
    public = set(importlib.import_module(module).__all__) - {"__version__"}
    missing = sorted(public - listed)
    assert not missing, f"add {missing} to docs/api.rst under {module}"


def test_gallery_examples_exist():
    examples = sorted(p.name for p in (DOCS / "examples").glob("plot_*.py"))
    assert len(examples) >= 6
    assert (DOCS / "examples" / "README.rst").is_file()
