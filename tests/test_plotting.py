"""Tests of the displays in ``sklearn_gpca.plotting`` (Agg backend)."""

# SPDX-License-Identifier: BSD-3-Clause

import subprocess
import sys

import numpy as np
import pytest
from numpy.testing import assert_allclose
from sklearn.cluster import KMeans
from sklearn.pipeline import make_pipeline

from sklearn_gpca import (
    GPCAClustering,
    PowerFactorization,
    ShapeInteractionClustering,
    shape_interaction_matrix,
)
from sklearn_gpca.datasets import make_motions

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
    display = ErrorCurveDisplay.from_estimator(
        gpca_pipeline(),
        X,
        y,
        param_name="missing_fraction",
        param_values=[0.0, 0.3],
        n_repeats=2,
        random_state=0,
    )
    assert display.errors.shape == (2, 2)
    assert np.all((display.errors >= 0) & (display.errors <= 0.5))
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
