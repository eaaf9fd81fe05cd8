"""Tests for the groups' fitted dimensions and selection="fitted_separability"."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest

from sklearn_gpca._fitted_dimensions import (
    fitted_ambiguous_fraction,
    group_dimensions,
)
from sklearn_gpca._observed_subspaces import observed_entries
from sklearn_gpca._segment import AMBIGUITY_TOLERANCE, segment_motions
from sklearn_gpca._segment_selection import ambiguous_fraction, select_segmentation


def _tracks(bases, sizes, missing=0.0, seed=0):
    """Tracks on the given subspaces (columns), unit noise, 100 x signal."""
    rng = np.random.RandomState(seed)
    n_features = bases[0].shape[0]
    blocks = [
        100.0 * rng.standard_normal((size, b.shape[1])) @ b.T
        for b, size in zip(bases, sizes, strict=True)
    ]
    X = np.vstack(blocks) + rng.standard_normal((sum(sizes), n_features))
    unseen = rng.rand(X.shape[0], n_features // 2) < missing
    X[np.repeat(unseen, 2, axis=1)] = np.nan
    return X


def _split_background(missing, seed):
    """A 6-D background made of two 4-D halves sharing 2 dimensions (as a
    perspective background's near and far halves), and two 4-D objects.

    Returns the tracks, the truth and the wrong segmentation that cuts the
    background into its halves and merges the objects.
    """
    rng = np.random.RandomState(100 + seed)
    n_features = 40
    q = np.linalg.qr(rng.standard_normal((n_features, 14)))[0]
    half_a, half_b = q[:, [0, 1, 2, 3]], q[:, [0, 1, 4, 5]]
    objects = [q[:, 6:10], q[:, 10:14]]
    X = _tracks([half_a, half_b, *objects], [150, 150, 60, 60], missing, seed)
    truth = np.repeat([0, 0, 1, 2], [150, 150, 60, 60])
    wrong = np.repeat([0, 1, 2, 2], [150, 150, 60, 60])
    return X, truth, wrong


@pytest.mark.parametrize("missing", [0.0, 0.3])
@pytest.mark.parametrize("seed", range(2))
def test_fitted_dimensions_keep_the_split_background_apart(missing, seed):
    X, truth, wrong = _split_background(missing, seed)
    X0, mask = observed_entries(X)
    # derived: the background spans 6 dimensions, each object 4; no union of
    # two groups fits fewer than 8, so no cap applies
    dims = group_dimensions(X0, mask, truth, 1.0, min_dim=3, max_dim=7)
    np.testing.assert_array_equal(dims, [6, 4, 4])
    # the wrong candidate's halves need 4 each, the merged objects more
    # than 7 (they span 8): 7
    wrong_dims = group_dimensions(X0, mask, wrong, 1.0, min_dim=3, max_dim=7)
    np.testing.assert_array_equal(wrong_dims, [4, 4, 7])
    # at its own dimension the true background fits its tracks and none is
    # ambiguous; at the fixed dimension 3 its misfit leaves many ambiguous,
    # the failure that selection="fitted_separability" addresses
    right = fitted_ambiguous_fraction(X0, mask, truth, 1.0, min_dim=3, max_dim=7)
    fixed = ambiguous_fraction(X0, mask, truth, 1.0, subspace_dim=3)
    assert right < 0.01
    assert fixed > 0.15


def test_union_caps_a_group_that_would_hold_another():
    # a 3-D background inside the 5-D span of an object that moves with it
    # (nearly dependent motions, as in make_tracks' "lab" scene): the union
    # needs 5 dimensions, as the object alone does
    rng = np.random.RandomState(0)
    q = np.linalg.qr(rng.standard_normal((40, 5)))[0]
    X = _tracks([q[:, :3], q], [200, 100])
    X0, mask = observed_entries(X)
    truth = np.repeat([0, 1], [200, 100])
    dims = group_dimensions(X0, mask, truth, 1.0, min_dim=3, max_dim=7)
    # derived: the object needs 5, the union 5 too, so the object keeps 4
    np.testing.assert_array_equal(dims, [3, 4])
    # without the cap (the object alone) it needs 5
    alone = group_dimensions(X0, mask, np.ones(300, int), 1.0, min_dim=3, max_dim=7)
    np.testing.assert_array_equal(alone, [5])


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"min_dim": 0, "max_dim": 7}, "min_dim"),
        ({"min_dim": 5, "max_dim": 4}, "min_dim"),
        ({"min_dim": 3, "max_dim": 7, "noise": 0.0}, "noise"),
        ({"min_dim": 3, "max_dim": 7, "noise": np.nan}, "noise"),
    ],
)
def test_group_dimensions_rejects_bad_arguments(kwargs, match):
    X0, mask = observed_entries(np.ones((10, 8)))
    kwargs = {"noise": 1.0, **kwargs}
    noise = kwargs.pop("noise")
    with pytest.raises(ValueError, match=match):
        group_dimensions(X0, mask, np.arange(10) % 2, noise, **kwargs)


@pytest.mark.parametrize("subspace_dim", [[3], [3, 0], [3.0, 4.0], 0])
def test_ambiguous_fraction_rejects_bad_dimensions(subspace_dim):
    X0, mask = observed_entries(np.random.RandomState(0).rand(20, 8))
    with pytest.raises(ValueError, match="subspace_dim"):
        ambiguous_fraction(X0, mask, np.arange(20) % 2, 1.0, subspace_dim=subspace_dim)


def test_segment_motions_fitted_separability_reports_both_criteria():
    X, _, _ = _split_background(0.3, 0)
    # without screening, the info describes every track
    labels, info = segment_motions(
        X,
        3,
        selection="fitted_separability",
        screen_outliers=False,
        random_state=0,
        return_info=True,
    )
    assert info.fitted_ambiguity.shape == info.ambiguity.shape
    judged = ~np.isnan(info.ambiguity)
    assert np.isfinite(info.fitted_ambiguity[judged]).all()
    # the kept candidate is the rule's choice among the refined ones
    expected = select_segmentation(
        info.coding_lengths,
        np.fmax(info.ambiguity, info.fitted_ambiguity),
        selection="separability",
        tolerance=AMBIGUITY_TOLERANCE,
    )
    np.testing.assert_array_equal(labels, info.refined[expected])
