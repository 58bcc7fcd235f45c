// Scale-only ablation of the shared-focal solver: no shifts, unknowns scale and f.
// 3 correspondences, 2 of the 3 distance equations, at most 2 solutions.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "madsfm/geometry/affine_depth_pose.h"

namespace madsfm {

// Conventions of SolveRelposeAffineDepthSharedFocal4pt with shift0 = shift1 = 0.
int SolveRelposeScaleDepthSharedFocal3pt(const std::vector<Eigen::Vector2d>& p0, const std::vector<Eigen::Vector2d>& p1,
                                         const std::vector<double>& d0, const std::vector<double>& d1,
                                         std::vector<AffineDepthPose>* models);

}  // namespace madsfm
