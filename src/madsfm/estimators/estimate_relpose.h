// Public entry point: relative pose with affine-corrected depth priors from pixel matches.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "madsfm/estimators/hybrid_estimator_options.h"
#include "madsfm/estimators/relpose_problem.h"

namespace madsfm {

// p0[i] <-> p1[i]: matched pixel coordinates (pixel centres at integers); d0[i], d1[i]: depth priors
// at those pixels (NaN or <= 0: no prior; such matches still count as point correspondences).
// camera0/1: intrinsics; in the focal modes only their principal points are used.
// max_image_dim (> 0): plausible focal lengths are [0.1, 10] x max_image_dim (COLMAP's sanity bounds).
// The returned model has R, t (X1 = R X0 + t, in units of view 0's corrected prior), scale, shifts and
// f0, f1 in pixels: estimated in the focal modes, sqrt(fx * fy) of the cameras when calibrated.
HybridEstimate EstimateRelativePose(CameraMode mode, const std::vector<Eigen::Vector2d>& p0,
                                    const std::vector<Eigen::Vector2d>& p1, const std::vector<double>& d0,
                                    const std::vector<double>& d1, const PinholeCamera& camera0,
                                    const PinholeCamera& camera1, const HybridEstimatorOptions& options,
                                    double max_image_dim = 0.0);

// Options of the point-only baseline on the same engine: point solver only, Sampson scoring.
HybridEstimatorOptions PointOnlyOptions(const HybridEstimatorOptions& base);

}  // namespace madsfm
