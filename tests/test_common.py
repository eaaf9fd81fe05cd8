"""scikit-learn's own estimator checks, for every estimator the package exports."""

from sklearn.utils.estimator_checks import parametrize_with_checks

from sklearn_gpca import (
    GPCAClustering,
    NClustersSearch,
    PowerFactorization,
    ShapeInteractionClustering,
)

_BLOBS = (
    "check_clustering fits three Gaussian blobs, which are not a union of "
    "linear subspaces: the number of clusters the coding length chooses for "
    "them is not three"
)


def _expected_failures(estimator):
    if isinstance(estimator, NClustersSearch):
        return {
            "check_clustering": _BLOBS,
            "check_clustering(readonly_memmap=True)": _BLOBS,
        }
    return {}


# Common-check data have 2-3 features: test rank 1, as sklearn does for
# TruncatedSVD.
@parametrize_with_checks(
    [
        PowerFactorization(n_components=1),
        GPCAClustering(),
        ShapeInteractionClustering(),
        NClustersSearch(GPCAClustering(), n_clusters_grid=[1, 2, 3]),
    ],
    expected_failed_checks=_expected_failures,
)
def test_sklearn_compatible_estimator(estimator, check):
    check(estimator)
