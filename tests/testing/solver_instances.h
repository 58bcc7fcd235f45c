// Random minimal-solver instances with realistic two-view geometry, for the solver tests and the
// solver benchmark (issue 3): depths 0.5-50, rotations up to 60 deg, baselines 1-30% of the depth,
// relative scale 0.1-10, shifts up to +-50% of the median prior depth, focal lengths 200-3000 px.
#pragma once

#include <Eigen/Core>
#include <random>
#include <vector>

#include "madsfm/geometry/affine_depth_pose.h"

namespace madsfm::testing {

enum class CameraSetup { kCalibrated, kSharedFocal, kTwoFocal };

struct SolverInstance {
  // Ground truth. Calibrated: f0 = f1 = 1 (x are normalised); otherwise focal lengths in pixels.
  AffineDepthPose gt;
  // Image coordinates in solver units: normalised (calibrated) or pixels centred on the principal point.
  std::vector<Eigen::Vector2d> x0, x1;
  // Depth priors (> 0): gt.Depth0(d0[i]) and gt.Depth1(d1[i]) are the true depths.
  std::vector<double> d0, d1;
  // Focal lengths (pixels) of the simulated cameras; for calibrated instances they convert the
  // pixel noise to normalised units.
  double focal0 = 1.0, focal1 = 1.0;
  double median_depth = 1.0;  // median true depth in view 0
};

struct SolverInstanceOptions {
  CameraSetup setup = CameraSetup::kCalibrated;
  int num_points = 3;
  bool with_shift = true;        // false: shift0 = shift1 = 0 (scale-only ablation)
  double pixel_noise = 0.0;      // std. dev. of Gaussian noise added to image coordinates (pixels)
  double depth_noise = 0.0;      // relative std. dev. of multiplicative noise on the priors
};

SolverInstance MakeSolverInstance(std::mt19937& rng, const SolverInstanceOptions& options);

// Relative error of a model against the ground truth: the max of ||R - R_gt||_F, ||t - t_gt|| /
// ||t_gt||, |scale/scale_gt - 1|, |shift - shift_gt| / median_depth (per view, in that view's prior
// units) and |f/f_gt - 1|.
double ModelError(const AffineDepthPose& model, const SolverInstance& instance);

// Smallest ModelError over the given models (infinity if there are none).
double MinModelError(const std::vector<AffineDepthPose>& models, const SolverInstance& instance);

}  // namespace madsfm::testing
