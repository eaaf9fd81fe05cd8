"""The Gauss-Newton matrix ``J^T J`` of variable projection, assembled densely.

The matrix-free solver of :mod:`sklearn_gpca._varpro` uses it as an exact
preconditioner when the ``(n_features r)``-square system is cheaper to
factorise than the conjugate-gradient iterations it saves (Dinosaur-like
problems: few features, ill-conditioned).
"""

# SPDX-License-Identifier: BSD-3-Clause

import itertools

import numpy as np
from scipy import sparse

from sklearn_gpca._chunks import row_chunks

# Floats per temporary of shape (rows in a chunk, n_features, n_features) in
# the dense accumulation of J^T J: 2**22 float64 are 32 MiB, whatever the
# number of rows.
_CHUNK_FLOATS = 2**22
# Pairs of observed entries of a row per chunk in the sparse accumulation,
# and the most pairs whose indices are kept from one iteration to the next.
_CHUNK_PAIRS = 2**19
_CACHED_PAIRS = 2**22
# The sparse accumulation is used when the pairs of observed entries in a
# row are fewer than this fraction of all pairs of columns.
_SPARSE_DENSITY = 0.3


def _is_sparse(pairs, n_features):
    return pairs.sum() < _SPARSE_DENSITY * pairs.size * n_features**2 / 2


def factorisation_flops(mask, r):
    """Floating-point operations to assemble and factorise the dense matrix."""
    n_features = mask.shape[1]
    counts = mask.sum(axis=1)
    pairs = counts * (counts + 1) / 2
    assembly = (
        pairs.sum() if _is_sparse(pairs, n_features) else pairs.size * n_features**2
    )
    return 2 * r * r * assembly + (n_features * r) ** 3 / 3


class GaussNewtonMatrix:
    """Accumulation of ``J^T J`` over the observed entries.

    Row ``i`` has residual ``e_i = P_i x_i`` with ``P_i`` the projector on
    the orthogonal complement of ``diag(m_i) V`` among its observed entries,
    ``P_i = diag(m_i) - diag(m_i) V G_i^{-1} V^T diag(m_i)``. Its Ruhe-Wedin
    (RW2) Jacobian with respect to ``V`` is ``-P_i (u_i^T kron I)``, so

    ``J^T J = sum_i (u_i u_i^T) kron P_i``

    (the gradient ``-J^T e = E^T U`` is cheap and formed by the solver).

    The identity part of ``P_i`` gives the block diagonal
    ``sum_i m_ij u_i u_i^T``; the other part is nonzero only for pairs
    ``(j, l)`` of columns both observed in row ``i``. With sparse masks
    (tracks seen in a few frames) these pairs are far fewer than
    ``n_samples * n_features**2`` and are summed as a sparse product.
    """

    def __init__(self, mask, r):
        self.mask = mask
        self.r = r
        n_samples, n_features = mask.shape
        counts = mask.sum(axis=1).astype(np.int64)
        pairs = counts * (counts + 1) // 2
        self.sparse = _is_sparse(pairs, n_features)
        self.chunks = []
        if self.sparse:
            bounds = [0]
            cumulative = np.cumsum(pairs)
            while bounds[-1] < n_samples:
                done = cumulative[bounds[-1] - 1] if bounds[-1] else 0
                stop = np.searchsorted(cumulative, done + _CHUNK_PAIRS, side="right")
                bounds.append(min(max(stop, bounds[-1] + 1), n_samples))
            self.chunks = [slice(a, b) for a, b in itertools.pairwise(bounds)]
            self.cache = {} if pairs.sum() <= _CACHED_PAIRS else None

    def _pairs(self, k):
        if self.cache is not None and k in self.cache:
            return self.cache[k]
        rows_slice = self.chunks[k]
        m = self.mask[rows_slice]
        n_features = m.shape[1]
        rows, cols = np.nonzero(m)
        counts = np.bincount(rows, minlength=m.shape[0])
        starts = np.concatenate(([0], np.cumsum(counts)[:-1]))
        # entry e pairs with the entries of its row at or after it
        later = (starts + counts)[rows] - np.arange(rows.size)
        first = np.repeat(np.arange(rows.size), later)
        offsets = np.arange(first.size) - np.repeat(np.cumsum(later) - later, later)
        second = first + offsets
        key = cols[first] * n_features + cols[second]
        product = sparse.coo_matrix(
            (np.arange(1.0, first.size + 1), (key, rows[first])),
            shape=(n_features * n_features, m.shape[0]),
        ).tocsr()
        # the CSR arrays hold the pairs in another order: find it once
        order = product.data.astype(np.intp) - 1
        result = (rows, cols, first[order], second[order], product)
        if self.cache is not None:
            self.cache[k] = result
        return result

    def assemble(self, V, U, inv_gram):
        """``J^T J`` indexed by ``j * r + k`` for ``V[j, k]``."""
        n_samples, n_features = self.mask.shape
        r = self.r
        UU = (U[:, :, None] * U[:, None, :]).reshape(n_samples, r * r)
        if self.sparse:
            upper = np.zeros((n_features * n_features, r * r))
            for k, rows_slice in enumerate(self.chunks):
                rows, cols, first, second, product = self._pairs(k)
                rows = rows + rows_slice.start
                # K_i[j, l] = y_j^T G_i^{-1} y_l for the rows y_j of V observed
                # in row i, one value per pair (first, second) of entries
                Y = V[cols]
                Z = np.einsum("ea,eab->be", Y, inv_gram[rows])
                Y = Y.T.copy()
                data = Z[0][first] * Y[0][second]
                for a in range(1, r):
                    data += Z[a][first] * Y[a][second]
                product.data = -data
                upper += product @ UU[rows_slice]
            upper = upper.reshape(n_features, n_features, r * r)
            hessian4 = upper + upper.transpose(1, 0, 2)
            idx = np.arange(n_features)
            hessian4[idx, idx] -= upper[idx, idx]
        else:
            hessian4 = np.zeros((n_features, n_features, r * r))
            # each row holds an (n_features, n_features) block
            size = max(1, _CHUNK_FLOATS // (n_features * n_features))
            for rows in row_chunks(n_samples, size):
                m = self.mask[rows]
                VC = np.einsum("jk,ikl->ijl", V, inv_gram[rows])
                K = VC @ V.T
                K *= m[:, :, None]
                K *= m[:, None, :]
                hessian4 -= (K.reshape(K.shape[0], -1).T @ UU[rows]).reshape(
                    hessian4.shape
                )
        idx = np.arange(n_features)
        hessian4[idx, idx] += self.mask.T @ UU
        return (
            hessian4.reshape(n_features, n_features, r, r)
            .transpose(0, 2, 1, 3)
            .reshape(n_features * r, n_features * r)
        )
