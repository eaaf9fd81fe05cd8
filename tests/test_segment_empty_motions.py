"""The consistency rule keeps candidates that model every motion asked for."""

# SPDX-License-Identifier: BSD-3-Clause

import warnings

import numpy as np

from sklearn_gpca import segment_motions
from sklearn_gpca._segment import (
    _all_motions_modelled,
    _consistency_choice,
    _reverts_to_kept,
)
from sklearn_gpca.datasets import make_tracks
from sklearn_gpca.metrics import misclassification_rate


def test_all_motions_modelled_counts_common_tracks():
    labels = np.repeat([0, 1, 2], [10, 10, 5])
    common = np.ones(labels.size, dtype=bool)
    assert _all_motions_modelled([labels], common, 3, 4).tolist() == [True]
    # four tracks of motion 2 fit any 4-D subspace exactly: not a model
    common[-1] = False
    assert _all_motions_modelled([labels], common, 3, 4).tolist() == [False]
    # a motion with no track at all
    assert _all_motions_modelled([labels], np.ones(25, bool), 4, 4).tolist() == [False]


def test_consistency_choice_skips_candidates_with_unmodelled_motions():
    # (inconsistency, residual): the first fits best but leaves a motion empty
    scores = np.array([[0.0, 250.0], [0.01, 240.0], [0.02, 300.0]])
    assert _consistency_choice(scores, 300) == 0
    assert _consistency_choice(scores, 300, np.array([False, True, True])) == 1
    # none models every motion: the penalised fit alone decides
    assert _consistency_choice(scores, 300, np.zeros(3, dtype=bool)) == 0
    # an eligible candidate that was not judged does not exclude the others
    unjudged = scores.copy()
    unjudged[1] = np.nan
    assert _consistency_choice(unjudged, 300, np.array([False, True, False])) == 0


def test_significance_guard_keeps_a_choice_that_models_every_motion():
    def not_better():
        return False

    def never_asked():
        raise AssertionError("the test decides nothing here")

    # both model every motion (or neither): back to the kept one unless the
    # choice is significantly better
    assert _reverts_to_kept(np.array([True, True]), 0, 1, not_better)
    assert not _reverts_to_kept(np.array([True, True]), 0, 1, lambda: True)
    assert _reverts_to_kept(np.array([False, False]), 1, 0, not_better)
    # the choice models every motion, the kept one leaves a motion empty
    assert not _reverts_to_kept(np.array([False, True]), 0, 1, never_asked)
    # the kept one models every motion, the choice does not
    assert _reverts_to_kept(np.array([True, False]), 0, 1, not_better)


def test_segment_motions_finds_a_small_motion_not_an_empty_one():
    # 360 hand-held tracks over 40 frames, half the entries missing: a
    # candidate that merges the 64-track motion into the background and
    # leaves its label empty has the least penalised fit (no model to misfit)
    X, y = make_tracks(
        scene="handheld",
        n_tracks=400,
        n_frames=40,
        missing=0.5,
        outlier_fraction=0.1,
        random_state=11,
    )
    X, y = X[y >= 0], y[y >= 0]
    with warnings.catch_warnings():
        warnings.simplefilter("error", UserWarning)
        labels = segment_motions(X, 3, random_state=0)
    assert np.bincount(labels[labels >= 0], minlength=3).min() > 4
    assert misclassification_rate(y, labels) < 0.05
