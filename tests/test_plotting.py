"""Tests of the displays in ``sklearn_gpca.plotting`` (Agg backend)."""

# SPDX-License-Identifier: BSD-3-Clause

import subprocess
import sys

import numpy as np
import pytest
from numpy.testing import assert_allclose
from sklearn.base import BaseEstimator, ClusterMixin
from sklearn.cluster import KMeans
from sklearn.pipeline import make_pipeline

from sklearn_gpca import (
    GPCAClustering,
    PowerFactorization,
    ShapeInteractionClustering,
    shape_interaction_matrix,
)
from sklearn_gpca.datasets import make_missing, make_motions
from sklearn_gpca.metrics import misclassification_rate

mpl = pytest.importorskip("matplotlib")
mpl.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from sklearn_gpca.plotting import (  # noqa: E402
    ErrorCurveDisplay,
    SimilarityMatrixDisplay,
    TrajectoryDisplay,
)


@pytest.fixture(autouse=True)
def close_figures():
    yield
    plt.close("all")


@pytest.fixture(scope="module")
def motions():
    return make_motions(
        2,
        n_points=[40, 40],
        n_frames=6,
        missing=0.2,
        missing_pattern="occlusion",
        random_state=0,
    )


def gpca_pipeline(n=2):
    return make_pipeline(
        PowerFactorization(random_state=0), GPCAClustering(n, random_state=0)
    )


def test_import_sklearn_gpca_does_not_import_matplotlib():
    code = "import sys, sklearn_gpca; print('matplotlib' in sys.modules)"
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    )
    assert result.stdout.strip() == "False"


@pytest.mark.parametrize(
    "call",
    [
        lambda: TrajectoryDisplay(np.zeros((2, 6)), [0, 1]).plot(),
        lambda: SimilarityMatrixDisplay(np.eye(2)).plot(),
        lambda: ErrorCurveDisplay([0, 1], [0, 1]).plot(),
    ],
)
def test_clear_error_without_matplotlib(monkeypatch, call):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    with pytest.raises(ImportError, match=r"requires matplotlib: pip install"):
        call()


@pytest.mark.parametrize("kind", ["tracks", "displacement"])
def test_trajectory_display_from_estimator(motions, kind):
    X, y = motions
    display = TrajectoryDisplay.from_estimator(
        gpca_pipeline(), X, y_true=y, kind=kind, frames=(0, 5)
    )
    assert len(display.lines_) == 2
    assert display.ax_.figure is display.figure_
    assert display.ax_.yaxis_inverted()
    legend = [t.get_text() for t in display.ax_.get_legend().get_texts()]
    assert legend[:2] == ["motion 0", "motion 1"]
    assert display.misclassified.shape == (80,)


def test_trajectory_display_matches_labels_to_truth(motions):
    X, y = motions
    display = TrajectoryDisplay.from_predictions(X, 1 - y, y_true=y)
    # Swapped labels are a perfect segmentation: nothing is misclassified.
    assert not display.misclassified.any()
    np.testing.assert_array_equal(display.labels, y)
    assert len(display.ax_.get_legend().get_texts()) == 2


def test_trajectory_display_fitted_estimator_uses_predict(motions):
    X, _ = motions
    X_complete = np.nan_to_num(X)
    model = KMeans(2, n_init=2, random_state=0).fit(X_complete)
    display = TrajectoryDisplay.from_estimator(model, X_complete)
    np.testing.assert_array_equal(display.labels, model.predict(X_complete))


def test_trajectory_display_on_given_axes(motions):
    X, y = motions
    fig, ax = plt.subplots()
    display = TrajectoryDisplay(X, y).plot(ax=ax, invert_yaxis=False, legend=False)
    assert display.ax_ is ax
    assert display.figure_ is fig
    assert not ax.yaxis_inverted()
    assert ax.get_legend() is None


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"kind": "arrows"}, "kind must be"),
        ({"frames": (3, 3)}, "frames must satisfy"),
        ({"frames": (0, 6)}, "frames must satisfy"),
    ],
)
def test_trajectory_display_errors(motions, kwargs, message):
    X, y = motions
    with pytest.raises(ValueError, match=message):
        TrajectoryDisplay(X, y).plot(**kwargs)


def test_trajectory_display_shape_errors(motions):
    X, y = motions
    with pytest.raises(ValueError, match="even number of columns"):
        TrajectoryDisplay(X[:, :-1], y).plot()
    with pytest.raises(ValueError, match="labels has 79 entries"):
        TrajectoryDisplay(X, y[:-1]).plot()


def test_similarity_display_gpca_is_cos_squared(motions):
    X, _ = motions
    pipe = gpca_pipeline().fit(X)
    display = SimilarityMatrixDisplay.from_estimator(pipe)
    normals = pipe[-1].point_normals_
    assert_allclose(display.similarity, (normals @ normals.T) ** 2, atol=1e-12)
    np.testing.assert_array_equal(display.labels, pipe[-1].labels_)
    order = display.order_
    assert np.all(np.diff(pipe[-1].labels_[order]) >= 0)
    image = display.im_.get_array()
    assert_allclose(image, display.similarity[np.ix_(order, order)])


def test_similarity_display_fits_unfitted_and_orders_by_y(motions):
    X, y = motions
    display = SimilarityMatrixDisplay.from_estimator(gpca_pipeline(), X, y=y)
    assert display.similarity.shape == (80, 80)
    np.testing.assert_array_equal(display.labels, y)
    assert len(display.figure_.axes) == 2  # the matrix and its colour bar


def test_similarity_display_affinity_matrix():
    X_complete = make_motions(2, n_points=[30, 30], n_frames=6, random_state=0)[0]
    model = ShapeInteractionClustering(2, random_state=0).fit(X_complete)
    display = SimilarityMatrixDisplay.from_estimator(model, colorbar=False)
    assert_allclose(display.similarity, model.affinity_matrix_)
    assert len(display.figure_.axes) == 1


def test_similarity_display_from_predictions():
    X, y = make_motions(2, n_points=[20, 20], n_frames=6, random_state=0)
    Q = np.abs(shape_interaction_matrix(X, rank=8))
    display = SimilarityMatrixDisplay.from_predictions(Q, y, title="|Q|")
    assert display.ax_.get_title() == "|Q|"
    np.testing.assert_array_equal(np.sort(display.order_), np.arange(40))


def test_similarity_display_errors(motions):
    X, _ = motions
    with pytest.raises(ValueError, match="max_samples=10"):
        SimilarityMatrixDisplay.from_estimator(gpca_pipeline(), X, max_samples=10)
    with pytest.raises(ValueError, match="neither point_normals_"):
        SimilarityMatrixDisplay.from_estimator(
            KMeans(2, n_init=1, random_state=0), np.nan_to_num(X)
        )
    with pytest.raises(ValueError, match="X is required"):
        SimilarityMatrixDisplay.from_estimator(gpca_pipeline())
    with pytest.raises(ValueError, match="must be square"):
        SimilarityMatrixDisplay(np.ones((2, 3))).plot()


def test_error_curve_from_predictions_band():
    errors = np.array([[0.0, 0.1], [0.2, 0.4]])
    display = ErrorCurveDisplay.from_predictions(
        [0.0, 0.5], errors, param_name="missing", name="GPCA"
    )
    assert_allclose(display.line_.get_ydata(), [0.05, 0.3])
    assert display.fill_between_ is not None
    assert display.ax_.get_xlabel() == "missing"
    assert display.ax_.get_ylabel() == "misclassification rate"
    second = ErrorCurveDisplay.from_predictions(
        [0.0, 0.5], [0.3, 0.3], name="other", ax=display.ax_
    )
    assert second.fill_between_ is None
    assert len(display.ax_.get_lines()) == 2


def test_error_curve_from_estimator_missing_fraction():
    X, y = make_motions(2, n_points=[40, 40], n_frames=6, random_state=0)
    values, n_repeats, pattern = [0.0, 0.3], 2, "occlusion"
    display = ErrorCurveDisplay.from_estimator(
        gpca_pipeline(),
        X,
        y,
        param_name="missing_fraction",
        param_values=values,
        n_repeats=n_repeats,
        missing_pattern=pattern,
        random_state=0,
    )
    # random_state seeds the masks, drawn in order: the same fits by hand.
    rng = np.random.RandomState(0)
    expected = [
        [
            misclassification_rate(
                y,
                gpca_pipeline().fit_predict(
                    make_missing(X, value, pattern=pattern, random_state=rng)
                ),
            )
            for _ in range(n_repeats)
        ]
        for value in values
    ]
    assert_allclose(display.errors, expected)
    assert_allclose(display.line_.get_ydata(), np.mean(expected, axis=1))
    assert display.ax_.get_xlabel() == "missing fraction"


def test_error_curve_from_estimator_parameter():
    X, y = make_motions(2, n_points=[40, 40], n_frames=6, random_state=0)
    display = ErrorCurveDisplay.from_estimator(
        gpca_pipeline(),
        X,
        y,
        param_name="powerfactorization__n_components",
        param_values=[4, 5],
    )
    assert display.errors.shape == (2, 1)


def test_error_curve_shape_error():
    with pytest.raises(ValueError, match="errors must have shape"):
        ErrorCurveDisplay([0, 1, 2], [0.1, 0.2]).plot()


def test_trajectory_display_on_shared_axes(motions):
    X, y = motions
    _, axes = plt.subplots(1, 2, sharex=True, sharey=True)
    for ax in axes:
        TrajectoryDisplay(X, y).plot(ax=ax)
    assert axes[0].get_aspect() == 1.0


# --- the displays' numbers against hand-computed values --------------------


class _Threshold(ClusterMixin, BaseEstimator):
    """Label 1 where the first column exceeds ``threshold``: hand-checkable."""

    fitted_on = []  # missing fraction of every X this class was fitted on

    def __init__(self, threshold=0.0):
        self.threshold = threshold

    def fit(self, X, y=None):
        X = np.asarray(X, dtype=float)
        type(self).fitted_on.append(np.isnan(X).mean())
        self.labels_ = (np.nan_to_num(X[:, 0], nan=-np.inf) > self.threshold).astype(
            int
        )
        return self


def test_error_curve_from_estimator_parameter_hand_computed():
    X = np.array([[0.1], [0.2], [0.4], [0.5], [0.6], [0.9]])
    y = np.array([0, 0, 1, 1, 1, 1])
    display = ErrorCurveDisplay.from_estimator(
        _Threshold(), X, y, param_name="threshold", param_values=[-0.5, 0.3, 0.8]
    )
    # t=-0.5: one cluster, group 0 (2 points) lost; t=0.3: exact;
    # t=0.8: clusters {0.1..0.6} and {0.9}: 3 of 6 points matched.
    assert_allclose(display.errors, [[2 / 6], [0.0], [3 / 6]])
    assert_allclose(display.line_.get_ydata(), [2 / 6, 0.0, 3 / 6])
    assert_allclose(display.line_.get_xdata(), [-0.5, 0.3, 0.8])
    assert display.ax_.get_xlabel() == "threshold"


def test_error_curve_fits_on_the_requested_missing_fractions():
    X = np.random.RandomState(0).uniform(size=(200, 10))
    y = (X[:, 0] > 0.5).astype(int)
    _Threshold.fitted_on.clear()
    display = ErrorCurveDisplay.from_estimator(
        _Threshold(0.5),
        X,
        y,
        param_name="missing_fraction",
        param_values=[0.0, 0.2, 0.4],
        n_repeats=3,
        missing_pattern="random",
        random_state=0,
    )
    assert_allclose(_Threshold.fitted_on, np.repeat([0.0, 0.2, 0.4], 3), atol=0.02)
    assert_allclose(display.errors[0], 0.0)
    assert np.all(display.errors[1:] > 0)  # points with x_1 missing fall to 0
    band = display.fill_between_.get_paths()[0].vertices[:, 1]
    assert_allclose(band.min(), display.errors.min(axis=1).min())
    assert_allclose(band.max(), display.errors.max(axis=1).max())


def _offsets(collection):
    """A collection's offsets with masked (non-finite) points as NaN.

    matplotlib masks NaN offsets, and ``assert_allclose`` skips masked entries:
    compared raw, a point drawn at NaN would match any expected point.
    """
    return np.ma.filled(np.ma.asarray(collection.get_offsets(), dtype=float), np.nan)


def _two_groups_with_errors():
    rng = np.random.RandomState(0)
    X = rng.uniform(0, 100, size=(10, 8))
    X[4, 6:] = np.nan  # last frame of trajectory 4 missing
    y_true = np.array([0, 0, 0, 0, 0, 1, 1, 1, 1, 1])
    labels = np.array([7, 7, 7, 7, 3, 3, 3, 3, 3, 7])
    return X, y_true, labels


def test_trajectory_display_marks_exactly_the_misclassified_tracks():
    X, y_true, labels = _two_groups_with_errors()
    display = TrajectoryDisplay.from_predictions(X, labels, y_true=y_true)
    # 7 -> 0 (4 points), 3 -> 1 (4 points): trajectories 4 and 9 are wrong.
    expected = np.zeros(10, dtype=bool)
    expected[[4, 9]] = True
    np.testing.assert_array_equal(display.misclassified, expected)
    np.testing.assert_array_equal(display.labels, [0, 0, 0, 0, 1, 1, 1, 1, 1, 0])
    crosses = display.ax_.collections[-1]
    assert crosses.get_label() == "misclassified (2)"
    # crosses at the last observed point: frame 3 for track 4, frame 4 for 9
    assert_allclose(_offsets(crosses), [X[4, 4:6], X[9, 6:8]])


def test_trajectory_display_draws_each_group_s_tracks():
    X, y_true, _ = _two_groups_with_errors()
    display = TrajectoryDisplay(X, y_true).plot()
    tracks = X.reshape(10, 4, 2)
    for k, collection in enumerate(display.lines_):
        segments = collection.get_segments()
        members = tracks[y_true == k]
        assert len(segments) == len(members)
        for segment, track in zip(segments, members, strict=True):
            # a missing frame ends the drawn line
            assert_allclose(segment, track[~np.isnan(track).any(axis=1)])


def test_trajectory_display_y_true_of_the_wrong_length():
    X, y_true, labels = _two_groups_with_errors()
    with pytest.raises(ValueError, match="y_true has 9 entries for 10 trajectories"):
        TrajectoryDisplay.from_predictions(X, labels, y_true=y_true[:-1])
    with pytest.raises(ValueError, match="labels has 11 entries for 10 trajectories"):
        TrajectoryDisplay.from_predictions(X, np.r_[labels, 0], y_true=y_true)


def test_trajectory_display_noise_label():
    X, y_true, labels = _two_groups_with_errors()
    y_true = y_true.copy()
    y_true[[0, 5]] = -1  # two true outliers
    labels = labels.copy()
    labels[[0, 1]] = -1  # flags outlier 0 (right) and inlier 1 (wrong)
    display = TrajectoryDisplay.from_predictions(X, labels, y_true=y_true)
    # wrong: 1 (an inlier flagged), 4 and 9 (swapped), 5 (an outlier in a motion)
    np.testing.assert_array_equal(np.flatnonzero(display.misclassified), [1, 4, 5, 9])
    assert display.labels[0] == display.labels[1] == -1
    legend = [t.get_text() for t in display.ax_.get_legend().get_texts()]
    assert legend[0] == "outliers (-1)"
    grey = display.lines_[0].get_colors()[0]
    assert_allclose(grey[:3], mpl.colors.to_rgb("0.5"))


def test_similarity_display_order_and_blocks_hand_computed():
    S = np.array(
        [
            [1.0, 0.1, 0.9, 0.2],
            [0.1, 1.0, 0.3, 0.8],
            [0.9, 0.3, 1.0, 0.4],
            [0.2, 0.8, 0.4, 1.0],
        ]
    )
    display = SimilarityMatrixDisplay.from_predictions(S, [1, 0, 1, 0])
    np.testing.assert_array_equal(display.order_, [1, 3, 0, 2])
    assert_allclose(
        display.im_.get_array(),
        [
            [1.0, 0.8, 0.1, 0.3],
            [0.8, 1.0, 0.2, 0.4],
            [0.1, 0.2, 1.0, 0.9],
            [0.3, 0.4, 0.9, 1.0],
        ],
    )
    lines = display.ax_.get_lines()
    assert [line.get_ydata()[0] for line in lines[0::2]] == [1.5]
    assert [line.get_xdata()[0] for line in lines[1::2]] == [1.5]
    with pytest.raises(ValueError, match="labels has 3 entries"):
        SimilarityMatrixDisplay.from_predictions(S, [0, 1, 0])


# --- what mutation testing found untested (benchmarks/results/mutation.md) --


@pytest.mark.parametrize("n_labels", [1, 9, 10, 11, 19, 20, 21, 33])
def test_label_colors_are_distinct_and_from_the_documented_maps(n_labels):
    from sklearn_gpca.plotting._base import label_colors

    colors = label_colors(n_labels)
    assert len(colors) == n_labels
    rgb = {tuple(np.round(mpl.colors.to_rgb(c), 6)) for c in colors}
    assert len(rgb) == n_labels
    if n_labels <= 10:
        assert_allclose(colors, mpl.colormaps["tab10"].colors[:n_labels])
    elif n_labels <= 20:
        assert_allclose(colors, mpl.colormaps["tab20"].colors[:n_labels])
    else:  # evenly spaced over the whole of turbo, both ends included
        assert_allclose(colors, mpl.colormaps["turbo"](np.linspace(0, 1, n_labels)))


def test_match_labels_ignores_pairs_with_noise_on_one_side():
    from sklearn_gpca.plotting._base import match_labels

    # true 0 is predicted 5, 5, 6; true 1 is predicted 6, 6, 5: 5 -> 0, 6 -> 1
    # (4 points). Five true outliers predicted 5 must not pull 5 to motion 1,
    # and an inlier flagged -1 must not count for any pair.
    y_true = np.array([0, 0, 0, 1, 1, 1, -1, -1, -1, -1, -1, 1])
    y_pred = np.array([5, 5, 6, 6, 6, 5, 5, 5, 5, 5, 5, -1])
    pred, true = match_labels(y_true, y_pred)
    np.testing.assert_array_equal(true, y_true)
    np.testing.assert_array_equal(pred, [0, 0, 1, 1, 1, 0, 0, 0, 0, 0, 0, -1])


def test_match_labels_gives_unmatched_clusters_the_codes_after():
    from sklearn_gpca.plotting._base import match_labels

    y_true = np.array([0, 0, 0, 1, 1, 1])
    y_pred = np.array([3, 3, 8, 1, 1, 9])  # 3 -> 0, 1 -> 1; 8 and 9 unmatched
    pred, true = match_labels(y_true, y_pred)
    np.testing.assert_array_equal(true, y_true)
    np.testing.assert_array_equal(pred, [0, 0, 2, 1, 1, 3])


class _FitPredictOnly(ClusterMixin, BaseEstimator):
    """A clusterer without ``predict`` (as DBSCAN): labels by the sign of x_1."""

    def fit(self, X, y=None):
        self.labels_ = (np.asarray(X)[:, 0] > 0).astype(int)
        return self


class _FitThenPredict(BaseEstimator):
    """No ``fit_predict``: ``fit`` then ``predict``, labels by the sign of x_1."""

    def fit(self, X, y=None):
        self.fitted_rows_ = len(X)
        return self

    def predict(self, X):
        return (np.asarray(X)[:, 0] > 0).astype(int)


@pytest.mark.parametrize("estimator_class", [_FitPredictOnly, _FitThenPredict])
def test_trajectory_display_unfitted_estimator_routes(estimator_class):
    X = np.array([[-1.0, 0, 0, 1], [2, 0, 1, 1], [-3, 1, 1, 0], [4, 1, 0, 0]])
    display = TrajectoryDisplay.from_estimator(estimator_class(), X)
    np.testing.assert_array_equal(display.labels, [0, 1, 0, 1])


def test_similarity_display_of_a_three_step_pipeline(motions):
    from sklearn.preprocessing import FunctionTransformer

    X, _ = motions
    pipe = make_pipeline(
        FunctionTransformer(),
        PowerFactorization(random_state=0),
        GPCAClustering(2, random_state=0),
    ).fit(X)
    display = SimilarityMatrixDisplay.from_estimator(pipe)
    normals = pipe[-1].point_normals_
    assert_allclose(display.similarity, (normals @ normals.T) ** 2, atol=1e-12)


def test_similarity_display_sparse_affinity_is_made_dense():
    from sklearn.cluster import SpectralClustering

    X = make_motions(2, n_points=[20, 20], n_frames=6, random_state=0)[0]
    model = SpectralClustering(
        2, affinity="nearest_neighbors", n_neighbors=5, random_state=0
    ).fit(X)
    display = SimilarityMatrixDisplay.from_estimator(model, colorbar=False)
    assert isinstance(display.similarity, np.ndarray)
    assert_allclose(display.similarity, model.affinity_matrix_.toarray())


@pytest.mark.parametrize(
    "call, caller",
    [
        (lambda: TrajectoryDisplay(np.zeros((2, 6)), [0, 1]).plot(), "plot"),
        (
            lambda: TrajectoryDisplay.from_predictions(np.zeros((2, 6)), [0, 1]),
            "from_predictions",
        ),
        (
            lambda: TrajectoryDisplay.from_estimator(
                _FitPredictOnly(), np.ones((2, 6))
            ),
            "from_estimator",
        ),
    ],
)
def test_trajectory_display_without_matplotlib_names_the_caller(
    monkeypatch, call, caller
):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    with pytest.raises(ImportError, match=rf"^TrajectoryDisplay\.{caller} requires"):
        call()


@pytest.mark.parametrize(
    "call, caller",
    [
        (lambda: SimilarityMatrixDisplay(np.eye(2)).plot(), "plot"),
        (
            lambda: SimilarityMatrixDisplay.from_predictions(np.eye(2)),
            "from_predictions",
        ),
        (
            lambda: SimilarityMatrixDisplay.from_estimator(_FitPredictOnly()),
            "from_estimator",
        ),
        (lambda: ErrorCurveDisplay([0, 1], [0, 1]).plot(), "plot"),
        (
            lambda: ErrorCurveDisplay.from_predictions([0, 1], [0, 1]),
            "from_predictions",
        ),
        (
            lambda: ErrorCurveDisplay.from_estimator(
                _Threshold(),
                np.ones((2, 2)),
                [0, 1],
                param_name="threshold",
                param_values=[0],
            ),
            "from_estimator",
        ),
    ],
)
def test_matrix_and_curve_without_matplotlib_name_the_caller(monkeypatch, call, caller):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    with pytest.raises(ImportError, match=rf"Display\.{caller} requires matplotlib"):
        call()


def test_similarity_display_without_labels_keeps_the_order():
    S = np.array([[1.0, 0.2, 0.3], [0.2, 1.0, 0.4], [0.3, 0.4, 1.0]])
    display = SimilarityMatrixDisplay(S).plot()
    np.testing.assert_array_equal(display.order_, [0, 1, 2])
    assert_allclose(display.im_.get_array(), S)
    assert display.ax_.get_lines() == []  # no label blocks, no lines


def test_similarity_display_orders_stably_with_a_line_between_every_block():
    rng = np.random.RandomState(0)
    labels = rng.randint(3, size=300)
    S = rng.uniform(size=(300, 300))
    display = SimilarityMatrixDisplay(S + S.T, labels).plot()
    expected = np.concatenate([np.flatnonzero(labels == k) for k in range(3)])
    np.testing.assert_array_equal(display.order_, expected)
    sizes = np.bincount(labels)
    lines = display.ax_.get_lines()
    positions = [sizes[0] - 0.5, sizes[0] + sizes[1] - 0.5]
    assert [line.get_ydata()[0] for line in lines[0::2]] == positions
    assert [line.get_xdata()[0] for line in lines[1::2]] == positions


def test_similarity_display_passes_axes_and_image_options():
    S = np.array([[1.0, 0.5], [0.5, 1.0]])
    _, ax = plt.subplots()
    display = SimilarityMatrixDisplay.from_predictions(
        S, [0, 1], ax=ax, cmap="gray", vmin=0.0, vmax=2.0
    )
    assert display.ax_ is ax and display.figure_ is ax.figure
    assert display.im_.get_cmap().name == "gray"
    assert display.im_.get_clim() == (0.0, 2.0)


def test_similarity_display_from_estimator_on_given_axes(motions):
    X, _ = motions
    _, ax = plt.subplots()
    display = SimilarityMatrixDisplay.from_estimator(gpca_pipeline(), X, ax=ax)
    assert display.ax_ is ax


def test_similarity_display_max_samples_is_inclusive_and_named(motions):
    X, _ = motions
    pipe = gpca_pipeline().fit(X)
    assert SimilarityMatrixDisplay.from_estimator(
        pipe, max_samples=80
    ).similarity.shape == (80, 80)
    with pytest.raises(
        ValueError,
        match=r"^n_samples=80 exceeds max_samples=79: the dense similarity would "
        r"have 6400 entries\.$",
    ):
        SimilarityMatrixDisplay.from_estimator(pipe, max_samples=79)


def test_similarity_display_messages_name_the_problem(motions):
    X, _ = motions
    with pytest.raises(
        ValueError, match=r"^X is required to fit an unfitted estimator\.$"
    ):
        SimilarityMatrixDisplay.from_estimator(gpca_pipeline())
    with pytest.raises(
        ValueError,
        match=r"^KMeans exposes neither point_normals_ nor affinity_matrix_; use "
        r"from_predictions with a similarity matrix\.$",
    ):
        SimilarityMatrixDisplay.from_estimator(
            KMeans(2, n_init=1, random_state=0), np.nan_to_num(X)
        )


def test_error_curve_names_and_labels():
    # defaults of the constructor, its name, and plot's name overriding it
    display = ErrorCurveDisplay([0.0, 1.0], [0.1, 0.2], name="A").plot()
    assert display.ax_.get_ylabel() == "misclassification rate"
    assert display.line_.get_label() == "A"
    assert display.figure_ is display.ax_.figure
    legend = [t.get_text() for t in display.ax_.get_legend().get_texts()]
    assert legend == ["A"]
    assert display.plot(name="B").line_.get_label() == "B"
    display = ErrorCurveDisplay.from_predictions(
        [0.0, 1.0], [0.1, 0.2], error_name="mean error", name="C"
    )
    assert display.ax_.get_ylabel() == "mean error"
    assert [t.get_text() for t in display.ax_.get_legend().get_texts()] == ["C"]


def test_error_curve_passes_line_options_and_axes():
    _, ax = plt.subplots()
    display = ErrorCurveDisplay.from_predictions(
        [0.0, 1.0], [[0.1, 0.3], [0.2, 0.6]], ax=ax, band=False, color="red"
    )
    assert display.ax_ is ax
    assert display.fill_between_ is None
    assert mpl.colors.to_rgb(display.line_.get_color()) == (1.0, 0.0, 0.0)


def test_error_curve_band_spans_each_value_s_range_in_the_line_s_colour():
    errors = np.array([[0.1, 0.3, 0.2], [0.4, 0.5, 0.45], [0.2, 0.1, 0.15]])
    display = ErrorCurveDisplay([0.0, 1.0, 2.0], errors).plot(color="green")
    vertices = display.fill_between_.get_paths()[0].vertices
    for x, low, high in zip(
        [0.0, 1.0, 2.0], [0.1, 0.4, 0.1], [0.3, 0.5, 0.2], strict=True
    ):
        at_x = vertices[np.isclose(vertices[:, 0], x), 1]
        assert_allclose([at_x.min(), at_x.max()], [low, high])
    assert set(np.round(vertices[:, 0], 12)) == {0.0, 1.0, 2.0}
    face = display.fill_between_.get_facecolor()[0][:3]
    assert_allclose(face, mpl.colors.to_rgb("green"))


def test_error_curve_shape_error_gives_the_shape():
    with pytest.raises(ValueError, match=r"got \(2,\)\.$"):
        ErrorCurveDisplay([0, 1, 2], [0.1, 0.2]).plot()


class _Recorder(ClusterMixin, BaseEstimator):
    """All in one cluster; keeps the missing-data mask of every fit."""

    masks = []

    def fit(self, X, y=None):
        type(self).masks.append(np.isnan(np.asarray(X, dtype=float)))
        self.labels_ = np.zeros(len(X), dtype=int)
        return self


@pytest.mark.parametrize("pattern", [None, "occlusion", "random"])
def test_error_curve_removes_entries_with_the_requested_pattern(pattern):
    X = np.random.RandomState(0).uniform(size=(30, 12))
    y = np.repeat([0, 1], 15)
    _Recorder.masks.clear()
    options = {} if pattern is None else {"missing_pattern": pattern}
    ErrorCurveDisplay.from_estimator(
        _Recorder(),
        X,
        y,
        param_name="missing_fraction",
        param_values=[0.2, 0.4],
        n_repeats=2,
        random_state=1,
        **options,
    )
    rng = np.random.RandomState(1)
    expected = [
        np.isnan(make_missing(X, v, pattern=pattern or "occlusion", random_state=rng))
        for v in (0.2, 0.2, 0.4, 0.4)
    ]
    assert len(_Recorder.masks) == 4
    for mask, truth in zip(_Recorder.masks, expected, strict=True):
        np.testing.assert_array_equal(mask, truth)


def test_error_curve_from_estimator_uses_the_scoring_and_passes_options():
    X = np.array([[0.1], [0.2], [0.4], [0.5], [0.6], [0.9]])
    y = np.array([0, 0, 1, 1, 1, 1])
    _, ax = plt.subplots()

    def n_in_cluster_1(y_true, y_pred):
        return float(np.sum(y_pred == 1))

    display = ErrorCurveDisplay.from_estimator(
        _Threshold(),
        X,
        y,
        param_name="threshold",
        param_values=[0.3, 0.8],
        scoring=n_in_cluster_1,
        name="count",
        ax=ax,
        color="red",
    )
    assert_allclose(display.errors, [[4.0], [1.0]])
    assert display.ax_ is ax
    assert display.line_.get_label() == "count"
    assert mpl.colors.to_rgb(display.line_.get_color()) == (1.0, 0.0, 0.0)


def test_trajectory_display_colours_dots_and_crosses():
    X, y_true, labels = _two_groups_with_errors()
    X = X.copy()
    X[2] = np.nan  # a track never observed: no dot, no crash
    y_true = y_true.copy()
    y_true[7] = 2  # a third motion, predicted as motion 1: three errors
    display = TrajectoryDisplay.from_predictions(
        X, labels, y_true=y_true, title="T", legend=True
    )
    ax = display.ax_
    assert ax.get_title() == "T"
    tab10 = mpl.colormaps["tab10"].colors
    tracks = X.reshape(10, 4, 2)
    # one dot per track at its last observed point, in its motion's colour
    dots = [c for c in ax.collections if c not in display.lines_][:2]
    for k, (line, dot) in enumerate(zip(display.lines_, dots, strict=True)):
        assert_allclose(line.get_colors()[0][:3], tab10[k])
        assert_allclose(dot.get_facecolor()[0][:3], tab10[k])
        members = np.flatnonzero(display.labels == k)
        expected = [
            t[~np.isnan(t).any(axis=1)][-1] if (~np.isnan(t)).any() else [np.nan] * 2
            for t in tracks[members]
        ]
        assert_allclose(_offsets(dot), expected)
    crosses = ax.collections[-1]
    wrong = np.flatnonzero(display.misclassified)
    np.testing.assert_array_equal(wrong, [4, 7, 9])
    assert crosses.get_label() == "misclassified (3)"
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert legend == ["motion 0", "motion 1", "misclassified (3)"]


def test_trajectory_display_frames_and_displacement_arrows():
    X, y_true, _ = _two_groups_with_errors()
    tracks = X.reshape(10, 4, 2)
    display = TrajectoryDisplay(X, y_true).plot(frames=(1, 2))
    for k, collection in enumerate(display.lines_):
        members = tracks[y_true == k][:, 1:3]
        for segment, track in zip(collection.get_segments(), members, strict=True):
            assert_allclose(segment, track[~np.isnan(track).any(axis=1)])
    plt.close("all")
    display = TrajectoryDisplay(X, y_true).plot(kind="displacement", frames=(0, 2))
    tab10 = mpl.colormaps["tab10"].colors
    for k, arrows in enumerate(display.lines_):
        members = tracks[y_true == k]
        assert_allclose(_offsets(arrows), members[:, 0])
        assert_allclose(arrows.U, members[:, 2, 0] - members[:, 0, 0])
        assert_allclose(arrows.V, members[:, 2, 1] - members[:, 0, 1])
        # the arrow ends on the last frame: data units, scale 1
        assert (arrows.angles, arrows.scale_units, arrows.scale) == ("xy", "xy", 1)
        assert_allclose(arrows.get_facecolor()[0][:3], tab10[k])


def test_trajectory_display_from_predictions_passes_axes_and_options():
    X, _, labels = _two_groups_with_errors()
    _, ax = plt.subplots()
    display = TrajectoryDisplay.from_predictions(X, labels, ax=ax, title="given")
    assert display.ax_ is ax and ax.get_title() == "given"
    assert display.misclassified is None
    _, ax = plt.subplots()
    display = TrajectoryDisplay.from_estimator(
        _FitPredictOnly(), X, ax=ax, legend=False
    )
    assert display.ax_ is ax and ax.get_legend() is None


def test_trajectory_display_label_count_message():
    X, y_true, _ = _two_groups_with_errors()
    with pytest.raises(
        ValueError, match=r"^labels has 9 entries for 10 trajectories\.$"
    ):
        TrajectoryDisplay(X, y_true[:-1]).plot()


def test_trajectory_display_equal_aspect_on_own_and_shared_axes(motions):
    X, y = motions
    display = TrajectoryDisplay(X, y).plot()
    # equal scales; alone, the data limits adapt and the axes keep their box
    assert display.ax_.get_aspect() == 1.0
    assert display.ax_.get_adjustable() == "datalim"
    fig, axes = plt.subplots(1, 2, sharex=True, sharey=True)
    for ax in axes:
        TrajectoryDisplay(X, y).plot(ax=ax)
    # shared limits cannot adapt: the box does (matplotlib refuses datalim)
    assert [ax.get_adjustable() for ax in axes] == ["box", "box"]
    fig.canvas.draw()


def test_trajectory_display_reads_masked_entries_as_missing():
    X, y_true, _ = _two_groups_with_errors()
    masked = np.ma.masked_invalid(X)
    masked.data[masked.mask] = 1e6  # what lies under the mask must not be drawn
    drawn = TrajectoryDisplay(masked, y_true).plot()
    expected = TrajectoryDisplay(X, y_true).plot()
    for got, want in zip(drawn.lines_, expected.lines_, strict=True):
        for a, b in zip(got.get_segments(), want.get_segments(), strict=True):
            assert_allclose(a, b)
