"""madsfm: relative pose from matched keypoints and monocular depth priors (affine-corrected), in Python.

The C++ estimator of the madsfm project (hybrid affine-depth LO-MSAC): see docs/python.md.

    import madsfm
    result = madsfm.estimate_relative_pose(kpts0, kpts1, depth0, depth1, K0, K1, image_size0=(w, h), ...)
    result.R, result.t, result.scale, result.shift0, result.shift1, result.inliers_sampson
"""

from ._madsfm import (  # noqa: F401
    METHODS,
    HybridEstimatorOptions,
    RelativePoseResult,
    ScoringMode,
    SolverChoice,
    __version__,
    rotation_error_deg,
    translation_error_deg,
)
from ._api import (  # noqa: F401
    estimate_relative_pose,
    estimate_shared_focal_relative_pose,
    estimate_two_focal_relative_pose,
    read_depth,
    sample_depth,
)

__all__ = [
    "HybridEstimatorOptions",
    "METHODS",
    "RelativePoseResult",
    "ScoringMode",
    "SolverChoice",
    "estimate_relative_pose",
    "estimate_shared_focal_relative_pose",
    "estimate_two_focal_relative_pose",
    "read_depth",
    "rotation_error_deg",
    "sample_depth",
    "translation_error_deg",
]
