"""The inputs of issue 13 (reliability), run on this checkout: what each gives now.

``python benchmarks/check_issue13_inputs.py [--slow]`` prints, per input, the
result or the error, the warnings and the seconds. ``--slow`` adds the
5,100 x 100 ``GPCAClustering`` fit (minutes on 2 cores). The regression tests
that pin each behaviour are named in the issue's closing note; this script is
the "after" column of its table. The command-line and loader items are covered
by ``tests/test_cli.py``, ``tests/test_hopkins155.py`` and ``tests/test_lowrank.py``.
"""

import sys
import time
import warnings

import numpy as np
from sklearn.pipeline import make_pipeline

from sklearn_gpca import GPCAClustering, PowerFactorization, estimate_motions
from sklearn_gpca.datasets import make_missing, make_motions
from sklearn_gpca.metrics import misclassification_rate


def run(name, f):
    """Print what ``f()`` returns or raises, its warnings and its time."""
    start = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            out = f()
        except Exception as error:  # the point is to show it
            out = f"{type(error).__name__}: {str(error)[:150]}"
    print(f"## {name}\n  -> {out}  ({time.perf_counter() - start:.2f} s)")
    for message in sorted({f"{type(w.message).__name__}: {w.message}" for w in caught}):
        print("     warning", message[:120])


def pipeline():
    return make_pipeline(
        PowerFactorization(random_state=0), GPCAClustering(3, random_state=0)
    )


def error(y, labels):
    return f"{100 * misclassification_rate(y, labels):.1f} %"


def main():
    X, y = make_motions(3, n_points=[60] * 3, n_frames=8, random_state=0)
    X_missing = make_missing(X, 0.2, random_state=0)
    for scale in (1e-300, 1e-200, 1e-155, 1.0, 1e154, 1e200, 1e300):
        run(
            f"1. pipeline, 20 % missing, X * {scale:g}",
            lambda s=scale: error(y, pipeline().fit_predict(X_missing * s)),
        )
    Z = PowerFactorization(random_state=0).fit_transform(X)
    run(
        "1. GPCAClustering(normalize=False) at 1e-300",
        lambda: error(
            y,
            GPCAClustering(3, normalize=False, random_state=0).fit_predict(Z * 1e-300),
        ),
    )

    rs = np.random.RandomState(0)
    planes = np.vstack(
        [
            rs.standard_normal((60, 4)) @ np.linalg.qr(rs.standard_normal((5, 4)))[0].T
            for _ in range(3)
        ]
    )
    y_planes = np.repeat([0, 1, 2], 60)

    def three_hyperplanes():
        labels = GPCAClustering(3, random_state=0).fit_predict(planes)
        sizes = np.bincount(labels, minlength=3).tolist()
        return f"sizes {sizes}, error {error(y_planes, labels)}"

    run("2. three exact hyperplanes, GPCAClustering(3)", three_hyperplanes)
    run(
        "2. 12 points, n_clusters=10",
        lambda: GPCAClustering(10, random_state=0).fit(rs.standard_normal((12, 5))),
    )

    X3, y3 = make_motions(3, n_points=[40] * 3, n_frames=10, random_state=0)
    Z3 = PowerFactorization(random_state=0).fit_transform(X3)
    for copies in (1, 11, 20):
        run(
            f"3. every point x{copies}",
            lambda c=copies: error(
                np.repeat(y3, c),
                GPCAClustering(3, random_state=0).fit_predict(np.repeat(Z3, c, axis=0)),
            ),
        )

    X4, y4 = make_motions(3, n_points=[100] * 3, n_frames=10, random_state=1)

    def predict_and_labels():
        fitted = pipeline().fit(X4)
        labels, predicted = fitted[-1].labels_, fitted.predict(X4)
        return (
            f"labels_ {error(y4, labels)}, predict {error(y4, predicted)}, "
            f"agreement {100 * np.mean(predicted == labels):.1f} %"
        )

    run("4. predict(X) against labels_", predict_and_labels)

    full = np.random.RandomState(1).standard_normal((60, 5)) @ np.random.RandomState(
        2
    ).standard_normal((5, 20))
    split = np.full((60, 20), np.nan)
    split[:30, :10], split[30:, 10:] = full[:30, :10], full[30:, 10:]

    def completion(seed):
        model = PowerFactorization(random_state=seed).fit(split)
        return model.inverse_transform(model.transform(split))

    run(
        "5. mask falling apart, completions of two seeds",
        lambda: f"max difference {np.abs(completion(0) - completion(1)).max():.3g}",
    )

    if "--slow" in sys.argv:
        noise = np.random.RandomState(0).standard_normal((5100, 100))
        run(
            "10. GPCAClustering(2) on 5100 x 100",
            lambda: np.bincount(GPCAClustering(2, random_state=0).fit_predict(noise)),
        )
    run(
        "10. GPCAClustering(4) on 300000 x 50",
        lambda: GPCAClustering(4, random_state=0).fit(np.ones((300000, 50))),
    )

    run(
        "12. estimate_motions, string labels",
        lambda: estimate_motions(X, np.array(["a", "b", "c"])[y]),
    )
    run("12. estimate_motions, 2-D labels", lambda: estimate_motions(X, y[:, None]))
    run("12. n_components=True", lambda: PowerFactorization(n_components=True).fit(X))
    run("12. n_clusters=True", lambda: GPCAClustering(n_clusters=True).fit(Z))
    run(
        "12. completion_rank=100 > 2F = 16",
        lambda: PowerFactorization(completion_rank=100).fit(X_missing),
    )


if __name__ == "__main__":
    main()
