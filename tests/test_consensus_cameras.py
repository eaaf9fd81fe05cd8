"""The perspective refinements start from one fit of the background the
candidates agree on (sklearn_gpca._segment._consensus_cameras)."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest

import sklearn_gpca._refine_observed as refine_module
from sklearn_gpca import segment_motions
from sklearn_gpca._hypotheses import local_noise_level
from sklearn_gpca._projective_motion import projective_residuals
from sklearn_gpca._refine_observed import refine_observed
from sklearn_gpca._segment import _consensus_cameras, _scaled_tracks
from sklearn_gpca._track_neighbors import track_neighbors
from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.metrics import misclassification_rate


class _Tracks:
    """The fields of the refiner that ``_consensus_cameras`` reads."""

    def __init__(self, X0, mask, n_motions):
        self.X0, self.mask, self.n_motions = X0, mask, n_motions
        neighbors = track_neighbors(X0, mask, n_neighbors=10)
        self.noise = local_noise_level(
            X0, mask, neighbors, random_state=np.random.RandomState(0)
        )


@pytest.fixture(scope="module")
def lab():
    X, y = make_tracks(scene="lab", n_frames=30, missing=0.4, random_state=2)[:2]
    keep = y >= 0
    X0, mask, _ = _scaled_tracks(X[keep])
    return X0, mask, y[keep]


def _count_cold_fits(monkeypatch):
    """Record, for each perspective fit of a refinement, whether it was cold."""
    calls = []
    fit = refine_module.fit_projective_motion

    def counted(X0, mask, *, cameras=None):
        calls.append(cameras is None)
        return fit(X0, mask, cameras=cameras)

    monkeypatch.setattr(refine_module, "fit_projective_motion", counted)
    return calls


def test_consensus_cameras_fit_the_background_the_starts_agree_on(lab):
    X0, mask, y = lab
    background = np.argmax(np.bincount(y))
    rng = np.random.default_rng(0)
    # three starts that each move a different twentieth of the background
    # away, and one whose larger motion is the other motion and 40 % of it
    starts = []
    for _ in range(3):
        start = y.copy()
        start[(rng.random(y.size) < 0.05) & (y == background)] = 1 - background
        starts.append(start)
    mixed = y.copy()
    mixed[(rng.random(y.size) < 0.4) & (y == background)] = 1 - background
    mixed = 1 - mixed
    starts.append(mixed)
    assert np.sum(mixed == np.argmax(np.bincount(mixed))) > 0.8 * np.sum(
        y != background
    )
    found = _consensus_cameras(_Tracks(X0, mask, 2), starts)
    assert [c is None for c in found] == [False, False, False, True]
    cameras = found[0]
    assert cameras.shape == (mask.shape[1] // 2, 3, 4)
    assert all(c is cameras for c in found[:3])
    supported = np.ones(cameras.shape[0], dtype=bool)
    residuals, dofs = projective_residuals(X0, mask, cameras, supported)
    per_dof = residuals / np.maximum(dofs, 1)
    ours = np.median(per_dof[(y == background) & (dofs > 0)])
    theirs = np.median(per_dof[(y != background) & (dofs > 0)])
    assert ours < theirs / 10


def test_consensus_cameras_start_a_part_of_the_background_not_a_mixture(lab):
    X0, mask, y = lab
    background = np.argmax(np.bincount(y))
    rng = np.random.default_rng(1)
    agreeing = y.copy()
    agreeing[(rng.random(y.size) < 0.05) & (y == background)] = 1 - background
    # a fifth of the background cut off (a different set of tracks from the
    # consensus by more than CONSENSUS_DIFFERENCE): the consensus cameras
    # explain the rest; a background with a third of the other motion
    # mixed in: they do not
    part = y.copy()
    part[(rng.random(y.size) < 0.2) & (y == background)] = 1 - background
    mixture = y.copy()
    mixture[(rng.random(y.size) < 0.33) & (y != background)] = background
    starts = [agreeing, agreeing.copy(), part, mixture]
    largest = [s == np.argmax(np.bincount(s)) for s in starts]
    assert np.all(largest[2] <= (y == background))
    assert np.count_nonzero(largest[2] ^ largest[0]) > 0.1 * np.sum(largest[2])
    found = _consensus_cameras(_Tracks(X0, mask, 2), starts)
    assert [c is None for c in found] == [False, False, False, True]


def test_consensus_cameras_none_when_the_starts_disagree(lab):
    X0, mask, y = lab
    n, half = y.size, y.size // 2
    index = np.arange(n)
    # each start's larger motion is half the tracks and 3 more, a different
    # half: they share 6 tracks
    first = (index < half + 3).astype(np.intp)
    second = (index >= half - 3).astype(np.intp)
    tracks = _Tracks(X0, mask, 2)
    assert _consensus_cameras(tracks, [first, second]) == [None, None]
    assert _consensus_cameras(tracks, []) == []


def test_refinement_from_given_cameras_fits_none_from_scratch(lab, monkeypatch):
    X0, mask, y = lab
    neighbors = track_neighbors(X0, mask, n_neighbors=10)
    background = int(np.argmax(np.bincount(y)))
    common = dict(
        neighbors=neighbors,
        perspective_cluster=background,
        random_state=np.random.RandomState(0),
    )
    calls = _count_cold_fits(monkeypatch)
    cold = refine_observed(X0, mask, y, 2, **common)
    assert calls[0] and not any(calls[1:])
    calls.clear()
    warm = refine_observed(
        X0, mask, y, 2, perspective_cameras=cold[1][background], **common
    )
    assert calls and not any(calls)
    assert misclassification_rate(cold[0], warm[0]) < 0.01


def test_segment_motions_refines_every_perspective_start_warm(monkeypatch):
    X, y = make_tracks(scene="lab", n_frames=30, missing=0.4, random_state=3)[:2]
    keep = y >= 0
    calls = _count_cold_fits(monkeypatch)
    labels = segment_motions(X[keep], 2, random_state=0)
    assert calls and not any(calls)
    assert misclassification_rate(y[keep], labels) < 0.05
