"""scikit-learn's own estimator checks."""

from sklearn.utils.estimator_checks import parametrize_with_checks

from sklearn_gpca import PowerFactorization


# Common-check data have 2-3 features: test rank 1, as sklearn does for
# TruncatedSVD.
@parametrize_with_checks([PowerFactorization(n_components=1)])
def test_sklearn_compatible_estimator(estimator, check):
    check(estimator)
