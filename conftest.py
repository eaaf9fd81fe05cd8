"""Skip the plotting doctests when matplotlib (the ``plot`` extra) is absent."""

# SPDX-License-Identifier: BSD-3-Clause

import importlib.util

if importlib.util.find_spec("matplotlib") is None:
    collect_ignore_glob = ["_*.py"]
