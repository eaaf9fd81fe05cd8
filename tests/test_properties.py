"""Invariance properties on data drawn by hypothesis (not only a seed).

The strategies draw the factors, singular values, masks, normals, points,
scales and permutations themselves, so that a failure shrinks to a small
matrix that can be read.
"""

# SPDX-License-Identifier: BSD-3-Clause

import warnings

import numpy as np
from _hyperplanes import draw_points_on_hyperplanes
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from numpy.testing import assert_allclose
from sklearn.exceptions import ConvergenceWarning

from sklearn_gpca import GPCAClustering, PowerFactorization
from sklearn_gpca.metrics import misclassification_rate

FINITE = st.floats(-1.0, 1.0, allow_nan=False, allow_subnormal=False)


@st.composite
def incomplete_low_rank(draw):
    """``(X, rank)``: an exactly low-rank matrix with drawn gaps.

    ``X = Q_B diag(s) Q_A^T`` with ``Q_B``, ``Q_A`` the orthonormal factors of
    drawn matrices and distinct drawn singular values, so the rank is exact
    and the components unique; entries are removed where a drawn uniform
    number falls below a drawn fraction, as long as the completion stays
    unique.
    """
    rank = draw(st.integers(1, 4))
    n_features = draw(st.integers(rank + 3, 14))
    n_samples = draw(st.integers(3 * n_features, 60))
    B = draw(arrays(np.float64, (n_samples, rank), elements=FINITE))
    A = draw(arrays(np.float64, (n_features, rank), elements=FINITE))
    # Independent columns: a drawn matrix with repeated columns is rejected.
    assume(np.linalg.matrix_rank(B) == rank and np.linalg.matrix_rank(A) == rank)
    # Singular values 1.5 to 3 times apart: tied ones leave the components
    # free to rotate, and then no order of rows gives the same basis.
    ratios = draw(arrays(np.float64, rank - 1, elements=st.floats(1.5, 3.0)))
    s = np.cumprod(np.r_[1.0, ratios])[::-1]
    Q_B, Q_A = np.linalg.qr(B)[0], np.linalg.qr(A)[0]
    X = (Q_B * s) @ Q_A.T
    fraction = draw(st.floats(0.0, 0.3))
    uniform = draw(
        arrays(np.float64, X.shape, elements=st.floats(0.0, 1.0, exclude_max=True))
    )
    observed = uniform >= fraction
    # A unique completion: the observed entries of every row determine its
    # coordinates, and those of every column its basis vector (else the
    # answer depends on rounding, issue 13).
    for factor, mask in ((Q_A, observed), (Q_B, observed.T)):
        for seen in mask:
            assume(seen.sum() >= rank)
            assume(np.linalg.svd(factor[seen], compute_uv=False)[rank - 1] > 0.05)
    return np.where(observed, X, np.nan), rank


@settings(max_examples=25, deadline=None)
@given(data=incomplete_low_rank(), order_seed=st.data())
def test_power_factorization_permuting_rows_permutes_the_output(data, order_seed):
    X, rank = data
    order = np.array(order_seed.draw(st.permutations(range(X.shape[0]))))
    # Run far below the default tol, so that the two runs do not stop one
    # iteration apart (rounding differs with the order of the rows). On exactly
    # low-rank data the residual falls geometrically to zero, so the relative
    # decrease may never reach tol: then both runs stop at max_iter, equally.
    pf = PowerFactorization(rank, tol=1e-12, max_iter=2000, random_state=0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        Z = pf.fit_transform(X)
        Z_permuted = pf.fit_transform(X[order])
    assert_allclose(Z_permuted, Z[order], atol=1e-5 * np.abs(Z).max())


@settings(max_examples=25, deadline=None)
@given(data=incomplete_low_rank())
def test_power_factorization_fits_exactly_low_rank_data(data):
    X, rank = data
    pf = PowerFactorization(rank, whiten=False, random_state=0).fit(X)
    observed = ~np.isnan(X)
    fit = pf.inverse_transform(pf.transform(X))
    assert pf.reconstruction_err_ < 1e-5
    assert_allclose(fit[observed], X[observed], atol=1e-5)


@st.composite
def separable_hyperplanes(draw):
    """``(X, y)``: points on 2 hyperplanes of ``R^4``.

    The normals are coordinate axes moved by drawn perturbations (norm at
    most 0.3, so they stay more than 50 degrees apart) and turned by a drawn
    rotation. Each hyperplane gets 25 points: a fixed design of 25 distinct
    points spanning it, moved by drawn coefficients. Points within
    a sine distance of 0.1 of another hyperplane are ambiguous and left out.
    """
    # Two hyperplanes only: with three, hypothesis finds draws (about 21
    # points each, normals over 50 degrees apart, noise-free) on which a
    # 1e-9 perturbation flips the default GPCAClustering between its initial
    # candidates and 21 % of the points are misclassified. Reported (issue
    # 13); widen to st.integers(2, 3) once it is fixed.
    n_clusters = 2
    half = st.floats(-0.15, 0.15)
    normals = np.eye(4)[:n_clusters] + draw(
        arrays(np.float64, (n_clusters, 4), elements=half)
    )
    rotation = np.linalg.qr(draw(arrays(np.float64, (4, 4), elements=FINITE)))[0]
    normals = normals @ rotation.T
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    # 25 distinct directions: copies of a point are another matter (issue 13)
    design = np.random.RandomState(0).standard_normal((25, 3))
    X, y = draw_points_on_hyperplanes(draw, normals, design, FINITE)
    assume(np.bincount(y, minlength=n_clusters).min() >= 12)
    return X, y


@settings(max_examples=20, deadline=None)
@given(
    data=separable_hyperplanes(),
    log_scale=st.floats(-3.0, 3.0),
    permutation=st.data(),
)
def test_gpca_segments_drawn_hyperplanes_whatever_the_scale_and_order(
    data, log_scale, permutation
):
    X, y = data
    order = np.array(permutation.draw(st.permutations(range(X.shape[0]))))
    model = GPCAClustering(int(y.max()) + 1, random_state=0)
    labels = model.fit_predict(X)
    scaled = model.fit_predict(10.0**log_scale * X[order])
    assert misclassification_rate(y, labels) == 0.0
    assert misclassification_rate(y[order], scaled) == 0.0
