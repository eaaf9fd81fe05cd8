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
    assert_allclose(crosses.get_offsets(), [X[4, 4:6], X[9, 6:8]])


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
