"""Where the real datasets are looked for, without creating any folder."""

# SPDX-License-Identifier: BSD-3-Clause

import os
from pathlib import Path


def default_data_home():
    """``$SKLEARN_GPCA_DATA``, else scikit-learn's data home, not created.

    scikit-learn's data home is ``$SCIKIT_LEARN_DATA`` or
    ``~/scikit_learn_data``, as in :func:`sklearn.datasets.get_data_home`,
    which, unlike this function, creates the folder: a failed load must not
    leave one behind.
    """
    env = os.environ.get("SKLEARN_GPCA_DATA")
    if env:
        return Path(env).expanduser()
    sklearn_home = os.environ.get("SCIKIT_LEARN_DATA", "~/scikit_learn_data")
    return Path(sklearn_home).expanduser()
