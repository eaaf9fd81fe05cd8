"""Tests for the over-segmentation and the greedy merge of fragments."""

# SPDX-License-Identifier: BSD-3-Clause

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_array_equal

from sklearn_gpca._fragments import (
    _group_medians,
    absorb_small_fragments,
    merge_fragments,
    over_segment,
)
from sklearn_gpca._hypotheses import local_noise_level
from sklearn_gpca._motion_graph import motion_affinity
from sklearn_gpca._observed_subspaces import (
    fit_adaptive_subspace,
    observed_entries,
    subspace_residuals,
)
from sklearn_gpca._track_neighbors import track_neighbors
from sklearn_gpca.datasets import make_motions, make_tracks
from sklearn_gpca.metrics import misclassification_rate


def _reference_merge(X0, mask, fragments, n_clusters, noise, max_dim=8, min_dof=4):
    """The greedy merge as first written: a dict of linkages over fragment
    pairs, every linkage of the merged fragment recomputed from its tracks."""
    groups = {g: np.flatnonzero(fragments == g) for g in np.unique(fragments)}

    def fit(index):
        return fit_adaptive_subspace(X0[index], mask[index], noise, max_dim=max_dim)

    fits = {g: fit(index) for g, index in groups.items()}

    def misfit(a, b):
        index = groups[b]
        residuals, dofs = subspace_residuals(
            X0[index], mask[index], [fits[a][0]], [fits[a][1]]
        )
        usable = dofs[:, 0] >= min_dof
        if not usable.any():
            return np.inf
        return float(np.median(residuals[usable, 0] / dofs[usable, 0]) / noise)

    def linkage(a, b):
        return min(misfit(a, b), misfit(b, a))

    keys = sorted(groups)
    links = {(a, b): linkage(a, b) for i, a in enumerate(keys) for b in keys[i + 1 :]}
    while len(groups) > n_clusters:
        a, b = min(links, key=links.get)
        groups[a] = np.concatenate([groups[a], groups.pop(b)])
        fits.pop(b)
        fits[a] = fit(groups[a])
        links = {p: v for p, v in links.items() if a not in p and b not in p}
        for g in groups:
            if g != a:
                links[(min(a, g), max(a, g))] = linkage(a, g)
    labels = np.empty(fragments.shape[0], dtype=np.intp)
    for new, index in enumerate(groups.values()):
        labels[index] = new
    return labels


def _fragments_of_a_draw(seed, n_tracks=300, n_frames=15):
    X, _ = make_tracks(
        3,
        scene="lab",
        n_tracks=n_tracks,
        n_frames=n_frames,
        missing=0.3,
        random_state=seed,
    )
    X0, mask = observed_entries(X)
    X0 /= np.sqrt(np.mean(X0[mask] ** 2))
    affinity = motion_affinity(X0, mask, track_neighbors(X0, mask, 20))
    fragments = over_segment(
        affinity, n_tracks // 20, random_state=np.random.RandomState(seed)
    )
    return X0, mask, absorb_small_fragments(affinity, fragments, 6)


@pytest.mark.parametrize("seed", range(2))
def test_merge_fragments_equals_the_pairwise_reference(seed):
    X0, mask, fragments = _fragments_of_a_draw(seed)
    assert fragments.max() + 1 > 6
    neighbors = track_neighbors(X0, mask, 20)
    noise = local_noise_level(
        X0, mask, neighbors, random_state=np.random.RandomState(0)
    )
    for n_clusters in (2, 5):
        assert_array_equal(
            merge_fragments(X0, mask, fragments, n_clusters, noise),
            _reference_merge(X0, mask, fragments, n_clusters, noise),
        )


def test_large_groups_are_fitted_on_a_spread_of_their_tracks(monkeypatch):
    # the cap keeps each refit bounded (linear merging cost); with groups
    # fitted on 50 evenly spread tracks, 30 fragments of three motions of 200
    # tracks with 30 % occlusion still merge into the motions
    import sklearn_gpca._fragments as fragments_module

    X, y = make_motions(
        3,
        n_points=[200, 200, 200],
        n_frames=10,
        missing=0.3,
        missing_pattern="occlusion",
        random_state=0,
    )
    X0, mask = observed_entries(X)
    X0 /= np.sqrt(np.mean(X0[mask] ** 2))
    sizes = []

    def recorded(X0, mask, noise, max_dim):
        sizes.append(X0.shape[0])
        return fit_adaptive_subspace(X0, mask, noise, max_dim=max_dim)

    monkeypatch.setattr(fragments_module, "MAX_GROUP_TRACKS", 50)
    monkeypatch.setattr(fragments_module, "fit_adaptive_subspace", recorded)
    fragments = y * 10 + np.arange(y.size) % 10
    labels = merge_fragments(X0, mask, fragments, 3, 1e-4)
    assert max(sizes) == 50
    assert misclassification_rate(y, labels) == 0.0


def test_merge_fragments_takes_any_fragment_labels():
    X0, mask, fragments = _fragments_of_a_draw(0, n_tracks=120)
    labels = merge_fragments(X0, mask, fragments, 3, 1e-4)
    sparse_labels = merge_fragments(X0, mask, 7 * fragments + 2, 3, 1e-4)
    assert_array_equal(sparse_labels, labels)
    assert_array_equal(np.unique(labels), [0, 1, 2])


@pytest.mark.parametrize("n_clusters", [1, 2, 5])
def test_merge_fragments_without_evidence_still_merges_to_n_clusters(n_clusters):
    """With 4 coordinates no track has ``min_dof`` residual degrees of
    freedom: every linkage is inf, and the merges still go down to
    ``n_clusters`` (a tie must not pair a fragment with itself)."""
    rng = np.random.RandomState(0)
    X0 = rng.standard_normal((70, 4))
    fragments = np.repeat(np.arange(7), 10)
    labels = merge_fragments(
        X0, np.ones_like(X0, dtype=bool), fragments, n_clusters, 1.0
    )
    assert_array_equal(np.unique(labels), np.arange(n_clusters))
    # fragments are merged whole
    assert all(np.unique(labels[fragments == g]).size == 1 for g in range(7))


@settings(max_examples=50, deadline=None)
@given(
    values=st.lists(
        st.one_of(
            st.floats(0, 1e6, allow_nan=False),
            st.just(np.nan),
            st.just(np.inf),
        ),
        min_size=1,
        max_size=40,
    ),
    data=st.data(),
)
def test_group_medians_are_numpys_medians_of_the_finite_values(values, data):
    values = np.array(values)
    n_groups = data.draw(st.integers(1, 5))
    groups = np.array(
        data.draw(
            st.lists(
                st.integers(0, n_groups - 1), min_size=values.size, max_size=values.size
            )
        )
    )
    expected = []
    for g in range(n_groups):
        mine = values[(groups == g) & np.isfinite(values)]
        expected.append(np.median(mine) if mine.size else np.inf)
    assert_array_equal(_group_medians(values, groups, n_groups), expected)
