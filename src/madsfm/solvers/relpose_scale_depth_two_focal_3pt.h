// Scale-only ablation of the two-focal solver: no shifts, unknowns scale, f0, f1.
// 3 correspondences, the 3 distance equations are linear in (w0, scale^2 w1, scale^2):
// at most 1 solution.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "madsfm/geometry/affine_depth_pose.h"

namespace madsfm {

// Conventions of SolveRelposeAffineDepthTwoFocal4pt with shift0 = shift1 = 0: p0, p1 are pixel
// coordinates minus the principal points, f0, f1 come out in pixels. The 3 distance equations are
// met exactly and R, t map the 3 lifted points onto each other exactly. Uses the first 3 entries;
// needs d0[i], d1[i] > 0. Returns 0 or 1.
int SolveRelposeScaleDepthTwoFocal3pt(const std::vector<Eigen::Vector2d>& p0, const std::vector<Eigen::Vector2d>& p1,
                                      const std::vector<double>& d0, const std::vector<double>& d1,
                                      std::vector<AffineDepthPose>* models);

}  // namespace madsfm
