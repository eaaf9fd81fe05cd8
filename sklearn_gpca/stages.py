"""The stages of :func:`sklearn_gpca.gpca`, as public building blocks.

Each stage is a pure function, arrays in and arrays out; :func:`~sklearn_gpca.
gpca` chains them (``docs/user_guide/code_organisation.rst`` draws the data
flow) and :class:`~sklearn_gpca.GPCAClustering` stores what it returns.
Benchmarks and new segmentation routes call them directly:

1. vanishing polynomials: :func:`vanishing_polynomials`, :func:`unit_gradients`;
2. normals at each point: :func:`sign_invariant_neighbors`,
   :func:`point_normal_bases`;
3. affinity candidates: :func:`candidate_graphs`, :func:`spectral_candidates`
   (a candidate is any labelling of the points);
4. refinement: :func:`~sklearn_gpca.k_subspaces`;
5. selection: :func:`select_candidate`, :func:`normalized_cut`;
6. extension from a subsample: :func:`extension_neighbors`,
   :func:`extend_labels`;
7. after the pipeline, K-subspaces on the raw tracks' observed entries:
   :func:`refine_full_space`, or one anchored reassignment
   :func:`reassign_full_space`;

and the per-cluster subspaces: :func:`fit_subspaces`, :func:`sine_residuals`,
:func:`unit_rows`.
"""

# SPDX-License-Identifier: BSD-3-Clause

from sklearn_gpca._affinity import normalized_cut, sign_invariant_neighbors
from sklearn_gpca._candidates import candidate_graphs, spectral_candidates
from sklearn_gpca._extension import extend_labels, extension_neighbors
from sklearn_gpca._full_space import reassign_full_space, refine_full_space
from sklearn_gpca._normals import point_normal_bases
from sklearn_gpca._polynomials import unit_gradients, vanishing_polynomials
from sklearn_gpca._rows import unit_rows
from sklearn_gpca._selection import select_candidate
from sklearn_gpca._subspaces import fit_subspaces, sine_residuals

__all__ = [
    "candidate_graphs",
    "extend_labels",
    "extension_neighbors",
    "fit_subspaces",
    "normalized_cut",
    "point_normal_bases",
    "reassign_full_space",
    "refine_full_space",
    "select_candidate",
    "sign_invariant_neighbors",
    "sine_residuals",
    "spectral_candidates",
    "unit_gradients",
    "unit_rows",
    "vanishing_polynomials",
]
