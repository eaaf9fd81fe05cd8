"""Entry point of ``python -m sklearn_gpca``."""

# SPDX-License-Identifier: BSD-3-Clause

import sys

from sklearn_gpca._cli import main

if __name__ == "__main__":
    sys.exit(main())
