"""Collection rules for the doctests of the package (``--doctest-modules``).

The plotting doctests need matplotlib (the ``plot`` extra): without it they
are not collected. Kept out of the package, which ships no test code.
"""

# SPDX-License-Identifier: BSD-3-Clause

import importlib.util

collect_ignore_glob = []
if importlib.util.find_spec("matplotlib") is None:
    collect_ignore_glob = ["sklearn_gpca/plotting/_*.py"]
