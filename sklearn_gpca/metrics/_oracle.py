"""Reference segmentations from the ground truth: how separable are the motions?"""

# SPDX-License-Identifier: BSD-3-Clause

from numbers import Integral

import numpy as np
from sklearn.utils._param_validation import Interval, validate_params

from sklearn_gpca._magnitude import in_safe_range
from sklearn_gpca._missing import masked_to_nan
from sklearn_gpca._observed_subspaces import (
    fit_observed_subspace,
    observed_entries,
    subspace_residuals,
)
from sklearn_gpca._projective_motion import (
    fit_projective_motion,
    projective_residuals,
)


def _check_oracle_input(X, y_true):
    X = np.asarray(masked_to_nan(X), dtype=np.float64)
    y_true = np.asarray(y_true)
    if X.ndim != 2:
        raise ValueError(f"X must be 2-D, got an array of shape {X.shape}.")
    if y_true.ndim != 1 or y_true.shape[0] != X.shape[0]:
        raise ValueError(
            f"y_true must be 1-D with one label per row of X ({X.shape[0]}), got "
            f"shape {y_true.shape}."
        )
    if np.isinf(X).any():
        raise ValueError("X contains infinite values; use NaN for missing entries.")
    return X, y_true


@validate_params(
    {
        "X": ["array-like"],
        "y_true": ["array-like"],
        "subspace_dim": [Interval(Integral, 1, None, closed="left")],
        "perspective_background": ["boolean"],
    },
    prefer_skip_nested_validation=True,
)
def oracle_labels(X, y_true, subspace_dim=4, *, perspective_background=False):
    """Each track to the nearest true motion subspace, on its observed entries.

    One linear subspace of dimension ``subspace_dim`` of ``R^{2F}`` is fitted
    to the observed entries of each true group (the least-squares optimum:
    alternating least squares, then variable projection, see Notes), and
    every track is assigned to the subspace with the smallest
    mean squared residual per residual degree of freedom on the track's own
    observed entries. Its misclassification rate measures how separable the
    motions are under the subspace model when the groups are known: a
    reference for any method that has to find them (issue 17's oracle, 3.8 %
    on real tracker output).

    Parameters
    ----------
    X : array-like or masked array of shape (n_samples, n_features)
        Trajectories, NaN (or masked) where missing.
    y_true : array-like of shape (n_samples,)
        True groups; ``-1`` marks outliers, which fit no subspace and keep
        ``-1`` (the oracle knows them).
    subspace_dim : int, default=4
        Dimension of every motion subspace (4 for a rigid motion seen by an
        affine camera).
    perspective_background : bool, default=False
        Model the largest true group (the background of tracker output) by a
        perspective camera per frame instead of a subspace
        (``sklearn_gpca._projective_motion``, as
        ``segment_motions(perspective_background=True)`` does), its residual
        counted with ``2 m - 4`` degrees of freedom for a track seen in ``m``
        frames: the oracle of a model that holds a deep static scene.

    Returns
    -------
    labels : ndarray of shape (n_samples,)
        The nearest group's label (values of ``y_true``). A track fitted on
        ``k <= subspace_dim`` coordinates of every subspace carries no
        evidence and gets the largest group's label.

    Notes
    -----
    A track observed on the coordinates ``O`` has residual ``r_k = min_z
    ||x_O - (B_k)_O z||^2`` to subspace ``k`` with basis ``B_k`` and ``|O| -
    d`` residual degrees of freedom; it goes to ``argmin_k r_k / (|O| - d)``.
    Coordinates observed by fewer than ``d`` tracks of a group are left out
    of that group's subspace. The subspaces are fitted to convergence
    (``fit_observed_subspace(..., polish=True)``): with many entries
    missing, 30 alternations alone can leave a true motion's residual several
    times its least value and the oracle needlessly weak (driving draws of
    ``make_tracks``, seeds 0-3: 7.7 % with 30 alternations, 4.3 % at the
    optimum; ``benchmarks/results/subspace_convergence.md``).

    Examples
    --------
    >>> from sklearn_gpca.datasets import make_motions
    >>> from sklearn_gpca.metrics import misclassification_rate, oracle_labels
    >>> X, y = make_motions(3, n_points=150, n_frames=10, missing=0.2,
    ...                     random_state=0)
    >>> round(misclassification_rate(y, oracle_labels(X, y)), 3)
    0.013
    """
    X, y_true = _check_oracle_input(X, y_true)
    X, _ = in_safe_range(X)
    X0, mask = observed_entries(X)
    groups, counts = np.unique(y_true[y_true != -1], return_counts=True)
    labels = np.full(y_true.shape, -1, dtype=y_true.dtype)
    if groups.size == 0:
        return labels
    inliers = y_true != -1
    residuals = np.empty((int(inliers.sum()), groups.size))
    dofs = np.empty((int(inliers.sum()), groups.size), dtype=np.intp)
    background = int(np.argmax(counts))
    for k, g in enumerate(groups):
        members = y_true == g
        if perspective_background and k == background:
            cameras, supported = fit_projective_motion(X0[members], mask[members])
            residuals[:, k], dofs[:, k] = projective_residuals(
                X0[inliers], mask[inliers], cameras, supported
            )
            continue
        basis, support = fit_observed_subspace(
            X0[members], mask[members], subspace_dim, polish=True
        )
        r, d = subspace_residuals(X0[inliers], mask[inliers], [basis], [support])
        residuals[:, k], dofs[:, k] = r[:, 0], d[:, 0]
    per_dof = np.where(dofs > 0, residuals / np.maximum(dofs, 1), np.inf)
    nearest = groups[np.argmin(per_dof, axis=1)]
    nearest[~np.isfinite(per_dof).any(axis=1)] = groups[np.argmax(counts)]
    labels[inliers] = nearest
    return labels
