// Affine-depth relative pose with one unknown focal length shared by both views (paper Sec. 4.1,
// "Shared-Focal Solver"): 4 correspondences with depth priors, 4 of the 6 distance equations,
// at most 8 solutions.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "madsfm/geometry/affine_depth_pose.h"

namespace madsfm {

// p0[i], p1[i]: pixel coordinates minus the principal point; d0[i], d1[i]: depth priors.
// With K = diag(f, f, 1), finds every real (R, t, scale, shift0, shift1, f) that satisfies the
// distance equations of 4 of the 6 point pairs exactly (R, t then by rigid alignment of the 4
// lifted points), with f > 0, scale > 0 and all corrected depths > 0. f0 = f1 = f.
// Returns the number of solutions (<= 8); uses the first 4 entries.
int SolveRelposeAffineDepthSharedFocal4pt(const std::vector<Eigen::Vector2d>& p0, const std::vector<Eigen::Vector2d>& p1,
                                          const std::vector<double>& d0, const std::vector<double>& d1,
                                          std::vector<AffineDepthPose>* models);

}  // namespace madsfm
