"""The variable-projection solver: its products, routes and restarts."""

import _matrices
import numpy as np
import pytest
from _matrices import remove
from numpy.testing import assert_allclose
from scipy.linalg import subspace_angles

from sklearn_gpca import PowerFactorization, _gauss_newton, _multistart, _varpro
from sklearn_gpca._als import ALS, squared_residual
from sklearn_gpca.datasets import load_lowrank


def low_rank(n_samples=200, n_features=24, rank=4, seed=0):
    return _matrices.low_rank(n_samples, n_features, rank, seed)


def banded(n_frames=40, n_tracks=200, window=5, rank=4, seed=0):
    """Tracks of ``window`` consecutive frames (2 coordinates each) along a
    long sequence: a rank-``rank`` matrix observed on a band."""
    rng = np.random.RandomState(seed)
    X = low_rank(n_tracks, 2 * n_frames, rank, seed)
    starts = np.arange(n_tracks) % (n_frames - window + 1)
    rng.shuffle(starts)
    frames = np.arange(n_frames)
    visible = (frames >= starts[:, None]) & (frames < starts[:, None] + window)
    return X, np.where(np.repeat(visible, 2, axis=1), X, np.nan)


def zero_filled(X):
    mask = ~np.isnan(X)
    return np.where(mask, X, 0.0), mask.astype(float)


def start(n_features, rank, seed):
    return _multistart.random_basis(n_features, rank, np.random.RandomState(seed))


def silent(message):
    pass


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("rank", [2, 4])
def test_exact_recovery_of_missing_entries(seed, rank):
    X = low_rank(rank=rank, seed=seed)
    X0, mask = zero_filled(remove(X, 0.4, seed=seed))
    B, A, _, converged = _varpro.varpro(
        X0, mask, start(24, rank, seed), max_iter=500, tol=1e-10, log=silent
    )
    assert converged
    assert_allclose(B.T @ B, np.eye(rank), atol=1e-10)
    assert np.linalg.norm(B @ A.T - X) / np.linalg.norm(X) < 1e-6


def test_estimator_recovers_missing_entries():
    X = low_rank(seed=3)
    X_missing = remove(X, 0.5, seed=3)
    pf = PowerFactorization(4, solver="varpro", random_state=0).fit(X_missing)
    X_completed = pf.inverse_transform(pf.transform(X_missing))
    assert np.linalg.norm(X_completed - X) / np.linalg.norm(X) < 1e-6


@pytest.mark.parametrize("seed", [0, 1])
def test_banded_short_tracks_reach_the_optimum(seed):
    X, X_banded = banded(seed=seed)
    assert np.isnan(X_banded).mean() > 0.85
    pf = PowerFactorization(4, random_state=seed).fit(X_banded)
    X_completed = pf.inverse_transform(pf.transform(X_banded))
    assert pf.reconstruction_err_ < 1e-6 * np.sqrt(np.mean(X**2))
    assert np.linalg.norm(X_completed - X) / np.linalg.norm(X) < 1e-6


def test_complete_noisy_data_give_the_svd_subspace():
    rng = np.random.RandomState(0)
    X = low_rank() + 0.05 * rng.standard_normal((200, 24))
    pf = PowerFactorization(4, solver="varpro", random_state=0).fit(X)
    _, s, vt = np.linalg.svd(X, full_matrices=False)
    assert subspace_angles(pf.components_.T, vt[:4].T).max() < 1e-6
    assert_allclose(pf.singular_values_, s[:4], rtol=1e-6)


def test_nearly_complete_noisy_data_give_the_svd_subspace():
    # one missing entry, filled by the fit itself: the optimum is the SVD of
    # the completed matrix, which both solvers must reach
    rng = np.random.RandomState(1)
    X = low_rank() + 0.05 * rng.standard_normal((200, 24))
    X[5, 7] = np.nan
    fits = [
        PowerFactorization(4, solver=solver, tol=1e-12, max_iter=5000, random_state=0)
        .fit(X)
        .components_
        for solver in ("varpro", "als")
    ]
    assert subspace_angles(fits[0].T, fits[1].T).max() < 1e-5


def explicit_jacobian(X0, mask, V, U):
    """The Ruhe-Wedin (RW2) Jacobian of the reduced residual, row by row."""
    n_features, r = V.shape
    blocks = []
    for i in range(X0.shape[0]):
        seen = mask[i] > 0
        projector = np.eye(seen.sum()) - V[seen] @ np.linalg.pinv(V[seen])
        block = np.zeros((seen.sum(), n_features, r))
        block[:, seen, :] = -projector[:, :, None] * U[i]
        blocks.append(block.reshape(seen.sum(), -1))
    return np.vstack(blocks)


def noisy_problem(seed=0, n_samples=30, n_features=8, r=2):
    rng = np.random.RandomState(seed)
    X0, mask = zero_filled(remove(rng.standard_normal((n_samples, n_features)), 0.4))
    V = start(n_features, r, seed)
    return X0, mask, V


@pytest.mark.parametrize("sparse", [True, False])
def test_dense_gauss_newton_matrix_matches_the_explicit_ruhe_wedin_jacobian(
    monkeypatch, sparse
):
    X0, mask, V = noisy_problem()
    state = _varpro._Projection(X0, mask, V)
    J = explicit_jacobian(X0, mask, V, state.U)
    residual = ((X0 - state.U @ V.T) * mask)[mask > 0]
    # several chunks of rows must give the same sums as one, with the pairs
    # of observed entries cached or recomputed
    monkeypatch.setattr(_gauss_newton, "_CHUNK_FLOATS", 7 * 8**2)
    monkeypatch.setattr(_gauss_newton, "_CHUNK_PAIRS", 50)
    monkeypatch.setattr(_gauss_newton, "_SPARSE_DENSITY", 2.0 if sparse else 0.0)
    for cached in (2**22, 0):
        monkeypatch.setattr(_gauss_newton, "_CACHED_PAIRS", cached)
        layout = _gauss_newton.GaussNewtonMatrix(mask, 2)
        assert layout.sparse == sparse
        assert not sparse or len(layout.chunks) > 3
        for _ in range(2):
            hessian = layout.assemble(V, state.U, state.inv_gram)
            assert_allclose(hessian, J.T @ J, atol=1e-10)
    # the solver's gradient: -J^T e on the tangent space at V
    gradient = _varpro.VarPro(X0, mask, V, tol=0, log=silent)._linearise()[0]
    expected = _varpro._tangent(V, (-J.T @ residual).reshape(V.shape))
    assert_allclose(gradient, expected, atol=1e-10)


def test_matrix_free_gauss_newton_product_is_the_explicit_one():
    X0, mask, V = noisy_problem(seed=1)
    solver = _varpro.VarPro(X0, mask, V, tol=0, log=silent)
    J = explicit_jacobian(X0, mask, V, solver.state.U)
    D = _varpro._tangent(V, np.random.RandomState(2).standard_normal(V.shape))
    expected = _varpro._tangent(V, (J.T @ J @ D.ravel()).reshape(D.shape))
    assert_allclose(solver._product(D, 0.0, newton=False), expected, atol=1e-10)
    assert_allclose(
        solver._product(D, 0.5, newton=False), expected + 0.5 * D, atol=1e-10
    )


def test_newton_product_is_the_derivative_of_the_gradient():
    # along a tangent direction D, the Hessian of half the cost is minus the
    # derivative of the descent direction R^T U, projected on the tangent space
    X0, mask, V = noisy_problem(seed=3)
    D = _varpro._tangent(V, np.random.RandomState(4).standard_normal(V.shape))

    def descent(V):
        state = _varpro._Projection(X0, mask, V)
        return state.residual.T @ state.U

    h = 1e-6
    derivative = (descent(V + h * D) - descent(V - h * D)) / (2 * h)
    solver = _varpro.VarPro(X0, mask, V, tol=0, log=silent)
    product = solver._product(D, 0.0, newton=True)
    assert_allclose(product, -_varpro._tangent(V, derivative), atol=1e-6)
    # Gauss-Newton differs from it by a term proportional to the residual
    assert not np.allclose(solver._product(D, 0.0, newton=False), product, atol=1e-3)


def test_dense_preconditioner_gives_the_same_fit_as_conjugate_gradients(monkeypatch):
    _, X = banded(n_frames=20, n_tracks=120, window=6, seed=2)
    X0, mask = zero_filled(X)
    X0 += 0.01 * np.random.RandomState(0).standard_normal(X0.shape) * mask
    init = start(40, 4, 0)
    monkeypatch.setattr(_varpro, "_MAX_DENSE_UNKNOWNS", 0)
    matrix_free = _varpro.VarPro(X0, mask, init, tol=1e-12, log=silent).run(500)
    assert matrix_free.dense is None
    # the dense Gauss-Newton matrix as soon as conjugate gradients cost anything
    monkeypatch.setattr(_varpro, "_MAX_DENSE_UNKNOWNS", 2**12)
    monkeypatch.setattr(_varpro, "factorisation_flops", lambda mask, r: 0.0)
    dense = _varpro.VarPro(X0, mask, init, tol=1e-12, log=silent).run(500)
    assert dense.dense is not None
    assert_allclose(dense.cost, matrix_free.cost, rtol=1e-8)
    angles = subspace_angles(dense.state.V, matrix_free.state.V)
    assert angles.max() < 1e-6


def test_als_and_varpro_share_their_interface():
    X0, mask = zero_filled(remove(low_rank(), 0.3))
    init = start(24, 4, 0)
    for Solver in (ALS, _varpro.VarPro):
        solver = Solver(X0, mask, init, tol=1e-10, log=silent)
        solver.run(500, max_accepted=3)
        assert not solver.done
        solver.run(500)
        B, A, n_iter, converged = solver.result()
        assert converged and solver.done and n_iter == solver.n_iter
        assert_allclose(squared_residual(X0, mask, B, A, None), solver.cost, atol=1e-12)


class FakeStart:
    """A solver whose residual after each accepted step is scripted."""

    def __init__(self, costs, pursued):
        self.costs, self.pursued, self.total = list(costs), pursued, 1.0
        self.n_iter, self.cost, self.done, self.runs = 0, np.inf, False, 0

    def run(self, max_iter, max_accepted=None):
        # every run after the trial steps pursues the start
        self.runs += 1
        if self.runs == 2:
            self.pursued.append(self)
        steps = len(self.costs) if max_accepted is None else max_accepted
        for _ in range(min(steps, len(self.costs))):
            self.n_iter += 1
            self.cost = self.costs.pop(0)
        self.done = not self.costs
        return self


@pytest.mark.parametrize(
    "n_init, expected", [(1, [0]), (3, [0, 1, 2]), (6, [0, 1, 4, 2])]
)
def test_restarts_pursue_promising_starts_then_the_lowest_waiting(
    monkeypatch, n_init, expected
):
    monkeypatch.setattr(_multistart, "TRIAL_STEPS", 2)
    monkeypatch.setattr(_multistart, "PURSUIT_STEPS", 2)
    # start k: (residual after the 2 trial steps, final residual)
    scripts = [(5.0, 1.0), (3.0, 2.0), (4.0, 1.0), (9.0, 0.5), (2.0, 3.0), (6.0, 1.0)]
    pursued, made = [], []

    def make_start(init):
        fake = FakeStart([10.0, *scripts[len(made)]], pursued)
        made.append(fake)
        return fake

    best, n_starts = _multistart.best_of_starts(
        make_start,
        4,
        2,
        n_init=n_init,
        max_iter=100,
        random_state=np.random.RandomState(0),
        log=silent,
    )
    assert n_starts == n_init
    # a start whose trial residual is the lowest so far is pursued at once
    # (0, 1, then 4); the others wait and are pursued lowest first (2 before
    # 5 and 3) until the lowest final residual, 1, is reached twice; start 3,
    # which would reach 0.5, is never pursued
    assert [made.index(start) for start in pursued] == expected
    assert best.cost == 1.0


def test_a_promising_start_crawling_along_waits_for_the_other_starts(monkeypatch):
    monkeypatch.setattr(_multistart, "TRIAL_STEPS", 2)
    monkeypatch.setattr(_multistart, "PURSUIT_STEPS", 3)
    # start 0 crawls for 50 steps to a poor minimum; starts 1 and 2, drawn
    # meanwhile, reach the lowest residual, 1, in a few steps: start 0 gets
    # its trial and pursuit steps only
    crawl = [10.0, 3.0, *np.linspace(2.9, 2.0, 50)]
    scripts = [crawl, [10.0, 2.8, 2.5, 1.0], [10.0, 2.7, 1.0]]
    pursued, made = [], []

    def make_start(init):
        made.append(FakeStart(scripts[len(made)], pursued))
        return made[-1]

    best, n_starts = _multistart.best_of_starts(
        make_start,
        4,
        2,
        n_init=5,
        max_iter=100,
        random_state=np.random.RandomState(0),
        log=silent,
    )
    assert (n_starts, best.cost) == (3, 1.0)
    assert made[0].n_iter == 2 + 3 and not made[0].done
    assert [made.index(start) for start in pursued] == [0, 1, 2]


def test_a_pursued_waiting_start_does_not_confirm_itself(monkeypatch):
    monkeypatch.setattr(_multistart, "TRIAL_STEPS", 2)
    monkeypatch.setattr(_multistart, "PURSUIT_STEPS", 1)
    # start 0 ends at 2; starts 1 and 2 wait and both end at 1: the minimum
    # at 1 is confirmed only once start 2 has reached it too
    scripts = [[10.0, 5.0, 2.0], [10.0, 6.0, 1.0], [10.0, 7.0, 1.0]]
    pursued, made = [], []

    def make_start(init):
        made.append(FakeStart(scripts[len(made)], pursued))
        return made[-1]

    best, n_starts = _multistart.best_of_starts(
        make_start,
        4,
        2,
        n_init=3,
        max_iter=100,
        random_state=np.random.RandomState(0),
        log=silent,
    )
    assert [made.index(start) for start in pursued] == [0, 1, 2]
    assert (n_starts, best.cost) == (3, 1.0)


def test_restarts_stop_when_the_best_fit_repeats():
    X = remove(low_rank(), 0.3)
    pf = PowerFactorization(4, n_init=10, random_state=0).fit(X)
    assert pf.n_init_ == 2
    single = PowerFactorization(4, n_init=1, random_state=0).fit(X)
    assert single.n_init_ == 1


def test_dinosaur_reaches_the_best_known_fit(lowrank_dir):
    # the 10-seed success rate is in benchmarks/results/lowrank.md
    X = load_lowrank("Dino_trimmed", data_home=lowrank_dir.parent).X
    pf = PowerFactorization(4, completion_rank=None, random_state=0).fit(X)
    # best known rank-4 fit: 1.084673 pixels (Hong & Fitzgibbon, 2015)
    assert pf.reconstruction_err_ <= 1.0850
    X0, mask = zero_filled(X)
    B = pf.transform(X)
    basis = pf.singular_values_[:, None] * pf.components_
    rms = np.sqrt(squared_residual(X0, mask, B, basis.T, None) / mask.sum())
    assert_allclose(rms, pf.reconstruction_err_, rtol=1e-6)


def test_a_waiting_start_already_at_the_lowest_residual_confirms_it(monkeypatch):
    monkeypatch.setattr(_multistart, "TRIAL_STEPS", 2)
    # start 0 converges within its trial steps; start 1 waits (its trial
    # residual is higher) but is already within 1e-4 of it: no need to pursue
    scripts = [[10.0, 1.0], [10.0, 1.00001, 0.5], [10.0, 2.0, 0.1]]
    pursued, made = [], []

    def make_start(init):
        made.append(FakeStart(scripts[len(made)], pursued))
        return made[-1]

    best, n_starts = _multistart.best_of_starts(
        make_start,
        4,
        2,
        n_init=3,
        max_iter=100,
        random_state=np.random.RandomState(0),
        log=silent,
    )
    assert (n_starts, pursued, best.cost) == (2, [], 1.0)
