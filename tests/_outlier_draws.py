"""The lab draw with outlier tracks shared by the outlier tests."""

from sklearn_gpca.datasets import make_tracks


def affine_lab_draw(seed=0, **kwargs):
    """150 complete lab tracks of 12 frames (affine camera), 10 % outliers.

    Returns ``make_tracks``' ``(X, y, info)``; ``kwargs`` override the keywords.
    """
    params = dict(
        scene="lab",
        camera="affine",
        n_tracks=150,
        n_frames=12,
        missing=0,
        outlier_fraction=0.1,
    )
    params.update(kwargs)
    return make_tracks(**params, random_state=seed, return_info=True)
