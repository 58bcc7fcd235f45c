// Gives a point-based relative pose the depth parameters of the affine-depth model (paper Sec. 4.4):
// triangulate the correspondences with the pose, then fit scale and shifts by least squares.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "madsfm/geometry/affine_depth_pose.h"

namespace madsfm {

// x0[i], x1[i]: normalised image coordinates (for focal-unknown models, pixel coordinates divided
// by the model's focal lengths); d0[i], d1[i]: depth priors (NaN = none). `model` holds R and a
// translation direction t (any length). Triangulates every correspondence, fits
//   k * z0_i = d0_i + shift0,   k * z1_i = scale * (d1_i + shift1)
// by linear least squares over the points in front of both cameras, and rescales model->t by k.
// Needs >= 2 points with depth in each view; returns false (model untouched) otherwise or when
// the fit gives a non-positive scale.
bool FitAffineDepthToPose(const std::vector<Eigen::Vector2d>& x0, const std::vector<Eigen::Vector2d>& x1,
                          const std::vector<double>& d0, const std::vector<double>& d1, AffineDepthPose* model,
                          bool fit_shift = true);

}  // namespace madsfm
