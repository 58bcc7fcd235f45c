// The data of one image pair prepared for the hybrid estimator, and the camera modes.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace madsfm {

enum class CameraMode { kCalibrated, kSharedFocal, kTwoFocal };

// "calibrated" | "shared_focal" | "two_focal" <-> CameraMode. Parse throws std::invalid_argument.
CameraMode ParseCameraMode(const std::string& name);
std::string CameraModeName(CameraMode mode);

// Pinhole intrinsics of one view (pixels). In the focal-unknown modes only cx, cy are used.
struct PinholeCamera {
  double fx = 1.0, fy = 1.0, cx = 0.0, cy = 0.0;
};

// Correspondences in solver units plus what scoring needs to express errors in pixels.
//  * calibrated:  x = K^-1 p (normalised), focal = 1, pixel_scale = sqrt(fx * fy) of each view;
//  * focal modes: x = p - principal point (pixels), focal estimated, pixel_scale = 1.
// d0 / d1 are the depth priors at the correspondences (NaN: no valid depth).
struct RelposeProblem {
  CameraMode mode = CameraMode::kCalibrated;
  std::vector<Eigen::Vector2d> x0, x1;
  std::vector<double> d0, d1;
  double pixel_scale0 = 1.0, pixel_scale1 = 1.0;
  // Plausible focal lengths (pixels) in the focal modes; hypotheses outside are discarded.
  double min_focal = 0.0, max_focal = 1e12;
  // Indices of correspondences with a valid prior in view 0 / view 1 / both.
  std::vector<int> with_depth0, with_depth1, with_both_depths;
  // Optional guide for the sampler: correspondences an earlier verification found consistent (COLMAP's inlier
  // matches of the pair), sorted and distinct. Minimal samples come from them with probability
  // HybridEstimatorOptions::guided_sampling_fraction; every correspondence is still scored. Empty: uniform sampling.
  std::vector<int> guided;

  int size() const { return static_cast<int>(x0.size()); }
  // Fills the index lists from d0 / d1 (valid = finite and > 0; invalid values are set to NaN).
  void IndexDepths();
};

// Builds the problem from pixel coordinates, depth priors (NaN or <= 0 = none) and cameras.
RelposeProblem MakeRelposeProblem(CameraMode mode, const std::vector<Eigen::Vector2d>& p0,
                                  const std::vector<Eigen::Vector2d>& p1, const std::vector<double>& d0,
                                  const std::vector<double>& d1, const PinholeCamera& camera0,
                                  const PinholeCamera& camera1);

}  // namespace madsfm
