"""Tests for sklearn_gpca.metrics.oracle_labels."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest

from sklearn_gpca._observed_subspaces import fit_observed_subspace, observed_entries
from sklearn_gpca.datasets import make_motions, make_tracks
from sklearn_gpca.metrics import misclassification_rate, oracle_labels


@pytest.mark.parametrize("missing", [0.0, 0.3])
def test_oracle_separates_generic_motions(missing):
    X, y = make_motions(
        3, n_points=[120, 40, 40], n_frames=10, missing=missing, random_state=0
    )
    labels = oracle_labels(X, y)
    assert set(np.unique(labels)) <= set(np.unique(y))
    assert misclassification_rate(y, labels) == 0.0


def test_oracle_keeps_outliers_and_labels():
    X, y = make_motions(2, n_points=60, n_frames=8, random_state=1)
    y = np.where(y == 1, 7, y)
    y[:3] = -1
    labels = oracle_labels(X, y)
    assert np.all(labels[:3] == -1)
    assert set(labels[3:]) <= {0, 7}


def test_oracle_without_evidence_gets_largest_group():
    X, y = make_motions(2, n_points=[50, 20], n_frames=8, random_state=2)
    X[0, 4:] = np.nan  # 4 coordinates <= subspace_dim=4: no evidence
    labels = oracle_labels(X, y)
    largest = np.bincount(y).argmax()
    assert labels[0] == largest


def test_oracle_assigns_by_residual_per_degree_of_freedom():
    # group 1 is seen on the first 5 frames only: its subspace is determined
    # on 10 of the 20 coordinates, so a group-0 track has 16 residual degrees
    # of freedom to subspace 0 and 6 to subspace 1
    rng = np.random.RandomState(4)
    X, y = make_motions(2, n_points=[80, 80], n_frames=10, noise=3.0, random_state=4)
    X[y == 1, 10:] = np.nan
    labels = oracle_labels(X, y)
    X0, mask = observed_entries(X)
    fits = [fit_observed_subspace(X0[y == g], mask[y == g], 4) for g in (0, 1)]
    for p in rng.choice(len(y), 20, replace=False):
        per_dof = []
        for basis, support in fits:
            seen = mask[p] & support
            z, *_ = np.linalg.lstsq(basis[seen], X[p, seen], rcond=None)
            r = X[p, seen] - basis[seen] @ z
            per_dof.append(r @ r / (seen.sum() - 4))
        assert labels[p] == np.argmin(per_dof)


@pytest.mark.parametrize(
    ("X", "y", "match"),
    [
        (np.zeros(5), np.zeros(5), "2-D"),
        (np.zeros((5, 4)), np.zeros(4), "one label per row"),
        (np.full((5, 4), np.inf), np.zeros(5), "infinite"),
    ],
)
def test_oracle_bad_input(X, y, match):
    with pytest.raises(ValueError, match=match):
        oracle_labels(X, y)


def test_perspective_background_oracle_holds_a_deep_background():
    """Over 100 hand-held frames the background fits no 4-D subspace: the
    nearest true model with a perspective background errs far less."""
    X, y = make_tracks(scene="handheld", n_tracks=400, random_state=3)
    inliers = y >= 0
    X, y = X[inliers], y[inliers]
    affine = misclassification_rate(y, oracle_labels(X, y))
    perspective = misclassification_rate(
        y, oracle_labels(X, y, perspective_background=True)
    )
    assert perspective < 0.02 < affine


def test_oracle_fits_the_true_subspaces_to_convergence():
    # 62 % missing: 30 alternations leave the background's subspace far from
    # its least-squares fit, and the oracle errs on 5.5 % of the tracks
    X, y = make_tracks(scene="driving", random_state=0)[:2]
    X, y = X[y >= 0], y[y >= 0]
    assert misclassification_rate(y, oracle_labels(X, y)) < 0.045
