"""PowerFactorization: project trajectories with missing entries to R^r."""

# SPDX-License-Identifier: BSD-3-Clause

import warnings
from numbers import Integral, Real

import numpy as np
from sklearn.base import (
    BaseEstimator,
    ClassNamePrefixFeaturesOutMixin,
    TransformerMixin,
    _fit_context,
)
from sklearn.exceptions import ConvergenceWarning
from sklearn.utils import check_array, check_random_state
from sklearn.utils._param_validation import Interval, StrOptions
from sklearn.utils.extmath import svd_flip
from sklearn.utils.validation import check_is_fitted, validate_data

from sklearn_gpca import _als, _varpro
from sklearn_gpca._als import squared_residual
from sklearn_gpca._completion_rank import (
    max_completion_rank,
    select_completion_rank,
)
from sklearn_gpca._least_squares import fit_rows
from sklearn_gpca._missing import describe_indices, masked_to_nan


class PowerFactorization(
    ClassNamePrefixFeaturesOutMixin, TransformerMixin, BaseEstimator
):
    """Rank-r factorisation of trajectories with missing entries.

    Fits ``X ~ Z diag(s) V`` minimising the squared error over the observed
    entries of ``X`` (equation (8) of Vidal & Hartley, 2004) with the
    PowerFactorization iteration, and projects trajectories (rows of ``X``,
    possibly incomplete, possibly new) to their ``n_components`` coordinates
    ``Z``. With complete data the fitted subspace is the truncated SVD's.

    The data are never centred: motion subspaces are linear subspaces through
    the origin.

    Parameters
    ----------
    n_components : int, default=5
        Rank ``r`` of the factorisation, the dimension of the projected
        space. The paper uses 5: each rigid motion spans at most 4
        dimensions, and a generic projection to 5 keeps them apart.

    whiten : bool, default=True
        If True, coordinates are those of the paper's projected matrix
        ``\\hat W``: the rows of ``V`` in the SVD ``X^T = U D V^T``, that is
        ``X`` projected on the components and divided by the singular
        values. If False, they are the plain projections on the components
        (in the units of ``X``).

    solver : {"varpro", "als"}, default="varpro"
        Minimiser of the squared residual over the observed entries when
        entries are missing. "als" is the paper's PowerFactorization
        (alternating least squares); "varpro" is variable projection with
        damped Gauss-Newton steps, which reaches the global optimum far
        more often on real tracks. See Notes. With complete data both use
        the power method.

    completion_rank : int, "auto" or None, default=None
        Rank ``q >= n_components`` of the factorisation fitted to the
        observed entries; trajectories are completed at rank ``q`` and then
        projected on the leading ``n_components`` directions. None fits at
        ``n_components`` (the paper). ``n`` motions span up to ``4 n``
        dimensions, so with missing entries a rank-5 fit cannot reproduce
        the projection of the complete data; an int (e.g. ``4 n``) or
        "auto" — the smallest rank within 5 % of the best error on held-out
        observed entries, searched from ``n_components`` up to
        ``3 n_components`` — fixes that. With complete training data "auto"
        is ``n_components`` (the projection is then exact at any rank).

    n_init : int, default=10
        Maximum number of random starts. Starts stop early once two of them
        reach the same lowest residual (to a relative ``1e-4``); the best
        fit is kept.

    max_iter : int, default=500
        Maximum number of iterations per start: alternations for "als",
        Levenberg-Marquardt trials for "varpro".

    tol : float, default=1e-7
        Stop when the squared residual over the observed entries decreases
        by less than ``tol`` times its value in one (accepted) iteration.

    max_init_samples : int or None, default=5000
        With missing entries and more (well-observed) rows than this, the
        random starts run on a uniform random subsample of this many rows;
        the best of them is then polished on all rows by alternating least
        squares until ``tol`` (beyond the paper; see Notes). None runs the
        starts on all rows. Time is then linear in ``n_samples`` with a
        constant set by the subsample.

    random_state : int, RandomState instance or None, default=None
        Seed of the random starting bases and of the subsample.

    verbose : int, default=0
        Print the residual at every iteration when positive.

    Attributes
    ----------
    components_ : ndarray of shape (n_components, n_features)
        Orthonormal basis of the fitted subspace of ``R^{n_features}``,
        ordered by decreasing singular value.

    singular_values_ : ndarray of shape (n_components,)
        Singular values of the fitted rank-r matrix.

    completion_rank_ : int
        Rank ``q`` of the fitted factorisation.

    completion_components_ : ndarray of shape (q, n_features)
        Orthonormal basis of the rank-q fit (``q = completion_rank_``);
        ``components_`` are its first ``n_components`` rows.

    completion_singular_values_ : ndarray of shape (q,)
        Singular values of the rank-q fit.

    completion_errors_ : dict
        Held-out root mean square error of each rank tried when
        ``completion_rank="auto"`` (empty otherwise).

    n_iter_ : int
        Number of iterations run by the start that was kept.

    n_polish_iter_ : int
        Number of alternating least-squares iterations polishing the kept
        start on all rows (0 when the starts ran on all rows).

    n_init_ : int
        Number of random starts run.

    reconstruction_err_ : float
        Root mean square residual of the rank-q fit over the observed
        entries of the training data, in the units of ``X``.

    n_features_in_ : int
        Number of features seen during :term:`fit`.

    feature_names_in_ : ndarray of shape (`n_features_in_`,)
        Names of features seen during :term:`fit`. Defined only when `X`
        has feature names that are all strings.

    See Also
    --------
    sklearn.decomposition.PCA : Projection of complete, centred data.
    sklearn.decomposition.TruncatedSVD : Projection of complete data.
    sklearn.impute.IterativeImputer : Imputation of missing entries.

    Notes
    -----
    With ``W = X^T`` the ``2F x P`` measurement matrix of the paper, the
    iteration alternates (1) the least-squares ``B`` given ``A`` over the
    observed entries, one small ``r x r`` system per trajectory, (2) the
    orthonormalisation of ``B``, (3) the least-squares ``A`` given ``B``, one
    system per feature. All systems are solved in one batched call, so a
    step costs ``O(P F r^2)``. With complete data (1) and (3) reduce to the
    products ``W^T A`` and ``W B`` of the power method, which converges to the
    best rank-r approximation at rate ``(s_{r+1} / s_r)^k``.

    With missing entries, ``solver="als"`` runs that iteration, which can
    crawl for thousands of iterations along flat valleys and stop far from
    the optimum. ``solver="varpro"`` eliminates the coordinates exactly
    instead: for a basis ``A`` every row's coordinates are its least-squares
    fit, so the residual is a function of ``A`` alone (variable projection,
    Golub & Pereyra; the Wiberg algorithm). It is minimised by
    Levenberg-Marquardt on the ``n_features x r`` entries of ``A``, with the
    Ruhe-Wedin (RW2) approximation of the Jacobian, steps orthogonal to the
    gauge directions ``A K`` and ``A`` re-orthonormalised after each step
    (Hong & Fitzgibbon, 2015). ``J^T J`` is accumulated over chunks of rows,
    so time and memory grow linearly with ``n_samples``; one iteration
    costs ``O(P n_features^2 r^2)`` plus the solve of an
    ``n_features r``-square system. Random starts still end in local minima
    on hard problems (about half the time on the Dinosaur sequence), hence
    the restarts of ``n_init``, stopped once the best residual has been
    reached twice (Hong & Fitzgibbon's meta-algorithm).

    Large ``n_samples`` (beyond the paper). A Levenberg-Marquardt trial
    costs about 9 s on a million rows of 20 features, and the restarts and
    races run a hundred or more of them. Above ``max_init_samples`` rows they
    run on a random subsample; the winning basis is then refined on all rows
    by the paper's alternating least squares (``O(P n_features r^2)`` per
    iteration, about 1 s per million rows), which from a start that near
    the optimum converges in a few iterations to a stationary point of the
    full residual (8). The subsample must observe every column at least
    ``q`` times, otherwise all rows are used. Memory stays ``O(P n_features)``:
    the per-row ``r x r`` systems are solved in chunks of rows.

    ``transform`` solves the same per-row least-squares problem against the
    fitted rank-q basis and keeps the leading ``n_components`` coordinates,
    so training and new trajectories are projected alike. A row observed in
    ``k < q`` entries is fitted on the leading ``k`` directions; rows need at
    least ``n_components`` observed entries. Only rows observed in at least
    ``q`` entries inform the basis.

    References
    ----------
    R. Vidal and R. Hartley, "Motion Segmentation with Missing Data using
    PowerFactorization and GPCA", CVPR 2004.

    J. H. Hong and A. Fitzgibbon, "Secrets of Matrix Factorization:
    Approximations, Numerics, Manifold Optimization and Random Restarts",
    ICCV 2015.

    R. Hartley and F. Schaffalitzky, "PowerFactorization: 3D reconstruction
    with missing or uncertain data", Australia-Japan Advanced Workshop on
    Computer Vision, 2003.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca import PowerFactorization
    >>> rng = np.random.RandomState(0)
    >>> X = rng.standard_normal((100, 3)) @ rng.standard_normal((3, 20))
    >>> X[rng.rand(*X.shape) < 0.2] = np.nan
    >>> pf = PowerFactorization(n_components=3, random_state=0)
    >>> Z = pf.fit_transform(X)
    >>> Z.shape
    (100, 3)
    >>> bool(np.nanmax(np.abs(pf.inverse_transform(Z) - X)) < 1e-6)
    True
    """

    _parameter_constraints: dict = {
        "n_components": [Interval(Integral, 1, None, closed="left")],
        "whiten": ["boolean"],
        "solver": [StrOptions({"varpro", "als"})],
        "completion_rank": [
            Interval(Integral, 1, None, closed="left"),
            StrOptions({"auto"}),
            None,
        ],
        "n_init": [Interval(Integral, 1, None, closed="left")],
        "max_iter": [Interval(Integral, 1, None, closed="left")],
        "tol": [Interval(Real, 0, None, closed="left")],
        "max_init_samples": [Interval(Integral, 1, None, closed="left"), None],
        "random_state": ["random_state"],
        "verbose": ["verbose"],
    }

    def __init__(
        self,
        n_components=5,
        *,
        whiten=True,
        solver="varpro",
        completion_rank=None,
        n_init=10,
        max_iter=500,
        tol=1e-7,
        max_init_samples=5000,
        random_state=None,
        verbose=0,
    ):
        self.n_components = n_components
        self.whiten = whiten
        self.solver = solver
        self.completion_rank = completion_rank
        self.n_init = n_init
        self.max_iter = max_iter
        self.tol = tol
        self.max_init_samples = max_init_samples
        self.random_state = random_state
        self.verbose = verbose

    @_fit_context(prefer_skip_nested_validation=True)
    def fit(self, X, y=None):
        """Fit the rank-r subspace to the observed entries of ``X``.

        Parameters
        ----------
        X : array-like or masked array of shape (n_samples, n_features)
            Trajectories, one per row; missing entries are NaN (or masked).

        y : Ignored
            Not used, present for API consistency by convention.

        Returns
        -------
        self : object
            Fitted estimator.
        """
        X = validate_data(
            self,
            masked_to_nan(X),
            dtype=[np.float64, np.float32],
            ensure_all_finite="allow-nan",
        )
        n_samples, n_features = X.shape
        if self.n_components > n_features:
            raise ValueError(
                f"n_components={self.n_components} must be at most "
                f"n_features={n_features}."
            )
        if self.n_components > n_samples:
            raise ValueError(
                f"n_components={self.n_components} must be at most "
                f"n_samples={n_samples}."
            )
        X0, mask = _zero_filled(X)
        if mask is not None:
            self._check_observed(mask, axis=1, what="row")
            self._check_observed(mask, axis=0, what="column")

        solve = _varpro.power_factorization
        if self.solver == "als":
            solve = _als.power_factorization
        random_state = check_random_state(self.random_state)
        rank, self.completion_errors_ = self._choose_rank(X0, mask, random_state)
        # Rows observed in fewer than `rank` entries cannot inform a rank-q
        # basis; they are projected afterwards at the rank they support.
        fitted_rows = slice(None) if mask is None else mask.sum(axis=1) >= rank
        X_fit = X0[fitted_rows]
        mask_fit = None if mask is None else mask[fitted_rows]
        X_start, mask_start = X_fit, mask_fit
        subsample = self._subsample(mask_fit, rank, random_state)
        if subsample is not None:
            X_start, mask_start = X_fit[subsample], mask_fit[subsample]
        best, self.n_init_ = self._best_start(
            solve, X_start, mask_start, rank, random_state
        )
        _, A, self.n_iter_, converged = best
        self.n_polish_iter_ = 0
        if subsample is not None:
            self._log(f"polishing the best start on all {X_fit.shape[0]} rows")
            _, A, self.n_polish_iter_, converged = _als.power_factorization(
                X_fit,
                mask_fit,
                rank,
                max_iter=self.max_iter,
                tol=self.tol,
                random_state=random_state,
                log=self._log,
                init=A,
            )
        if not converged:
            warnings.warn(
                f"PowerFactorization did not converge in max_iter={self.max_iter}"
                " iterations; increase max_iter or tol.",
                ConvergenceWarning,
                stacklevel=2,
            )
        # B has orthonormal columns, so the SVD of the fit B A^T is B u s vt
        # with u s vt the SVD of the small rank x n_features matrix A^T.
        u, s, vt = np.linalg.svd(A.T, full_matrices=False)
        u, vt = svd_flip(u, vt, u_based_decision=False)
        self.completion_rank_ = rank
        self.completion_components_ = vt.astype(X.dtype, copy=False)
        self.completion_singular_values_ = s.astype(X.dtype, copy=False)
        self.components_ = self.completion_components_[: self.n_components]
        self.singular_values_ = self.completion_singular_values_[: self.n_components]

        residual = X0 - self._coordinates(X0, mask) @ self._completion_basis()
        if mask is not None:
            residual *= mask
        n_observed = X0.size if mask is None else mask.sum()
        self.reconstruction_err_ = float(np.sqrt(np.sum(residual**2) / n_observed))
        return self

    def transform(self, X):
        """Project trajectories, complete or not, to the fitted subspace.

        Parameters
        ----------
        X : array-like or masked array of shape (n_samples, n_features)
            Trajectories, one per row; missing entries are NaN (or masked).
            Each row needs at least ``n_components`` observed entries.

        Returns
        -------
        Z : ndarray of shape (n_samples, n_components)
            Least-squares coordinates of each row over its observed entries.
        """
        check_is_fitted(self)
        X = validate_data(
            self,
            masked_to_nan(X),
            dtype=[np.float64, np.float32],
            ensure_all_finite="allow-nan",
            reset=False,
        )
        X0, mask = _zero_filled(X)
        if mask is not None:
            self._check_observed(mask, axis=1, what="row")
        Z = self._coordinates(X0, mask)[:, : self.n_components]
        return Z.astype(X.dtype, copy=False)

    def inverse_transform(self, X):
        """Complete trajectories from their coordinates.

        Parameters
        ----------
        X : array-like of shape (n_samples, n_components)
            Coordinates, as returned by :meth:`transform`.

        Returns
        -------
        X_completed : ndarray of shape (n_samples, n_features)
            The rank-r reconstruction of every entry, observed or missing.
        """
        check_is_fitted(self)
        X = _check_coordinates(X, self.n_components)
        return X @ self._basis().astype(X.dtype, copy=False)

    @property
    def _n_features_out(self):
        return self.components_.shape[0]

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.input_tags.allow_nan = True
        tags.transformer_tags.preserves_dtype = ["float64", "float32"]
        return tags

    def _best_start(self, solve, X0, mask, rank, random_state):
        """Best of up to ``n_init`` random starts, stopping once reached twice.

        Returns the solver's output for the best start and the number of
        starts run.
        """
        total = np.einsum("ij,ij->", X0, X0)
        best, best_residual, n_best = None, np.inf, 0
        for n_init in range(1, self.n_init + 1):
            fit = solve(
                X0,
                mask,
                rank,
                max_iter=self.max_iter,
                tol=self.tol,
                random_state=random_state,
                log=self._log,
            )
            residual = squared_residual(X0, mask, fit[0], fit[1], total)
            # two fits agree to 1e-4 relative (or both fit to round-off)
            margin = 1e-4 * min(residual, best_residual) + 1e-20 * total
            if residual < best_residual - margin:
                best, best_residual, n_best = fit, residual, 1
            elif residual <= best_residual + margin:
                n_best += 1
            self._log(
                f"start {n_init}, squared residual {residual:.6g}, "
                f"best {best_residual:.6g} reached {n_best} times"
            )
            if n_best >= 2 or best_residual <= 1e-28 * total:
                break
        return best, n_init

    def _choose_rank(self, X0, mask, random_state):
        """Completion rank and the held-out errors that chose it."""
        if self.completion_rank is None:
            return self.n_components, {}
        if mask is None:
            if self.completion_rank == "auto":
                return self.n_components, {}
            return min(max(self.completion_rank, self.n_components), *X0.shape), {}
        limit = 3 * self.n_components
        if self.completion_rank != "auto":
            limit = max(self.completion_rank, self.n_components)
        limit = max_completion_rank(mask, self.n_components, limit)
        if self.completion_rank != "auto":
            return limit, {}
        return select_completion_rank(X0, mask, self.n_components, limit, random_state)

    def _subsample(self, mask, rank, random_state):
        """Rows on which the random starts run, or None for all rows."""
        if mask is None or self.max_init_samples is None:
            return None
        n_rows = mask.shape[0]
        if n_rows <= self.max_init_samples:
            return None
        rows = np.sort(
            random_state.choice(n_rows, self.max_init_samples, replace=False)
        )
        if mask[rows].sum(axis=0).min() < rank:
            return None  # a column too rarely observed in the subsample
        return rows

    def _completion_basis(self):
        """Rows map rank-q coordinates to trajectories."""
        basis = self.completion_components_.astype(np.float64)
        if self.whiten:
            return self.completion_singular_values_[:, None] * basis
        return basis

    def _coordinates(self, X0, mask):
        """Rank-q least-squares coordinates of every row.

        A row observed in ``k < q`` entries gets the coordinates of the
        leading ``k`` directions (and zeros beyond): the most its entries
        determine.
        """
        basis = self._completion_basis()
        if mask is None:
            return fit_rows(X0, None, basis)
        rank = basis.shape[0]
        supported = np.minimum(mask.sum(axis=1), rank).astype(int)
        Z = np.zeros((X0.shape[0], rank))
        for k in np.unique(supported):
            rows = supported == k
            Z[rows, :k] = fit_rows(X0[rows], mask[rows], basis[:k])
        return Z

    def _basis(self):
        """Rows map coordinates to trajectories: ``X ~ Z @ basis``."""
        if self.whiten:
            return self.singular_values_[:, None] * self.components_
        return self.components_

    def _check_observed(self, mask, *, axis, what):
        counts = mask.sum(axis=axis)
        short = np.flatnonzero(counts < self.n_components)
        if short.size:
            empty = np.count_nonzero(counts[short] == 0)
            raise ValueError(
                f"Every {what} needs at least n_components={self.n_components} "
                f"observed entries to determine its coordinates; "
                f"{describe_indices(short)} {what}s have fewer ({empty} of them "
                f"have none). Remove them or lower n_components."
            )

    def _log(self, message):
        if self.verbose:
            print(f"[PowerFactorization] {message}")


def _zero_filled(X):
    """Return ``X`` in float64 with NaN set to 0, and the observed mask.

    The mask is None when nothing is missing, which selects the fast
    complete-data route.
    """
    X0 = X.astype(np.float64, copy=False)
    missing = np.isnan(X0)
    if not missing.any():
        return X0, None
    return np.where(missing, 0.0, X0), (~missing).astype(np.float64)


def _check_coordinates(Z, n_components):
    Z = check_array(Z, dtype=[np.float64, np.float32])
    if Z.shape[1] != n_components:
        raise ValueError(
            f"X has {Z.shape[1]} features, but PowerFactorization.inverse_transform "
            f"expects n_components={n_components} coordinates per row."
        )
    return Z
