"""Tests for the gpca route of segment_motions (``_segment.gpca_candidate``)."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest

from sklearn_gpca import PowerFactorization
from sklearn_gpca._observed_subspaces import observed_entries
from sklearn_gpca._segment import ROUTE_FIT_TRACKS, gpca_candidate
from sklearn_gpca.datasets import make_motions
from sklearn_gpca.metrics import misclassification_rate


@pytest.fixture
def fitted_rows(monkeypatch):
    """Rows of every ``PowerFactorization.fit`` / ``fit_transform`` call."""
    rows = []
    for name in ("fit", "fit_transform"):
        original = getattr(PowerFactorization, name)

        def spy(self, X, y=None, _original=original):
            rows.append(X.shape[0])
            return _original(self, X, y)

        monkeypatch.setattr(PowerFactorization, name, spy)
    return rows


@pytest.mark.parametrize("n_tracks", [300, ROUTE_FIT_TRACKS + 300])
def test_gpca_route_fits_at_most_route_fit_tracks_and_projects_the_rest(
    fitted_rows, n_tracks
):
    X, y = make_motions(
        2,
        n_points=[n_tracks // 2, n_tracks - n_tracks // 2],
        n_frames=8,
        missing=0.3,
        random_state=0,
    )
    X0, mask = observed_entries(X)
    labels = gpca_candidate(X, X0, mask, 2, random_state=np.random.RandomState(0))
    assert fitted_rows[0] == min(n_tracks, ROUTE_FIT_TRACKS)
    assert labels.shape == (n_tracks,)
    assert misclassification_rate(y, labels) < 0.05
