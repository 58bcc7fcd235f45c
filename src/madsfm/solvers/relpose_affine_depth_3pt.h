// Calibrated affine-depth relative pose from 3 correspondences with depth priors in both views
// (paper Sec. 4.1, "Calibrated Solver"). Minimal: 3 points, at most 4 solutions.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "madsfm/geometry/affine_depth_pose.h"

namespace madsfm {

// x0[i], x1[i]: normalised image coordinates (K^-1 p, z = 1 implied); d0[i], d1[i]: depth priors.
// Finds every real (R, t, scale, shift0, shift1) with
//   scale * (d1[i] + shift1) * [x1[i]; 1] = R * (d0[i] + shift0) * [x0[i]; 1] + t,   i = 0..2,
// scale > 0 and all corrected depths > 0. Writes them to *models (cleared first; f0 = f1 = 1)
// and returns their number (<= 4). Uses the first 3 entries; fewer, degenerate or non-finite
// input gives 0 solutions.
int SolveRelposeAffineDepth3pt(const std::vector<Eigen::Vector2d>& x0, const std::vector<Eigen::Vector2d>& x1,
                               const std::vector<double>& d0, const std::vector<double>& d1,
                               std::vector<AffineDepthPose>* models);

}  // namespace madsfm
