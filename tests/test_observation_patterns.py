"""Tracker-like observation patterns: short tracks, sparse frames, gaps.

A tracker's output is never refused: frames seen by too few tracks are left
out of the fit with a warning, every trajectory gets coordinates (and so a
label), and the under-observed ones are flagged.
"""

import warnings

import _matrices
import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal
from sklearn.exceptions import ConvergenceWarning
from sklearn.pipeline import make_pipeline

from sklearn_gpca import GPCAClustering, PowerFactorization
from sklearn_gpca.datasets import make_motions
from sklearn_gpca.metrics import misclassification_rate


def windows(n_tracks, n_frames, starts, lengths):
    frames = np.arange(n_frames)
    return (frames >= starts[:, None]) & (frames < (starts + lengths)[:, None])


def tracker_output(seed=0, n_frames=12):
    """Two motions; the first frame seen by no track, the last by 3 tracks,
    and 1- and 2-frame tracks among windows of 8 to 10 frames in between."""
    X, y = make_motions(
        2, n_points=120, n_frames=n_frames, noise=0.5, random_state=seed
    )[:2]
    rng = np.random.RandomState(seed)
    n_tracks = X.shape[0]
    lengths = rng.randint(8, 11, size=n_tracks)
    lengths[:10] = 1 + np.arange(10) % 2  # ten tracks of 1 or 2 frames
    starts = rng.randint(1, n_frames - lengths)  # frame 0 never seen
    visible = windows(n_tracks, n_frames, starts, lengths)
    visible[:, -1] = False
    visible[rng.choice(np.arange(10, n_tracks), 3, replace=False), -1] = True
    X = X.copy()
    X[~np.repeat(visible, 2, axis=1)] = np.nan
    return X, y, visible


def test_tracker_output_gets_a_label_for_every_track():
    X, y, visible = tracker_output()
    assert visible[:, 0].sum() == 0 and visible[:, -1].sum() == 3
    assert set(visible.sum(axis=1)[:10]) == {1, 2}
    pipeline = make_pipeline(
        PowerFactorization(random_state=0), GPCAClustering(2, random_state=0)
    )
    with pytest.warns(UserWarning) as record:
        labels = pipeline.fit_predict(X)
    messages = " ".join(str(w.message) for w in record)
    assert "left out of the fit" in messages
    assert "fewer than n_components=5 entries" in messages
    assert labels.shape == (X.shape[0],)
    assert set(np.unique(labels)) <= {0, 1}
    # the well-observed tracks are segmented as the truth says
    long = visible.sum(axis=1) >= 8
    assert misclassification_rate(y[long], labels[long]) < 0.05


def test_frames_seen_by_too_few_tracks_are_left_out_with_their_count():
    X, _, visible = tracker_output(seed=1)
    pf = PowerFactorization(random_state=0)
    # frame 0 (features 0, 1) is seen by no track, the last frame by 3 < 5
    with pytest.warns(UserWarning) as record:
        pf.fit(X)
    messages = " ".join(str(w.message) for w in record)
    assert "4 (0, 1, 22, 23) of the 24 features" in messages
    assert_array_equal(pf.components_[:, :2], 0.0)
    assert np.all(np.isfinite(pf.components_))
    # the last frame's entries are the minimum-norm fit to its 3 tracks:
    # reproduced exactly by the completion
    Z = pf.transform(X)
    seen = visible[:, -1]
    completed = pf.inverse_transform(Z)[seen][:, -2:]
    assert_allclose(completed, X[seen][:, -2:], atol=1e-6 * np.nanmax(np.abs(X)))


def test_short_tracks_are_placed_and_flagged():
    X, _, visible = tracker_output(seed=2)
    with pytest.warns(UserWarning) as record:
        pf = PowerFactorization(random_state=0).fit(X)
    messages = " ".join(str(w.message) for w in record)
    assert "10 (0, 1, 2, 3, 4, ...) trajectories are observed in fewer" in messages
    counts = 2 * visible.sum(axis=1)  # observed entries of each track
    assert_array_equal(pf.underdetermined_, counts < 5)
    Z = pf.transform(X)
    assert np.all(np.isfinite(Z))
    # a track of k < 5 entries is fitted on the leading k directions only
    for i in np.flatnonzero(counts < 5):
        assert_array_equal(Z[i, counts[i] :], 0.0)
        assert np.any(Z[i, : counts[i]] != 0.0)
    # the documented flag for new rows gives the same answer
    assert_array_equal(np.sum(~np.isnan(X), axis=1) < pf.n_components, counts < 5)


def test_new_short_and_empty_rows_are_placed_not_refused():
    X = _matrices.low_rank(n_samples=303)
    pf = PowerFactorization(5, random_state=0).fit(X[:300])
    X_new = X[300:].copy()
    X_new[0, 3:] = np.nan  # 3 observed entries
    X_new[1, :] = np.nan  # none
    Z = pf.transform(X_new)
    assert_array_equal(Z[0, 3:], 0.0)
    assert np.all(Z[0, :3] != 0.0)
    assert_array_equal(Z[1], 0.0)
    # the complete row is placed exactly
    assert_allclose(pf.inverse_transform(Z[2:]), X[302:], atol=1e-8)


def test_all_missing_rows_get_zero_coordinates_and_a_warning():
    X = _matrices.low_rank()
    X[[3, 10], :] = np.nan
    with pytest.warns(UserWarning, match=r"2 \(3, 10\) trajectories .* \(2 of them"):
        pf = PowerFactorization(5, random_state=0).fit(X)
    Z = pf.transform(X)
    assert_array_equal(Z[[3, 10]], 0.0)
    assert pf.underdetermined_.sum() == 2
    full = PowerFactorization(5, random_state=0).fit(np.delete(X, [3, 10], axis=0))
    assert_allclose(pf.reconstruction_err_, full.reconstruction_err_, atol=1e-8)


def test_all_missing_features_get_zero_components():
    X = _matrices.low_rank()
    X[:, [0, 7]] = np.nan
    with pytest.warns(UserWarning, match=r"2 \(0, 7\) of the 30 features .* in none"):
        pf = PowerFactorization(5, random_state=0).fit(X)
    assert_array_equal(pf.components_[:, [0, 7]], 0.0)
    rest = np.delete(np.arange(30), [0, 7])
    assert_allclose(
        pf.inverse_transform(pf.transform(X))[:, rest], X[:, rest], atol=1e-6
    )


def test_nothing_determinable_is_a_clear_error():
    X = _matrices.low_rank(n_samples=40, n_features=10)
    X[:, 2:] = np.nan  # every row observed in 2 < 5 entries
    with pytest.raises(ValueError, match="do not determine any rank-5 fit"):
        PowerFactorization(5).fit(X)


@pytest.mark.parametrize("solver", ["varpro", "als"])
def test_just_enough_entries_never_break_the_solvers(solver):
    # noisy tracks of 3 frames (6 entries), one in seven cut to 2 frames
    # (4 entries = n_components); the end frames are seen by 4 tracks only
    n_frames, n_tracks = 20, 72
    rng = np.random.RandomState(0)
    X = _matrices.low_rank(n_tracks, 2 * n_frames, 4) + 0.01 * rng.standard_normal(
        (72, 40)
    )
    starts = np.arange(n_tracks) % (n_frames - 2)
    cut = (np.arange(n_tracks) % 7 == 0) & (starts > 0) & (starts < 17)
    visible = windows(n_tracks, n_frames, starts, np.where(cut, 2, 3))
    X[~np.repeat(visible, 2, axis=1)] = np.nan
    assert (~np.isnan(X)).sum(axis=0).min() == 4
    assert (~np.isnan(X)).sum(axis=1).min() == 4
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        warnings.simplefilter("ignore", UserWarning)
        warnings.simplefilter("ignore", ConvergenceWarning)
        pf = PowerFactorization(4, solver=solver, n_init=2, max_iter=50)
        Z = pf.fit(X).transform(X)
    assert np.all(np.isfinite(Z))
    assert np.all(np.isfinite(pf.components_))
    assert np.isfinite(pf.reconstruction_err_)


def test_disconnected_observations_warn_that_the_completion_is_not_unique():
    # rows 0-29 observe columns 0-9, rows 30-59 observe columns 10-19
    X = _matrices.low_rank(n_samples=60, n_features=20, rank=3)
    X[:30, 10:] = np.nan
    X[30:, :10] = np.nan
    with pytest.warns(UserWarning, match="fall apart into 2 groups"):
        PowerFactorization(3, random_state=0).fit(X)
    X[0, 10:13] = _matrices.low_rank(n_samples=60, n_features=20, rank=3)[0, 10:13]
    with warnings.catch_warnings():
        warnings.simplefilter("error", UserWarning)
        PowerFactorization(3, random_state=0).fit(X)  # linked: no warning


def test_the_function_matches_the_estimator():
    from sklearn_gpca import power_factorization

    X = _matrices.remove(_matrices.low_rank() + 0.01, 0.3)
    pf = PowerFactorization(5, whiten=False, random_state=2).fit(X)
    Z, components, singular_values = power_factorization(
        X, 5, whiten=False, random_state=2
    )
    assert_allclose(Z, pf.transform(X), atol=1e-10)
    assert_allclose(components, pf.components_)
    assert_allclose(singular_values, pf.singular_values_)
