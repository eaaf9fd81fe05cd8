"""Real tracker output: the giraffe video's background and foreground tracks.

``Um_giraffe_bg`` and ``Um_giraffe_fg`` (``../shared/data/lowrank``) are the
two motions of one 190-frame video, each track seen on a short window (median
11 frames), 92 % of the entries missing; see
``benchmarks/check_real_composite.py``.
"""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest

from sklearn_gpca._observed_subspaces import observed_entries
from sklearn_gpca._segment import fragment_candidates, track_graph
from sklearn_gpca.datasets import load_lowrank
from sklearn_gpca.metrics import misclassification_rate


@pytest.fixture(scope="module")
def giraffe(lowrank_dir):
    """An eighth of the tracks (1,445), as the benchmark's seed 0 draws them."""
    background = load_lowrank("Um_giraffe_bg", data_home=lowrank_dir).X
    foreground = load_lowrank("Um_giraffe_fg", data_home=lowrank_dir).X
    X = np.vstack([background, foreground])
    y = np.r_[np.zeros(len(background), int), np.ones(len(foreground), int)]
    keep = np.random.RandomState(0).rand(len(X)) < 0.125
    return X[keep], y[keep]


def test_a_fragments_candidate_finds_the_real_motions(giraffe):
    # the noise measured between neighbours is far below the models' misfit
    # here, so the merge's groups all reach 8 dimensions and the two motions
    # fit one of them (45 % error): the low-dimensional merge keeps them
    # apart (5 %); the nearest true subspace errs 0.3 %
    X, y = giraffe
    X0, mask = observed_entries(X / np.sqrt(np.nanmean(X**2)))
    _, noise, affinity, _ = track_graph(
        X0, mask, 10, random_state=np.random.RandomState(0)
    )
    found = fragment_candidates(
        X0,
        mask,
        affinity,
        2,
        noise,
        subspace_dim=4,
        random_state=np.random.RandomState(0),
    )
    errors = {name: misclassification_rate(y, labels) for name, labels in found}
    assert min(errors.values()) < 0.1, errors
