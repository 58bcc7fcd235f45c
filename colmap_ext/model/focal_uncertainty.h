// How well bundle adjustment determines a camera's focal length in a reconstruction: the standard deviation of the
// focal length from the Gauss-Newton covariance of COLMAP's bundle adjustment problem at the model (reprojection
// errors of every observation; image poses, 3-D points, the focal length and the extra distortion parameters free,
// the principal point fixed, as `colmap mapper` refines by default). The colmap binary does not report it; the
// mapper compares it with the uncertainty of madsfm's own focal estimate (pipeline/mapper.cc).
#pragma once

#include <cstdint>
#include <optional>

#include "colmap_ext/model/reconstruction.h"

namespace madsfm::colmap {

struct FocalUncertainty {
  double focal = 0.0;           // the model's focal length, pixels (mean of fx and fy for two-focal models)
  double sigma = 0.0;           // its standard deviation, pixels
  double residual_sigma = 0.0;  // reprojection noise estimated from the residuals, pixels
  int num_observations = 0;     // observations of points with at least two registered observations
  double Relative() const { return sigma / focal; }
};

// 3-D points are eliminated (Schur complement); the reduced system over poses and camera parameters is dense, so
// models of more than max_images registered images are not evaluated. The similarity gauge (7 directions of zero
// curvature) is handled by a relative 1e-10 regularisation: the focal length does not change along it, so its
// variance is that of any generalised inverse. Returns nullopt for an unknown camera, an unsupported camera model,
// fewer than 2 registered images of the model, more than max_images, or too few observations.
std::optional<FocalUncertainty> BundleFocalUncertainty(const Reconstruction& model, uint32_t camera_id,
                                                       int max_images = 300);

}  // namespace madsfm::colmap
