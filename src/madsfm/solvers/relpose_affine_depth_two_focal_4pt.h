// Affine-depth relative pose with two unknown focal lengths (paper Sec. 4.1, "Two-Focal Solver"):
// 4 correspondences with depth priors, 5 of the 6 distance equations, at most 4 solutions.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "madsfm/geometry/affine_depth_pose.h"

namespace madsfm {

// p0[i], p1[i]: pixel coordinates minus each view's principal point; d0[i], d1[i]: depth priors.
// With K0 = diag(f0, f0, 1), K1 = diag(f1, f1, 1), finds every real (R, t, scale, shift0, shift1,
// f0, f1) satisfying 5 of the 6 distance equations exactly (R, t by rigid alignment of the 4
// lifted points), with f0, f1 > 0, scale > 0, corrected depths > 0. Returns the count (<= 4).
// The equations used are those of the point pairs (0,1), (0,2), (0,3), (1,2), (1,3); the distance
// of pair (2,3) is not enforced. Uses the first 4 entries; fewer, degenerate or non-finite input
// gives 0 solutions. f0, f1 are in the units of p0, p1 (pixels).
int SolveRelposeAffineDepthTwoFocal4pt(const std::vector<Eigen::Vector2d>& p0, const std::vector<Eigen::Vector2d>& p1,
                                       const std::vector<double>& d0, const std::vector<double>& d1,
                                       std::vector<AffineDepthPose>* models);

}  // namespace madsfm
