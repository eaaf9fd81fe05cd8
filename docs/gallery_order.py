"""The order of the examples in the gallery: a first pipeline, then the rest.

``sphinx_gallery_conf["within_subsection_order"]`` names this class by its
qualified name (``gallery_order.ExampleOrder``) so the configuration pickles.
"""

# SPDX-License-Identifier: BSD-3-Clause

#: Examples in reading order; any other example follows, by file name.
ORDER = [
    "plot_synthetic_pipeline.py",
    "plot_figure1_hopkins.py",
    "plot_figure2_similarity.py",
    "plot_missing_data.py",
    "plot_cluster_comparison.py",
    "plot_grid_search.py",
]


class ExampleOrder:
    """Sort key: position in :data:`ORDER`, then file name."""

    def __init__(self, src_dir):
        self.src_dir = src_dir

    def __call__(self, filename):
        rank = ORDER.index(filename) if filename in ORDER else len(ORDER)
        return (rank, filename)

    def __repr__(self):
        return f"<{self.__class__.__name__}>"
