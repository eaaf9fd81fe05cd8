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
from sklearn.utils import check_array, check_random_state
from sklearn.utils._param_validation import Interval, StrOptions, validate_params
from sklearn.utils.validation import check_is_fitted, validate_data

from sklearn_gpca._als import silent
from sklearn_gpca._factorization import factorise, project
from sklearn_gpca._missing import describe_indices, masked_to_nan
from sklearn_gpca._validation import Count

_PARAMETERS = {
    "n_components": [Count(1, None, closed="left")],
    "whiten": ["boolean"],
    "solver": [StrOptions({"varpro", "als"})],
    "completion_rank": [
        Count(1, None, closed="left"),
        StrOptions({"auto"}),
        None,
    ],
    "n_init": [Count(1, None, closed="left")],
    "max_iter": [Count(1, None, closed="left")],
    "tol": [Interval(Real, 0, None, closed="left")],
    "max_init_samples": [Count(1, None, closed="left"), None],
    "random_state": ["random_state"],
    "verbose": ["verbose"],
}


# the parameters handed to factorise as they are
_SOLVER_PARAMETERS = (
    "solver",
    "completion_rank",
    "n_init",
    "max_iter",
    "tol",
    "max_init_samples",
)


@validate_params(
    {"X": ["array-like"], **_PARAMETERS}, prefer_skip_nested_validation=True
)
def power_factorization(
    X,
    n_components=5,
    *,
    whiten=True,
    solver="varpro",
    completion_rank=None,
    n_init=10,
    max_iter=500,
    tol=1e-7,
    max_init_samples=1000,
    random_state=None,
    verbose=0,
):
    """Rank-r factorisation of trajectories with missing entries.

    The function behind :class:`PowerFactorization`: fits ``X ~ Z diag(s) V``
    to the observed entries of ``X`` (equation (8) of Vidal & Hartley, 2004)
    and returns the coordinates of every row. Read more in the documentation
    of :class:`PowerFactorization`, whose parameters are the same.

    Parameters
    ----------
    X : array-like or masked array of shape (n_samples, n_features)
        Trajectories, one per row; missing entries are NaN (or masked).

    n_components : int, default=5
        Rank ``r`` of the factorisation.

    whiten : bool, default=True
        Return the paper's whitened coordinates (True) or the plain
        projections on the components.

    solver : {"varpro", "als"}, default="varpro"
        Minimiser of the squared residual over the observed entries.

    completion_rank : int, "auto" or None, default=None
        Rank at which the trajectories are completed before the projection.

    n_init : int, default=10
        Maximum number of random starts.

    max_iter : int, default=500
        Maximum number of iterations per start.

    tol : float, default=1e-7
        Relative decrease of the residual below which iterations stop.

    max_init_samples : int or None, default=1000
        Rows on which the random starts run when there are more.

    random_state : int, RandomState instance or None, default=None
        Seed of the random starts and of the subsample.

    verbose : int, default=0
        Print the progress when positive.

    Returns
    -------
    Z : ndarray of shape (n_samples, n_components)
        Coordinates of every row, as :meth:`PowerFactorization.transform`
        returns them.

    components : ndarray of shape (n_components, n_features)
        Orthonormal basis of the fitted subspace.

    singular_values : ndarray of shape (n_components,)
        Singular values of the fitted matrix, in the units of ``X``.

    See Also
    --------
    PowerFactorization : The same as an estimator, with ``transform`` for new
        trajectories.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_gpca import power_factorization
    >>> rng = np.random.RandomState(0)
    >>> X = rng.standard_normal((100, 3)) @ rng.standard_normal((3, 20))
    >>> X[rng.rand(*X.shape) < 0.2] = np.nan
    >>> Z, components, singular_values = power_factorization(
    ...     X, n_components=3, random_state=0
    ... )
    >>> Z.shape, components.shape
    ((100, 3), (3, 20))
    >>> completed = (Z * singular_values) @ components
    >>> bool(np.nanmax(np.abs(completed - X)) < 1e-6)
    True
    """
    X = check_array(
        masked_to_nan(X), dtype=[np.float64, np.float32], ensure_all_finite="allow-nan"
    )
    _check_params_vs_input(X, n_components, completion_rank)
    fit = factorise(
        X,
        n_components,
        solver=solver,
        completion_rank=completion_rank,
        n_init=n_init,
        max_iter=max_iter,
        tol=tol,
        max_init_samples=max_init_samples,
        random_state=check_random_state(random_state),
        log=_logger(verbose),
    )
    _warn_underdetermined(X, n_components)
    Z = project(X, fit.components, fit.singular_values)[0][:, :n_components]
    singular_values = fit.singular_values[:n_components]
    if not whiten:
        Z = Z * singular_values
    return (
        Z.astype(X.dtype, copy=False),
        fit.components[:n_components].astype(X.dtype, copy=False),
        singular_values.astype(X.dtype, copy=False),
    )


class PowerFactorization(
    ClassNamePrefixFeaturesOutMixin, TransformerMixin, BaseEstimator
):
    """Rank-r factorisation of trajectories with missing entries.

    Fits ``X ~ Z diag(s) V`` minimising the squared error over the observed
    entries of ``X`` (equation (8) of [1]_), and projects
    trajectories (rows of ``X``, possibly incomplete, possibly new) to their
    ``n_components`` coordinates ``Z``. With complete data the fitted
    subspace is the truncated SVD's. :func:`power_factorization` is the same
    as a function.

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
        damped Gauss-Newton and Newton steps, which reaches the global
        optimum far more often on real tracks. Both cost
        ``O(|observed| r^2 + (n_samples + n_features) r^3)`` per iteration;
        see Notes. With complete data both use the power method.

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
        is ``n_components`` (the projection is then exact at any rank). An
        int larger than ``n_samples`` or ``n_features`` is an error; one
        larger than the number of trajectories observing some feature is
        lowered to it, with a warning.

    n_init : int, default=10
        Maximum number of random starts. Each start first runs for a few
        steps; the unfinished ones are then pursued lowest residual first,
        and starts stop once two of them reach the same lowest residual (to
        a relative ``1e-4``). The best fit is kept.

    max_iter : int, default=500
        Maximum number of iterations per start: alternations for "als",
        Levenberg-Marquardt trials for "varpro".

    tol : float, default=1e-7
        Stop when the squared residual over the observed entries decreases
        by less than ``tol`` times its value in one (accepted) iteration, or,
        for "varpro", when a nearly undamped step is predicted to.

    max_init_samples : int or None, default=1000
        With missing entries and more (well-observed) rows than this, the
        random starts run on the ``max_init_samples`` rows with the most
        observed entries; the best of them is then polished on all rows by
        the same solver (beyond the paper; see Notes). None runs the starts
        on all rows.

    random_state : int, RandomState instance or None, default=None
        Seed of the random starting bases and of the subsample.

    verbose : int, default=0
        Print the residual at every iteration when positive.

    Attributes
    ----------
    components_ : ndarray of shape (n_components, n_features)
        Orthonormal basis of the fitted subspace of the feature space :math:`R^{2F}`,
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

    underdetermined_ : ndarray of shape (n_samples,), dtype=bool
        True for the training trajectories observed in fewer than
        ``n_components`` entries: their coordinates are fitted on the
        leading directions their entries determine and are zero beyond (all
        zero for a trajectory with no observed entry). See Notes for new
        trajectories.

    n_iter_ : int
        Number of iterations run by the start that was kept.

    n_polish_iter_ : int
        Number of iterations polishing the kept start on all rows (0 when
        the starts ran on all rows).

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
    power_factorization : The same as a function.
    sklearn.decomposition.PCA : Projection of complete, centred data.
    sklearn.decomposition.TruncatedSVD : Projection of complete data.
    sklearn.impute.IterativeImputer : Imputation of missing entries.

    Notes
    -----
    With ``W = X^T`` the ``2F x P`` measurement matrix of the paper, the
    iteration of [1]_ and [2]_ alternates (1) the least-squares ``B`` given
    ``A`` over the observed entries, one small ``r x r`` system per
    trajectory, (2) the orthonormalisation of ``B``, (3) the least-squares
    ``A`` given ``B``, one system per feature. With complete data (1) and (3)
    reduce to the products ``W^T A`` and ``W B`` of the power method, which
    converges to the best rank-r approximation at rate
    ``(s_{r+1} / s_r)^k``.

    With missing entries, ``solver="als"`` runs that iteration, which can
    crawl for thousands of iterations along flat valleys and stop far from
    the optimum. ``solver="varpro"`` eliminates the coordinates exactly
    instead: for a basis ``A`` every row's coordinates are its least-squares
    fit, so the residual is a function of ``A`` alone (variable projection,
    Golub & Pereyra; the Wiberg algorithm). It is minimised by
    Levenberg-Marquardt on the ``n_features x r`` entries of ``A``, with the
    Ruhe-Wedin (RW2) approximation of the Jacobian, steps orthogonal to the
    gauge directions ``A K`` and ``A`` re-orthonormalised after each step
    [3]_; once the decrease slows down, the steps use
    the exact Hessian (Newton), which converges quadratically where
    Gauss-Newton converges linearly. The linear system of a step is solved
    by conjugate gradients (as in [4]_) whose products cost
    ``O(|observed| r)``, with the
    block diagonal of the Gauss-Newton matrix as preconditioner, so nothing
    of size ``(n_features r)^2`` is formed; on problems where conjugate
    gradients need many products (few features, ill-conditioned: the
    Dinosaur sequence) the ``(n_features r)``-square Gauss-Newton matrix
    becomes the preconditioner once it is cheaper than the products it
    saves. Random starts still end in local minima on hard problems, hence
    the restarts of ``n_init``. Timings and success rates are in the
    benchmarks (``benchmarks/results/lowrank.md`` and
    ``benchmarks/results/frames.md``).

    Large ``n_samples`` (beyond the paper). Above ``max_init_samples`` rows
    the restarts run on the best-observed rows; the winning basis is then
    refined on all rows, which from a start that near the optimum takes a
    few iterations. The subsample must observe every feature at least ``q``
    times, otherwise all rows are used. Memory stays ``O(n_samples
    n_features)``.

    What the observed entries cannot determine. A feature (frame
    coordinate) observed in fewer than ``n_components`` trajectories (after
    leaving out trajectories observed in fewer than ``n_components`` of the
    remaining features, repeatedly) cannot be fitted: it is left out of the
    fit with a warning, and its entries of the basis are the minimum-norm fit
    to its few observed entries (zero for a feature never observed).
    Trajectories observed in fewer than ``q`` entries do not inform the
    basis. When the observed entries fall apart
    into groups of trajectories and features that share no entry, the fit
    does not determine the completion between groups, and a warning says so.

    ``transform`` solves the same per-row least-squares problem against the
    fitted rank-q basis and keeps the leading ``n_components`` coordinates,
    so training and new trajectories are projected alike. A trajectory
    observed in ``k < q`` entries is fitted on the leading ``k`` directions,
    with zeros beyond; one with no observed entry gets zeros. Such rows
    never raise: for the training data ``underdetermined_`` flags those with
    ``k < n_components``, and for new data the same flag is
    ``np.sum(~np.isnan(X), axis=1) < n_components``. The data are rescaled
    internally, so the results do not depend on the units of ``X``.

    References
    ----------
    .. [1] R. Vidal and R. Hartley, "Motion Segmentation with Missing Data
       using PowerFactorization and GPCA", CVPR 2004.
    .. [2] R. Hartley and F. Schaffalitzky, "PowerFactorization: 3D
       reconstruction with missing or uncertain data", Australia-Japan
       Advanced Workshop on Computer Vision, 2003.
    .. [3] J. H. Hong and A. Fitzgibbon, "Secrets of Matrix Factorization:
       Approximations, Numerics, Manifold Optimization and Random Restarts",
       ICCV 2015.
    .. [4] N. Boumal and P.-A. Absil, "RTRMC: A Riemannian trust-region method
       for low-rank matrix completion", NIPS 2011.

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

    _parameter_constraints: dict = dict(_PARAMETERS)

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
        max_init_samples=1000,
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
        X = self._validate(X, reset=True)
        _check_params_vs_input(X, self.n_components, self.completion_rank)
        fit = factorise(
            X,
            self.n_components,
            **{name: getattr(self, name) for name in _SOLVER_PARAMETERS},
            random_state=check_random_state(self.random_state),
            log=_logger(self.verbose),
        )
        self.completion_rank_ = fit.components.shape[0]
        self.completion_components_ = fit.components.astype(X.dtype, copy=False)
        self.completion_singular_values_ = fit.singular_values.astype(X.dtype)
        self.components_ = self.completion_components_[: self.n_components]
        self.singular_values_ = self.completion_singular_values_[: self.n_components]
        self.completion_errors_ = fit.completion_errors
        self.n_iter_, self.n_polish_iter_ = fit.n_iter, fit.n_polish_iter
        self.n_init_ = fit.n_init
        self.underdetermined_ = _warn_underdetermined(X, self.n_components)
        _, self.reconstruction_err_ = project(X, fit.components, fit.singular_values)
        return self

    def transform(self, X):
        """Project trajectories, complete or not, to the fitted subspace.

        Parameters
        ----------
        X : array-like or masked array of shape (n_samples, n_features)
            Trajectories, one per row; missing entries are NaN (or masked).
            A row observed in fewer entries than the completion rank is
            fitted on the leading directions it determines (zeros beyond, all
            zeros for a row with no observed entry); see Notes.

        Returns
        -------
        Z : ndarray of shape (n_samples, n_components)
            Least-squares coordinates of each row over its observed entries.
        """
        check_is_fitted(self)
        X = self._validate(X, reset=False)
        Z, _ = project(X, self.completion_components_, self.completion_singular_values_)
        Z = Z[:, : self.n_components]
        if not self.whiten:
            Z = Z * self.singular_values_
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
        Z = check_array(X, dtype=[np.float64, np.float32])
        if Z.shape[1] != self.n_components:
            raise ValueError(
                f"X has {Z.shape[1]} features, but PowerFactorization."
                f"inverse_transform expects n_components={self.n_components} "
                "coordinates per row."
            )
        basis = self.components_
        if self.whiten:
            basis = self.singular_values_[:, None] * basis
        return Z @ basis.astype(Z.dtype, copy=False)

    @property
    def _n_features_out(self):
        return self.components_.shape[0]

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.input_tags.allow_nan = True
        tags.transformer_tags.preserves_dtype = ["float64", "float32"]
        return tags

    def _validate(self, X, *, reset):
        return validate_data(
            self,
            masked_to_nan(X),
            dtype=[np.float64, np.float32],
            ensure_all_finite="allow-nan",
            reset=reset,
        )


def _check_params_vs_input(X, n_components, completion_rank):
    """Checks of the parameters that param validation cannot make."""
    n_samples, n_features = X.shape
    for name, value in [
        ("n_components", n_components),
        ("completion_rank", completion_rank),
    ]:
        if not isinstance(value, Integral):
            continue
        if value > n_features:
            raise ValueError(f"{name}={value} must be at most n_features={n_features}.")
        if value > n_samples:
            raise ValueError(f"{name}={value} must be at most n_samples={n_samples}.")


def _warn_underdetermined(X, n_components):
    """Rows observed in fewer than ``n_components`` entries, with a warning."""
    counts = np.sum(~np.isnan(X), axis=1)
    short = np.flatnonzero(counts < n_components)
    if short.size:
        empty = np.count_nonzero(counts[short] == 0)
        warnings.warn(
            f"{describe_indices(short)} trajectories are observed in fewer than "
            f"n_components={n_components} entries ({empty} of them in none): "
            "their coordinates are fitted on the leading directions their "
            "entries determine and are zero beyond; underdetermined_ flags "
            "them.",
            UserWarning,
            stacklevel=4,
        )
    return counts < n_components


def _logger(verbose):
    if not verbose:
        return silent
    return lambda message: print(f"[PowerFactorization] {message}")
