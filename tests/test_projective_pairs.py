"""The perspective fit's steps on the seen point-frames (sklearn_gpca._projective_pairs)
agree with the dense steps of sklearn_gpca._projective_motion."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest

import sklearn_gpca._projective_pairs as pairs
from sklearn_gpca._observed_subspaces import observed_entries
from sklearn_gpca._projective_motion import (
    fit_projective_motion,
    projective_residuals,
    track_frames,
    triangulate,
)
from sklearn_gpca.datasets import make_tracks


def _sparse_tracks(seed=0):
    """A hand-held background over 60 frames, 85 % of its entries missing."""
    X, y = make_tracks(
        scene="handheld", n_tracks=300, n_frames=60, missing=0.85, random_state=seed
    )
    X = X[y == np.bincount(y[y >= 0]).argmax()]
    X[0] = np.nan  # a track seen nowhere: no point-frame at all
    X[1, 2:] = np.nan  # and one seen in a single frame
    X0, mask = observed_entries(X)
    return X0, mask


def _routes(monkeypatch, function):
    """``function()`` on the dense steps and on the seen point-frames."""
    results = []
    for density in (0.0, 1.01):
        monkeypatch.setattr(pairs, "MAX_DENSITY", density)
        results.append(function())
    return results


def _same_cameras(a, b):
    a = a / np.linalg.norm(a.reshape(len(a), -1), axis=1)[:, None, None]
    b = b / np.linalg.norm(b.reshape(len(b), -1), axis=1)[:, None, None]
    sign = np.sign(np.einsum("fij,fij->f", a, b))[:, None, None]
    return np.max(np.abs(a - sign * b))


def test_sparse_tracks_take_the_seen_point_frames():
    _, mask = _sparse_tracks()
    seen = mask[:, 0::2] & mask[:, 1::2]
    assert seen.mean() < pairs.MAX_DENSITY
    assert pairs.sparse_enough(seen)
    assert not pairs.sparse_enough(np.ones((5, 4), dtype=bool))
    assert not pairs.sparse_enough(np.zeros((0, 4), dtype=bool))


def test_triangulation_agrees(monkeypatch):
    X0, mask = _sparse_tracks()
    cameras, _ = fit_projective_motion(X0, mask)
    points, seen = track_frames(X0, mask)
    dense, flat = _routes(monkeypatch, lambda: triangulate(cameras, points, seen))
    # unit vectors up to sign; the tracks seen in two frames or more
    informative = seen.sum(axis=1) >= 2
    sign = np.sign(np.sum(dense * flat, axis=1))[:, None]
    assert np.max(np.abs(dense - sign * flat)[informative]) < 1e-6


def test_warm_fit_and_residuals_agree(monkeypatch):
    X0, mask = _sparse_tracks()
    start, _ = fit_projective_motion(X0, mask)

    def warm():
        cameras, supported = fit_projective_motion(X0, mask, cameras=start)
        return cameras, *projective_residuals(X0, mask, cameras, supported)

    (dense, r_dense, d_dense), (flat, r_flat, d_flat) = _routes(monkeypatch, warm)
    assert _same_cameras(dense, flat) < 1e-6
    np.testing.assert_array_equal(d_dense, d_flat)
    np.testing.assert_allclose(r_flat, r_dense, rtol=1e-6, atol=1e-12)
    assert r_flat[0] == 0 and d_flat[0] == 0  # the track seen nowhere


def test_fit_from_scratch_agrees(monkeypatch):
    X0, mask = _sparse_tracks(seed=1)

    def scratch():
        cameras, supported = fit_projective_motion(X0, mask)
        return cameras[supported]

    dense, flat = _routes(monkeypatch, scratch)
    assert _same_cameras(dense, flat) < 1e-6


@pytest.mark.parametrize("seed", [0, 1])
def test_seen_point_frames_fit_noise_free_tracks(seed, monkeypatch):
    # noise-free perspective tracks are fitted exactly on this route too
    X, y = make_tracks(
        scene="handheld",
        n_tracks=200,
        n_frames=40,
        missing=0.8,
        noise=0.0,
        random_state=seed,
    )
    X0, mask = observed_entries(X[y == np.bincount(y[y >= 0]).argmax()])
    monkeypatch.setattr(pairs, "MAX_DENSITY", 1.01)
    cameras, supported = fit_projective_motion(X0, mask)
    residuals, dofs = projective_residuals(X0, mask, cameras, supported)
    assert np.max(residuals[dofs > 0] / dofs[dofs > 0]) < 1e-10
