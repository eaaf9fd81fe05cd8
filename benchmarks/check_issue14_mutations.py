"""Issue 14's table: each change that once passed the tests now fails one.

Applies each change to the library in turn, runs the test files that cover
it, prints which tests fail, and restores the file (also on error).

    OMP_NUM_THREADS=1 python benchmarks/check_issue14_mutations.py
"""

# SPDX-License-Identifier: BSD-3-Clause

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: (name, file, original text, broken text, tests to run)
CHANGES = [
    (
        "the CLI writes all-zero labels to --output",
        "sklearn_gpca/_cli.py",
        'lambda tmp: np.savetxt(tmp, labels, fmt="%d")',
        'lambda tmp: np.savetxt(tmp, np.zeros_like(labels), fmt="%d")',
        "tests/test_cli.py",
    ),
    (
        "the CLI's fit returns all-zero labels",
        "sklearn_gpca/_cli.py",
        "return pipeline, pipeline.fit_predict(X)",
        "return pipeline, 0 * pipeline.fit_predict(X)",
        "tests/test_cli.py",
    ),
    (
        "ErrorCurveDisplay.from_estimator scores constant labels, never fits",
        "sklearn_gpca/plotting/_error_curve.py",
        "errors[i, r] = scoring(y, model.fit_predict(data))",
        "errors[i, r] = scoring(y, np.zeros(len(y), dtype=int))",
        "tests/test_plotting.py sklearn_gpca/plotting",
    ),
    (
        "estimate_motions returns residual=0.0 and the wrong points_3d",
        "sklearn_gpca/_motion.py",
        "points_3d=structure[:, :3] / structure[:, 3:],\n"
        "        residual=pf.reconstruction_err_,",
        "points_3d=structure[:, :3],\n        residual=0.0,",
        "tests/test_motion.py sklearn_gpca/_motion.py",
    ),
    (
        "TrajectoryDisplay marks no point as misclassified",
        "sklearn_gpca/plotting/_trajectories.py",
        "misclassified = labels != true",
        "misclassified = np.zeros(len(labels), dtype=bool)",
        "tests/test_plotting.py sklearn_gpca/plotting",
    ),
    (
        "PowerFactorization's completion rank ignores completion_rank",
        "sklearn_gpca/_factorization.py",
        '"""Completion rank and the held-out errors that chose it."""\n',
        '"""Completion rank and the held-out errors that chose it."""\n'
        "    return n_components, {}\n",
        "tests/test_completion_rank.py tests/test_power_factorization.py "
        "tests/test_varpro.py sklearn_gpca/_power_factorization.py",
    ),
    (
        "paper_pipeline returns the library defaults",
        "sklearn_gpca/_pipeline.py",
        "    return make_pipeline(\n",
        "    return make_pipeline(\n"
        "        PowerFactorization(random_state=random_state),\n"
        "        GPCAClustering(n_clusters, random_state=random_state),\n"
        "    )\n"
        "    return make_pipeline(\n",
        "tests/test_pipeline.py tests/test_composition.py sklearn_gpca/_pipeline.py",
    ),
]


def main():
    for name, file, original, broken, tests in CHANGES:
        path = ROOT / file
        text = path.read_text()
        if text.count(original) != 1:
            print(f"{name}: the original text is not in {file} once; update it")
            continue
        path.write_text(text.replace(original, broken))
        try:
            result = subprocess.run(
                [
                    sys.executable,
                    "-m",
                    "pytest",
                    "-q",
                    "-p",
                    "no:cacheprovider",
                    *tests.split(),
                ],
                cwd=ROOT,
                capture_output=True,
                text=True,
            )
        finally:
            path.write_text(text)
        lines = result.stdout.strip().splitlines()
        failed = [line.split(" - ")[0] for line in lines if line.startswith("FAILED")]
        print(f"{name}: {lines[-1] if lines else 'no output'}")
        for test in failed:
            print(f"    {test}")


if __name__ == "__main__":
    main()
