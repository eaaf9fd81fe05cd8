"""With 4 motions or more the segmentation runs at two fragment sizes and the
consistency rule keeps one."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
from sklearn.utils import check_random_state

from sklearn_gpca import segment_motions
from sklearn_gpca._fragments import TRACKS_PER_FRAGMENT
from sklearn_gpca._segment import FINE_TRACKS_PER_FRAGMENT, _fragment_sizes_judged
from sklearn_gpca.datasets import make_tracks


@pytest.fixture(scope="module")
def four_motions():
    X, y = make_tracks(
        scene="lab", n_motions=4, n_frames=20, camera="affine", random_state=0
    )[:2]
    return X[y >= 0], y[y >= 0]


def _swapped(y, share, seed=0):
    """``y`` with ``share`` of the tracks given another motion."""
    rng = np.random.RandomState(seed)
    wrong = y.copy()
    moved = rng.choice(y.size, int(share * y.size), replace=False)
    wrong[moved] = (y[moved] + 1 + rng.randint(y.max(), size=moved.size)) % (
        y.max() + 1
    )
    return wrong


def _fake_segment(by_size, calls):
    def segment(*, per_fragment, random_state):
        rng = check_random_state(random_state)
        calls.append((per_fragment, rng.get_state()[1].copy()))
        rng.randint(10)  # a run draws from its random state
        return by_size[per_fragment]

    return segment


@pytest.mark.parametrize("fine_is_true", [True, False])
def test_the_rule_keeps_the_run_that_fits(four_motions, fine_is_true):
    X, y = four_motions
    wrong = _swapped(y, 0.2)
    by_size = {
        FINE_TRACKS_PER_FRAGMENT: y if fine_is_true else wrong,
        TRACKS_PER_FRAGMENT: wrong if fine_is_true else y,
    }
    calls = []
    labels = _fragment_sizes_judged(
        _fake_segment(by_size, calls),
        X,
        4,
        random_state=np.random.RandomState(3),
        return_info=False,
        subspace_dim=4,
        perspective_background=False,
        n_jobs=None,
    )
    np.testing.assert_array_equal(labels, y)
    assert [size for size, _ in calls] == [
        TRACKS_PER_FRAGMENT,
        FINE_TRACKS_PER_FRAGMENT,
    ]
    # each run starts from the same state, not from where the other left it
    first, second = (state for _, state in calls)
    np.testing.assert_array_equal(first, second)


def test_outlier_labels_are_left_out_of_the_judgement(four_motions):
    X, y = four_motions
    coarse, fine = y.copy(), _swapped(y, 0.2)
    # the true run calls a fifth of the tracks outliers: judged on the
    # others it still fits better
    coarse[::5] = -1
    labels = _fragment_sizes_judged(
        _fake_segment(
            {TRACKS_PER_FRAGMENT: coarse, FINE_TRACKS_PER_FRAGMENT: fine}, []
        ),
        X,
        4,
        random_state=0,
        return_info=False,
        subspace_dim=4,
        perspective_background=False,
        n_jobs=None,
    )
    np.testing.assert_array_equal(labels, coarse)


def test_segment_motions_reports_the_kept_fragment_size(four_motions):
    X, y = four_motions
    labels, info = segment_motions(
        X,
        4,
        init="auto",
        perspective_background=False,
        random_state=0,
        return_info=True,
    )
    assert info.per_fragment in (TRACKS_PER_FRAGMENT, FINE_TRACKS_PER_FRAGMENT)
    assert set(np.unique(labels)) <= set(range(4))
    # the two runs start from copies of the state: the same state, the same labels
    again = segment_motions(
        X,
        4,
        init="auto",
        perspective_background=False,
        random_state=np.random.RandomState(0),
    )
    np.testing.assert_array_equal(
        again,
        segment_motions(
            X,
            4,
            init="auto",
            perspective_background=False,
            random_state=np.random.RandomState(0),
        ),
    )
    _, info = segment_motions(
        X[y < 3],
        3,
        init="auto",
        perspective_background=False,
        random_state=0,
        return_info=True,
    )
    assert info.per_fragment == TRACKS_PER_FRAGMENT
