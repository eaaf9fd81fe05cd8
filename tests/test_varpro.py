import warnings

import _matrices
import numpy as np
import pytest
from _matrices import remove
from numpy.testing import assert_allclose
from scipy.linalg import subspace_angles
from sklearn.exceptions import ConvergenceWarning

from sklearn_gpca import PowerFactorization, _varpro
from sklearn_gpca._als import squared_residual
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


def fit(X, rank, seed=0, max_iter=500):
    X0, mask = zero_filled(X)
    return _varpro.power_factorization(
        X0,
        mask,
        rank,
        max_iter=max_iter,
        tol=1e-10,
        random_state=np.random.RandomState(seed),
        log=lambda message: None,
    )


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("rank", [2, 4])
def test_exact_recovery_of_missing_entries(seed, rank):
    X = low_rank(rank=rank, seed=seed)
    X_missing = remove(X, 0.4, seed=seed)
    B, A, _, converged = fit(X_missing, rank, seed)
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


@pytest.mark.parametrize("sparse", [True, False])
def test_normal_equations_match_the_explicit_ruhe_wedin_jacobian(monkeypatch, sparse):
    rng = np.random.RandomState(0)
    n_samples, n_features, r = 30, 8, 2
    X0, mask = zero_filled(remove(rng.standard_normal((n_samples, n_features)), 0.4))
    V = np.linalg.qr(rng.standard_normal((n_features, r)))[0]
    U, inv_gram, _ = _varpro._project(X0, mask, V)
    blocks = []
    for i in range(n_samples):
        seen = mask[i] > 0
        projector = np.eye(seen.sum()) - V[seen] @ np.linalg.pinv(V[seen])
        block = np.zeros((seen.sum(), n_features, r))
        block[:, seen, :] = -projector[:, :, None] * U[i]
        blocks.append(block.reshape(seen.sum(), -1))
    J = np.vstack(blocks)
    residual = ((X0 - U @ V.T) * mask)[mask > 0]
    # several chunks of rows must give the same sums as one, with the pairs
    # of observed entries cached or recomputed
    monkeypatch.setattr(_varpro, "_CHUNK_FLOATS", 7 * n_features**2)
    monkeypatch.setattr(_varpro, "_CHUNK_PAIRS", 50)
    monkeypatch.setattr(_varpro, "_SPARSE_DENSITY", 2.0 if sparse else 0.0)
    for cached in (2**22, 0):
        monkeypatch.setattr(_varpro, "_CACHED_PAIRS", cached)
        layout = _varpro._Layout(mask, r)
        assert layout.sparse == sparse
        assert not sparse or len(layout.chunks) > 3
        for _ in range(2):
            hessian, gradient = layout.normal_equations(X0, V, U, inv_gram)
            assert_allclose(hessian, J.T @ J, atol=1e-10)
            assert_allclose(gradient.ravel(), -J.T @ residual, atol=1e-10)


@pytest.mark.parametrize("solver", ["varpro", "als"])
def test_just_enough_entries_never_break_the_solvers(solver):
    # noisy tracks of 3 frames (6 entries), one in seven cut to 2 frames
    # (4 entries = n_components); the end frames are seen by 4 tracks only
    n_frames, n_tracks = 20, 72
    rng = np.random.RandomState(0)
    X = low_rank(n_tracks, 2 * n_frames) + 0.01 * rng.standard_normal((72, 40))
    starts = np.arange(n_tracks) % (n_frames - 2)
    frames = np.arange(n_frames)
    cut = (np.arange(n_tracks) % 7 == 0) & (starts > 0) & (starts < 17)
    length = np.where(cut, 2, 3)
    visible = (frames >= starts[:, None]) & (frames < (starts + length)[:, None])
    X[~np.repeat(visible, 2, axis=1)] = np.nan
    assert (~np.isnan(X)).sum(axis=0).min() == 4
    assert (~np.isnan(X)).sum(axis=1).min() == 4
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        warnings.simplefilter("ignore", ConvergenceWarning)
        pf = PowerFactorization(4, solver=solver, n_init=2, max_iter=50)
        Z = pf.fit(X).transform(X)
    assert np.all(np.isfinite(Z))
    assert np.all(np.isfinite(pf.components_))
    assert np.isfinite(pf.reconstruction_err_)


@pytest.mark.parametrize("solver", ["varpro", "als"])
def test_underdetermined_rows_and_columns_are_named(solver):
    _, X = banded(n_frames=20, n_tracks=80, window=3)
    X[[4, 9], :] = np.nan
    X[4, :2] = 1.0  # 2 observed entries < n_components=4
    msg = r"Every row needs at least n_components=4 .* 2 \(4, 9\) rows have fewer"
    with pytest.raises(ValueError, match=msg + r" \(1 of them have none\)"):
        PowerFactorization(4, solver=solver).fit(X)
    _, X = banded(n_frames=20, n_tracks=80, window=3)
    X[:, [0, 1, 38]] = np.nan
    with pytest.raises(ValueError, match=r"Every column .* 3 \(0, 1, 38\) columns"):
        PowerFactorization(4, solver=solver).fit(X)


def test_unknown_solver_is_rejected():
    with pytest.raises(ValueError, match="'solver' parameter"):
        PowerFactorization(2, solver="svd").fit(low_rank())


def test_restarts_stop_when_the_best_fit_repeats():
    X = remove(low_rank(), 0.3)
    pf = PowerFactorization(4, n_init=10, random_state=0).fit(X)
    assert pf.n_init_ == 2
    single = PowerFactorization(4, n_init=1, random_state=0).fit(X)
    assert single.n_init_ == 1


def test_max_iter_warns():
    X = remove(low_rank() + np.random.RandomState(0).standard_normal((200, 24)), 0.5)
    with pytest.warns(ConvergenceWarning, match="did not converge in max_iter=2"):
        PowerFactorization(4, solver="varpro", n_init=1, max_iter=2, tol=0).fit(X)


def test_dinosaur_reaches_the_best_known_fit(lowrank_dir):
    # one start (a race of four random bases, the best pursued); the 10-seed
    # success rate is in benchmarks/results/lowrank.md
    X = load_lowrank("Dino_trimmed", data_home=lowrank_dir.parent).X
    pf = PowerFactorization(4, n_init=1, completion_rank=None, random_state=0).fit(X)
    # best known rank-4 fit: 1.084673 pixels (Hong & Fitzgibbon, 2015)
    assert pf.reconstruction_err_ <= 1.0850
    X0, mask = zero_filled(X)
    B = pf.transform(X)
    rms = np.sqrt(squared_residual(X0, mask, B, pf._basis().T, None) / mask.sum())
    assert_allclose(rms, pf.reconstruction_err_, rtol=1e-6)


def test_race_pursues_the_lowest_start(monkeypatch):
    # the race runs each random start for _RACE_STEPS accepted steps, then
    # pursues exactly the one with the lowest cost: replay it start by start
    X0, mask = zero_filled(banded(n_frames=20, n_tracks=80, window=4, seed=1)[1])
    X0 += 0.05 * np.random.RandomState(0).standard_normal(X0.shape) * mask
    monkeypatch.setattr(_varpro, "_RACE", 3)
    messages = []
    B, A, _, _ = _varpro.power_factorization(
        X0,
        mask,
        4,
        max_iter=500,
        tol=1e-10,
        random_state=np.random.RandomState(5),
        log=messages.append,
    )
    rng = np.random.RandomState(5)
    layout = _varpro._Layout(mask, 4)
    starts = []
    for _ in range(3):
        V, _ = np.linalg.qr(rng.standard_normal((X0.shape[1], 4)))
        start = _varpro._Start(X0, mask, V, layout, 1e-10, lambda m: None)
        start.run(500, max_accepted=_varpro._RACE_STEPS)
        starts.append(start)
    costs = [start.cost for start in starts]
    assert len(set(np.round(costs, 8))) == 3  # the starts are told apart
    winner = int(np.argmin(costs))
    assert f"race won by start {winner + 1}" in messages
    starts[winner].run(500)
    B_alone, A_alone, _, _ = starts[winner].result()
    assert_allclose(B @ A.T, B_alone @ A_alone.T, atol=1e-8)


def fit_at(X0, mask, seed):
    return _varpro.power_factorization(
        X0,
        mask,
        4,
        max_iter=500,
        tol=1e-10,
        random_state=np.random.RandomState(seed),
        log=lambda message: None,
    )
