// Joint least-squares refinement of all affine-depth model parameters over the inliers of the three
// data types (paper Sec. 4.4, local optimisation and final refinement):
//   E = sum_{I0} ||r_0->1||^2 + sum_{I1} ||r_1->0||^2 + w_s * sum_{Is} e_s^2
// with depth-induced reprojection residuals and the Sampson residual, all in pixels.
// Levenberg-Marquardt with analytic Jacobians; the rotation is updated on SO(3).
#pragma once

#include <vector>

#include "madsfm/estimators/relpose_problem.h"
#include "madsfm/geometry/affine_depth_pose.h"

namespace madsfm {

struct RelposeRefinerOptions {
  int max_iterations = 10;
  double sampson_weight = 1.0;  // w_s, weight of the squared Sampson residuals
  double reprojection_weight = 1.0;  // weight of the squared reprojection residuals (0: epipolar only)
  bool refine_focal = true;     // false: focal lengths stay fixed (focal modes)
  bool refine_shift = true;     // false: shifts stay as they are (scale-only ablation)
  bool refine_depth = true;     // false: scale and shifts stay fixed (no depth data)
  // false: R and the direction of t stay fixed, only |t| moves (with the depth parameters): fits the depth
  // corrections to a given pose.
  bool refine_pose = true;
  // > 0: steps that make |shift0| or |shift1| exceed max_shift times shift_reference0 / shift_reference1 (e.g.
  // the median prior of the view) are rejected, like steps that make an inlier's corrected depth non-positive.
  double max_shift = 0.0;
  double shift_reference0 = 1.0, shift_reference1 = 1.0;
  double function_tolerance = 1e-10;  // stop when the relative cost decrease is below this
  // > 0: a Cauchy loss s^2 log(1 + r^2 / s^2) on every residual r (pixels, after the weights above) with this scale
  // s, by reweighted normal equations (weight 1 / (1 + r^2 / s^2)); 0: least squares. The covariance of the summary
  // stays that of least squares at the solution.
  double cauchy_scale = 0.0;
};

struct RelposeRefinerSummary {
  double initial_cost = 0.0;
  double final_cost = 0.0;
  int iterations = 0;
  // Standard deviations of shift0, shift1 and scale at the solution from the Gauss-Newton covariance
  // (final_cost / (residuals - free parameters) * (J^T J)^-1); NaN for parameters that are not free.
  double sigma_shift0 = 0.0, sigma_shift1 = 0.0, sigma_scale = 0.0;
  // ... and of the focal lengths (pixels; shared focal: sigma_f0, with sigma_f1 NaN).
  double sigma_f0 = 0.0, sigma_f1 = 0.0;
};

// Refines *model in place. The focal lengths are refined in the focal modes (one shared or two
// independent), never when calibrated. Steps that make a corrected depth of an inlier non-positive
// or a focal / scale non-positive are rejected (the min-depth constraint). Returns false (model
// untouched) if there are fewer residuals than parameters or the problem is not finite.
bool RefineRelpose(const RelposeProblem& problem, const std::vector<int>& inliers_reproj0,
                   const std::vector<int>& inliers_reproj1, const std::vector<int>& inliers_sampson,
                   const RelposeRefinerOptions& options, AffineDepthPose* model,
                   RelposeRefinerSummary* summary = nullptr);

// Residual vector of the same cost (for tests: the Jacobian check against finite differences).
// Order: [r_0->1 (2 per inlier), r_1->0 (2 per inlier), sqrt(w_s) e_s (1 per inlier)].
void EvaluateRelposeResiduals(const RelposeProblem& problem, const std::vector<int>& inliers_reproj0,
                              const std::vector<int>& inliers_reproj1, const std::vector<int>& inliers_sampson,
                              double sampson_weight, const AffineDepthPose& model, std::vector<double>* residuals,
                              std::vector<std::vector<double>>* jacobian = nullptr);

// Parameter layout of the Jacobian columns: rotation (3, left perturbation exp([w]x) R), t (3),
// shift0, shift1, scale, f0, f1 (11 columns; in shared-focal mode use f0 + f1 columns for f).
inline constexpr int kRelposeNumParams = 11;

}  // namespace madsfm
