"""Tests for the criteria that choose among candidate segmentations."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
from _subspace_draws import subspace_tracks

from sklearn_gpca import MotionSegmentation
from sklearn_gpca._observed_subspaces import observed_entries
from sklearn_gpca._segment import (
    AMBIGUITY_TOLERANCE,
    CONSISTENCY_TOLERANCE,
    MISFIT_COST,
    segment_motions,
)
from sklearn_gpca._segment_selection import (
    ambiguous_fraction,
    coding_length,
    select_segmentation,
)
from sklearn_gpca.datasets import make_motions


def _merged_split(y):
    """Motions 1 and 2 merged, motion 0 cut in two halves: still 3 groups."""
    wrong = np.where(y == 2, 1, y)
    zeros = np.flatnonzero(y == 0)
    wrong[zeros[::2]] = 2
    return wrong


@pytest.mark.parametrize("missing", [0.0, 0.3])
@pytest.mark.parametrize("seed", range(3))
def test_ambiguous_fraction_prefers_truth_to_merge_and_split(missing, seed):
    X, y = subspace_tracks(missing=missing, seed=seed)
    X0, mask = observed_entries(X)
    truth = ambiguous_fraction(X0, mask, y, 1.0)
    wrong = ambiguous_fraction(X0, mask, _merged_split(y), 1.0)
    # the halves of motion 0 span one subspace: each of its tracks (half of
    # the draw) fits the other half within noise, so nearly all of them are
    # ambiguous; generic subspaces leave the true motions apart
    assert truth < 0.02
    assert wrong > 0.4
    # the coding length agrees here (complete enough, generic subspaces)
    assert coding_length(X0, y, 1.0, mask) < coding_length(
        X0, _merged_split(y), 1.0, mask
    )


def test_ambiguous_fraction_counts_only_testable_tracks():
    X, y = subspace_tracks()
    wrong = _merged_split(y)
    X0, mask = observed_entries(X)
    n_ambiguous = ambiguous_fraction(X0, mask, wrong, 1.0) * y.size
    # 20 tracks of the split motion (ambiguous: its halves span one subspace)
    # seen in two frames: 4 coordinates leave no residual degree of freedom in
    # 4-D, so they leave the count and the total
    short = np.flatnonzero(y == 0)[:20]
    X[short, 4:] = np.nan
    X0, mask = observed_entries(X)
    found = ambiguous_fraction(X0, mask, wrong, 1.0)
    expected = (n_ambiguous - 20) / (y.size - 20)
    assert found == pytest.approx(expected, abs=2 / y.size)
    mask[:] = False
    mask[:, :4] = True
    assert ambiguous_fraction(X0 * mask, mask, wrong, 1.0) == 0.0


def test_ambiguous_fraction_needs_two_groups():
    X, _ = make_motions(2, n_points=[20, 20], n_frames=6, random_state=0)
    X0, mask = observed_entries(X)
    with pytest.raises(ValueError, match="at least two groups, got 1"):
        ambiguous_fraction(X0, mask, np.zeros(40, dtype=int), 1.0)


@pytest.mark.parametrize(
    ("lengths", "ambiguity", "selection", "expected"),
    [
        ([3.0, 1.0, 2.0], [0.0, 0.5, 0.1], "coding_length", 1),
        # candidate 1 is shortest but ambiguous; 0 and 2 are within 0.02
        ([3.0, 1.0, 2.0], [0.0, 0.5, 0.01], "separability", 2),
        ([3.0, 1.0, 2.0], [0.0, 0.5, 0.1], "separability", 0),
        ([3.0, 1.0, 2.0], [0.2, 0.19, 0.2], "separability", 1),
        # candidate 1 collapsed to one motion (NaN): not eligible, even shortest
        ([3.0, 1.0, 2.0], [0.0, np.nan, 0.01], "separability", 2),
        ([3.0, 1.0, 2.0], [np.nan, np.nan, np.nan], "separability", 1),
        ([3.0, 1.0, 2.0], [0.0, np.nan, 0.1], "coding_length", 1),
    ],
)
def test_select_candidate_rules(lengths, ambiguity, selection, expected):
    chosen = select_segmentation(
        lengths, ambiguity, selection=selection, tolerance=0.02
    )
    assert chosen == expected


@pytest.mark.parametrize(
    ("lengths", "ambiguity", "selection", "match"),
    [
        ([1.0, 2.0], [0.1], "separability", "one shape"),
        ([], [], "separability", "non-empty"),
        ([1.0], [0.1], "bits", "selection must be"),
    ],
)
def test_select_candidate_bad_input(lengths, ambiguity, selection, match):
    with pytest.raises(ValueError, match=match):
        select_segmentation(lengths, ambiguity, selection=selection, tolerance=0.02)


@pytest.mark.parametrize("selection", ["coding_length", "separability", "consistency"])
def test_segment_motions_selection_wiring(selection):
    X, _ = make_motions(2, n_points=[80, 60], n_frames=10, missing=0.2, random_state=0)
    # without screening, the info describes every track
    kwargs = dict(init="all", selection=selection, screen_outliers=False)
    labels, info = segment_motions(X, 2, random_state=0, return_info=True, **kwargs)
    routes = ["gpca", "fragments", "votes"]
    assert info.candidates == routes + [
        f"{r} + perspective background{suffix}"
        for r in routes
        for suffix in ("", ", from its start")
    ]
    assert info.ambiguity.shape == info.coding_lengths.shape == (9,)
    assert np.all((info.ambiguity >= 0) & (info.ambiguity <= 1))
    assert np.all((info.inconsistency >= 0) & (info.inconsistency <= 1))
    expected = select_segmentation(
        info.coding_lengths,
        info.ambiguity,
        selection=selection,
        tolerance=(
            CONSISTENCY_TOLERANCE if selection == "consistency" else AMBIGUITY_TOLERANCE
        ),
        inconsistency=info.inconsistency,
        residual=info.residuals,
        misfit_cost=MISFIT_COST if selection == "consistency" else None,
        n_tracks=X.shape[0],
    )
    assert info.chosen == expected
    assert np.array_equal(labels, info.refined[expected])
    # the function without info picks the same
    plain = segment_motions(X, 2, random_state=0, **kwargs)
    assert np.array_equal(plain, labels)


def test_estimator_selection_and_ambiguity():
    X, _ = make_motions(2, n_points=[60, 60], n_frames=8, random_state=0)
    model = MotionSegmentation(2, selection="separability", random_state=0).fit(X)
    assert model.ambiguity_.shape == (len(model.candidates_),)
    # the estimator exposes the objective the function reports
    _, info = segment_motions(X, 2, random_state=0, return_info=True)
    np.testing.assert_array_equal(model.objectives_, info.objectives)
    np.testing.assert_array_equal(model.inconsistency_, info.inconsistency)
    assert model.inconsistency_.shape == (len(model.candidates_),)
    assert np.isfinite(model.objectives_).all()
    with pytest.raises(ValueError, match="selection"):
        MotionSegmentation(2, selection="bits").fit(X)
    with pytest.raises(ValueError, match="selection"):
        segment_motions(X, 2, selection="bits")


def test_default_candidates_include_votes_and_rule_uses_smallersubspace_tracks():
    X, _ = make_motions(2, n_points=[80, 60], n_frames=10, missing=0.2, random_state=0)
    labels, info = segment_motions(
        X, 2, random_state=0, return_info=True, screen_outliers=False
    )
    routes = ["gpca", "fragments", "votes"]
    assert info.candidates == routes + [
        f"{r} + perspective background{suffix}"
        for r in routes
        for suffix in ("", ", from its start")
    ]
    # the ambiguity of each candidate is measured with 3-D subspaces
    X0, mask = observed_entries(X)
    X0 = X0 / info.scale
    expected = [
        ambiguous_fraction(X0, mask, refined, info.noise, subspace_dim=3)
        for refined in info.refined
    ]
    np.testing.assert_allclose(info.ambiguity, expected)
    assert np.array_equal(labels, info.refined[info.chosen])
