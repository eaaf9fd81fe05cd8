"""Sphinx configuration of the sklearn_gpca documentation.

Build offline, warnings as errors::

    sphinx-build -W --keep-going -b html docs docs/_build/html

Set ``SKLEARN_GPCA_INTERSPHINX=1`` to link to the scikit-learn, NumPy, SciPy
and matplotlib documentation (needs the network).
"""

# SPDX-License-Identifier: BSD-3-Clause

import os
import re
import warnings
from pathlib import Path

import sklearn_gpca

DOCS = Path(__file__).parent
ROOT = DOCS.parent

project = "sklearn_gpca"
author = "sklearn_gpca developers"
copyright = "sklearn_gpca developers, BSD-3-Clause"
version = release = sklearn_gpca.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "numpydoc",
    "sphinx_gallery.gen_gallery",
]
if os.environ.get("SKLEARN_GPCA_INTERSPHINX") == "1":
    extensions.append("sphinx.ext.intersphinx")
    intersphinx_mapping = {
        "python": ("https://docs.python.org/3", None),
        "numpy": ("https://numpy.org/doc/stable", None),
        "scipy": ("https://docs.scipy.org/doc/scipy", None),
        "sklearn": ("https://scikit-learn.org/stable", None),
        "matplotlib": ("https://matplotlib.org/stable", None),
    }

templates_path = ["_templates"]
exclude_patterns = ["_build", "examples", "**.ipynb_checkpoints", "user_guide/_*.rst"]
default_role = "literal"

autosummary_generate = True
autodoc_default_options = {"members": True, "inherited-members": True}
autodoc_typehints = "none"
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False

html_theme = "pydata_sphinx_theme"
html_static_path = ["_static"]
html_title = f"sklearn_gpca {release}"
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
}
html_show_sourcelink = False

sphinx_gallery_conf = {
    "examples_dirs": "examples",
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "doc_module": ("sklearn_gpca",),
    "backreferences_dir": "gen_modules/backreferences",
    "reference_url": {"sklearn_gpca": None},
    "matplotlib_animations": False,
    "abort_on_example_error": True,
    "show_memory": False,
    "image_scrapers": ("matplotlib",),
}

# Examples may warn (e.g. a baseline's ConvergenceWarning); that is their
# output, not a documentation error.
warnings.filterwarnings("ignore", category=UserWarning, message="Matplotlib")


# Docstrings write attribute shapes such as ``(n_features_in_,)`` without
# quotes; in reST the trailing underscore makes them links, so give them a target.
rst_epilog = """
.. _n_features_in: https://scikit-learn.org/stable/glossary.html#term-n_features_in_
"""

_REF = re.compile(r":ref:`([^`<]*?)\s*(?:<[^>]*>)?`")


def strip_sklearn_refs(app, what, name, obj, options, lines):
    """Inherited scikit-learn docstrings link to labels of scikit-learn's docs.

    Offline those labels do not exist; keep their text.
    """
    module = getattr(obj, "__module__", "") or ""
    if module.startswith("sklearn."):
        lines[:] = [_REF.sub(lambda m: m.group(1) or "", line) for line in lines]


def setup(app):
    app.connect("autodoc-process-docstring", strip_sklearn_refs)


def write_benchmark_tables():
    """Include every ``benchmarks/results/*.md`` verbatim, so the docs stay in sync."""
    titles = {
        "hopkins155.md": "Hopkins155, complete data",
        "hopkins155_missing.md": "Hopkins155 with occlusions",
        "ablation.md": "Ablation of GPCAClustering's components",
        "power_factorization.md": "PowerFactorization against the SVD",
    }
    results = ROOT / "benchmarks" / "results"
    files = sorted(
        results.glob("*.md"),
        key=lambda p: (list(titles).index(p.name) if p.name in titles else 99, p),
    )
    lines = []
    for path in files:
        title = titles.get(path.name, path.stem.replace("_", " "))
        lines += [
            title,
            "-" * len(title),
            "",
            f"From ``benchmarks/results/{path.name}``:",
            "",
            f".. literalinclude:: ../../benchmarks/results/{path.name}",
            "   :language: none",
            "",
        ]
    if not files:
        lines.append("No benchmark results were found in ``benchmarks/results``.")
    target = DOCS / "user_guide" / "_benchmark_tables.rst"
    text = "\n".join(lines) + "\n"
    if not target.exists() or target.read_text() != text:
        target.write_text(text)


write_benchmark_tables()
