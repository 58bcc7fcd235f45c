// Calibrated scale-only ablation (paper Sec. 5.3): depth priors corrected by one relative scale,
// no shifts. 3 correspondences, one solution (similarity alignment of the lifted points).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "madsfm/geometry/affine_depth_pose.h"

namespace madsfm {

// Same conventions as SolveRelposeAffineDepth3pt with shift0 = shift1 = 0: finds (R, t, scale)
// with scale * d1[i] * [x1[i]; 1] ~= R * d0[i] * [x0[i]; 1] + t in the least-squares sense
// (exact for consistent data). Uses the first 3 entries; needs d0[i], d1[i] > 0 (there is no shift
// to fix a non-positive prior). Returns 0 or 1.
int SolveRelposeScaleDepth3pt(const std::vector<Eigen::Vector2d>& x0, const std::vector<Eigen::Vector2d>& x1,
                              const std::vector<double>& d0, const std::vector<double>& d1,
                              std::vector<AffineDepthPose>* models);

}  // namespace madsfm
