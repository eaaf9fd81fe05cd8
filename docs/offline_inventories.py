"""Inventories of scikit-learn, NumPy and SciPy written without the network.

intersphinx links a name such as :class:`sklearn.cluster.KMeans` to another
project's documentation through that project's inventory (``objects.inv``).
Instead of downloading them, :func:`write_inventories` writes them from the
installed packages: every public name of the listed modules, at the address
the project's documentation gives it, and the scikit-learn glossary terms
that docstrings use. The links then point to the projects' stable pages.
"""

# SPDX-License-Identifier: BSD-3-Clause

import importlib
import inspect
import warnings
import zlib

SKLEARN_MODULES = [
    "sklearn",
    "sklearn.base",
    "sklearn.cluster",
    "sklearn.compose",
    "sklearn.datasets",
    "sklearn.decomposition",
    "sklearn.exceptions",
    "sklearn.impute",
    "sklearn.manifold",
    "sklearn.metrics",
    "sklearn.mixture",
    "sklearn.model_selection",
    "sklearn.neighbors",
    "sklearn.pipeline",
    "sklearn.preprocessing",
    "sklearn.utils",
    "sklearn.utils.validation",
]

#: scikit-learn glossary terms that docstrings (ours and inherited) use.
SKLEARN_TERMS = [
    "clusterer",
    "components_",
    "cross-validation",
    "estimator",
    "feature_names_in_",
    "fit",
    "fit_predict",
    "fit_transform",
    "get_feature_names_out",
    "get_params",
    "inverse_transform",
    "labels_",
    "meta-estimator",
    "n_features_in_",
    "n_iter_",
    "n_jobs",
    "predict",
    "random_state",
    "sample_weight",
    "score",
    "scorer",
    "set_params",
    "transform",
    "transformer",
    "verbose",
]

NUMPY_MODULES = ["numpy", "numpy.linalg", "numpy.random", "numpy.ma"]
SCIPY_MODULES = [
    "scipy.io",
    "scipy.linalg",
    "scipy.optimize",
    "scipy.sparse",
    "scipy.sparse.linalg",
    "scipy.spatial",
    "scipy.special",
]


def public_objects(module_names):
    """``(qualified name, role)`` of the public names of the given modules."""
    found = {}
    for module_name in module_names:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            module = importlib.import_module(module_name)
        names = getattr(module, "__all__", None) or [
            n for n in dir(module) if not n.startswith("_")
        ]
        for name in names:
            try:
                obj = getattr(module, name, None)
            except ImportError:  # experimental names need an enabling import
                continue
            if inspect.ismodule(obj) or obj is None:
                continue
            if inspect.isclass(obj):
                role = "py:exception" if issubclass(obj, BaseException) else "py:class"
            elif callable(obj):
                role = "py:function"
            else:
                continue
            found.setdefault(f"{module_name}.{name}", role)
    return found


def write_inventory(path, project_name, project_version, entries):
    """Write a Sphinx objects.inv: ``entries`` of ``(name, role, uri)``."""
    header = (
        "# Sphinx inventory version 2\n"
        f"# Project: {project_name}\n"
        f"# Version: {project_version}\n"
        "# The remainder of this file is compressed using zlib.\n"
    )
    body = "".join(f"{name} {role} 1 {uri} -\n" for name, role, uri in entries)
    data = header.encode() + zlib.compress(body.encode())
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.exists() or path.read_bytes() != data:
        path.write_bytes(data)


def write_inventories(folder):
    """Inventories of scikit-learn, NumPy and SciPy; return intersphinx_mapping."""
    import numpy
    import scipy
    import sklearn

    # experimental estimators (IterativeImputer, HalvingGridSearchCV) are
    # public names of their modules once enabled
    from sklearn.experimental import (  # noqa: F401
        enable_halving_search_cv,
        enable_iterative_imputer,
    )

    sources = {
        "sklearn": (
            "https://scikit-learn.org/stable",
            sklearn.__version__,
            SKLEARN_MODULES,
            "modules/generated/{}.html#{}",
        ),
        "numpy": (
            "https://numpy.org/doc/stable",
            numpy.__version__,
            NUMPY_MODULES,
            "reference/generated/{}.html#{}",
        ),
        "scipy": (
            "https://docs.scipy.org/doc/scipy",
            scipy.__version__,
            SCIPY_MODULES,
            "reference/generated/{}.html#{}",
        ),
    }
    mapping = {}
    for key, (url, project_version, modules, page) in sources.items():
        entries = []
        for name, role in sorted(public_objects(modules).items()):
            # scikit-learn documents each name under its public module; the
            # package root re-exports only a few functions
            entries.append((name, role, page.format(name, name)))
        if key == "sklearn":
            entries += [
                (term, "std:term", f"glossary.html#term-{term}")
                for term in SKLEARN_TERMS
            ]
        path = folder / f"{key}-objects.inv"
        write_inventory(path, key, project_version, entries)
        mapping[key] = (url, str(path))
    return mapping
