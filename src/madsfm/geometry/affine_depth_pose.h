// The model every affine-depth solver and estimator of madsfm produces.
//
// Conventions (docs/conventions.md):
//  * Views are numbered 0 and 1. A 3-D point X0 in camera 0 maps to camera 1 as X1 = R * X0 + t
//    (R, t = cam1_from_cam0).
//  * Depth priors d0, d1 are corrected affinely: view 0 uses d0 + shift0, view 1 uses
//    scale * (d1 + shift1). t is in the units of the corrected depth of view 0.
//  * f0, f1 are focal lengths in the units of the image coordinates the model was estimated
//    from: 1 for normalised coordinates (calibrated), pixels for principal-point-centred pixel
//    coordinates (shared / two focal).
#pragma once

#include <Eigen/Core>

namespace madsfm {

struct AffineDepthPose {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  double scale = 1.0;
  double shift0 = 0.0;
  double shift1 = 0.0;
  double f0 = 1.0;
  double f1 = 1.0;

  // Corrected depth of a prior in view 0 / view 1.
  double Depth0(double d0) const { return d0 + shift0; }
  double Depth1(double d1) const { return scale * (d1 + shift1); }
};

}  // namespace madsfm
