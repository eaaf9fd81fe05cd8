"""Sphinx configuration of the sklearn_gpca documentation.

Builds offline, warnings as errors::

    sphinx-build -W --keep-going -b html docs docs/_build/html

Nothing is fetched: MathJax comes from the ``sphinx-mathjax-offline`` package
(copied into ``_static/mathjax``), and links to scikit-learn, NumPy and SciPy
come from inventories written here from the installed packages (see
:func:`write_inventories`). The figures of "How the results compare" are drawn
from ``benchmarks/results/`` by ``docs/make_result_figures.py`` at each build.
"""

# SPDX-License-Identifier: BSD-3-Clause

import sys
import warnings
from pathlib import Path

import sklearn_gpca

DOCS = Path(__file__).parent
sys.path.insert(0, str(DOCS))

from inherited_docstrings import clean_sklearn_docstrings
from offline_inventories import write_inventories

project = "sklearn_gpca"
author = "sklearn_gpca developers"
copyright = "sklearn_gpca developers, BSD-3-Clause"
version = release = sklearn_gpca.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.intersphinx",
    "sphinx.ext.mathjax",
    # MathJax 3 served from _static/mathjax: equations render offline
    "sphinx-mathjax-offline",
    "sphinx.ext.viewcode",
    "numpydoc",
    "sphinx_gallery.gen_gallery",
]

templates_path = ["_templates"]
exclude_patterns = ["_build", "examples", "**.ipynb_checkpoints"]
default_role = "literal"

autosummary_generate = True
autodoc_default_options = {"members": True, "inherited-members": True}
autodoc_typehints = "none"
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False

html_theme = "pydata_sphinx_theme"
html_static_path = ["_static"]
html_css_files = ["custom.css"]
html_title = f"sklearn_gpca {release}"
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    # the results page lists its sections itself and needs the width
    "secondary_sidebar_items": {
        "**": ["page-toc"],
        "user_guide/benchmarks": [],
    },
}
html_show_sourcelink = False

sphinx_gallery_conf = {
    "examples_dirs": "examples",
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "download_all_examples": False,
    "remove_config_comments": True,
    # the introductory pipeline first (docs/gallery_order.py)
    "within_subsection_order": "gallery_order.ExampleOrder",
    "doc_module": ("sklearn_gpca",),
    "backreferences_dir": "gen_modules/backreferences",
    "reference_url": {"sklearn_gpca": None},
    "matplotlib_animations": False,
    "abort_on_example_error": True,
    "show_memory": False,
    "image_scrapers": ("matplotlib",),
    # the execution-times page loads its table script from a CDN
    "write_computation_times": False,
}

# Examples may warn (e.g. a baseline's ConvergenceWarning); that is their
# output, not a documentation error.
warnings.filterwarnings("ignore", category=UserWarning, message="Matplotlib")


# Docstrings write attribute shapes such as ``(n_features_in_,)`` without
# quotes; in reST the trailing underscore makes them links, so give them a target.
rst_epilog = """
.. _n_features_in: https://scikit-learn.org/stable/glossary.html#term-n_features_in_
"""

# Links to scikit-learn, NumPy and SciPy without the network: inventories
# written from the installed packages (docs/offline_inventories.py).
intersphinx_mapping = write_inventories(DOCS / "_build" / "inventories")


def draw_result_figures(app):
    """The figures of the benchmark page, from the committed results."""
    import make_result_figures

    make_result_figures.main(DOCS / "user_guide" / "_figures")


def setup(app):
    # before numpydoc (priority 500) parses the sections
    app.connect("autodoc-process-docstring", clean_sklearn_docstrings, priority=400)
    app.connect("builder-inited", draw_result_figures)
