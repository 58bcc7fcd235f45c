#include "madsfm/estimators/pair_evaluation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "madsfm/geometry/pose_error.h"
#include "madsfm/io/depth_sampling.h"

namespace madsfm {

const std::vector<std::string>& MethodNames() {
  static const std::vector<std::string> names = {"hybrid", "points", "depth_only", "no_shift", "sampson_score"};
  return names;
}

HybridEstimatorOptions OptionsForMethod(const std::string& method, const HybridEstimatorOptions& base) {
  HybridEstimatorOptions o = base;
  if (method == "hybrid") return o;
  if (method == "points") return PointOnlyOptions(base);
  if (method == "depth_only") {
    o.solvers = SolverChoice::kDepthOnly;
    o.scoring = ScoringMode::kReprojectionOnly;
    return o;
  }
  if (method == "no_shift") {
    o.estimate_shift = false;
    return o;
  }
  if (method == "sampson_score") {
    o.scoring = ScoringMode::kSampsonOnly;
    return o;
  }
  throw std::invalid_argument("unknown method '" + method +
                              "' (expected hybrid, points, depth_only, no_shift or sampson_score)");
}

void SamplePairDepths(const PairData& pair, std::vector<double>* d0, std::vector<double>* d1) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (pair.depth0) *d0 = SampleDepths(*pair.depth0, pair.p0, pair.width0, pair.height0);
  else d0->assign(pair.p0.size(), nan);
  if (pair.depth1) *d1 = SampleDepths(*pair.depth1, pair.p1, pair.width1, pair.height1);
  else d1->assign(pair.p1.size(), nan);
}

PairResult EvaluatePair(const PairData& pair, CameraMode mode, const std::string& method,
                        const HybridEstimatorOptions& base_options) {
  PairResult r;
  r.pair = pair.path;
  r.method = method;
  r.camera_mode = CameraModeName(mode);
  r.num_matches = static_cast<int>(pair.p0.size());
  r.notes = pair.warnings;

  std::vector<double> d0, d1;
  SamplePairDepths(pair, &d0, &d1);
  for (size_t i = 0; i < d0.size(); ++i) r.num_with_depth += (d0[i] > 0.0 && d1[i] > 0.0);

  HybridEstimatorOptions options = OptionsForMethod(method, base_options);
  if (method != "points" && r.num_with_depth < 4) {
    options = PointOnlyOptions(base_options);
    r.notes.push_back(pair.HasDepth() ? "fewer than 4 matches with valid depth in both views: point method"
                                      : "no depth: point method");
  }

  PinholeCamera cam0{pair.K0(0, 0), pair.K0(1, 1), pair.K0(0, 2), pair.K0(1, 2)};
  PinholeCamera cam1{pair.K1(0, 0), pair.K1(1, 1), pair.K1(0, 2), pair.K1(1, 2)};
  if (mode != CameraMode::kCalibrated) {
    // Only the principal points may be used: make sure no focal length leaks into the estimate.
    cam0.fx = cam0.fy = cam1.fx = cam1.fy = 1.0;
  }
  const double max_dim = std::max({pair.width0, pair.height0, pair.width1, pair.height1});
  const HybridEstimate est = EstimateRelativePose(mode, pair.p0, pair.p1, d0, d1, cam0, cam1, options,
                                                  mode == CameraMode::kCalibrated ? 0.0 : max_dim);
  if (mode == CameraMode::kCalibrated) {
    // Report the focal lengths that were used.
    r.model.f0 = std::sqrt(pair.K0(0, 0) * pair.K0(1, 1));
    r.model.f1 = std::sqrt(pair.K1(0, 0) * pair.K1(1, 1));
  }
  r.success = est.success;
  r.iterations = est.iterations;
  r.runtime_ms = est.runtime_ms;
  if (est.success) {
    const double f0 = r.model.f0, f1 = r.model.f1;
    r.model = est.model;
    if (mode == CameraMode::kCalibrated) {
      r.model.f0 = f0;
      r.model.f1 = f1;
    }
    r.num_inliers_reproj0 = est.num_inliers_reproj0;
    r.num_inliers_reproj1 = est.num_inliers_reproj1;
    r.num_inliers_sampson = est.num_inliers_sampson;
  }

  if (pair.T_0to1) {
    const Eigen::Matrix3d R_gt = pair.T_0to1->topLeftCorner<3, 3>();
    const Eigen::Vector3d t_gt = pair.T_0to1->topRightCorner<3, 1>();
    const double fgt0 = 0.5 * (pair.K0(0, 0) + pair.K0(1, 1));
    const double fgt1 = 0.5 * (pair.K1(0, 0) + pair.K1(1, 1));
    if (r.success) {
      r.rot_err_deg = RotationErrorDeg(r.model.R, R_gt);
      r.trans_err_deg = TranslationErrorDeg(r.model.t, t_gt);
      if (mode == CameraMode::kSharedFocal) {
        const double fgt = 0.5 * (fgt0 + fgt1);
        r.focal_err = std::abs(r.model.f0 - fgt) / fgt;
      } else if (mode == CameraMode::kTwoFocal) {
        r.focal_err = std::max(std::abs(r.model.f0 - fgt0) / fgt0, std::abs(r.model.f1 - fgt1) / fgt1);
      }
    } else {
      r.rot_err_deg = 180.0;
      r.trans_err_deg = 180.0;
      if (mode != CameraMode::kCalibrated) r.focal_err = 1.0;
    }
  }
  return r;
}

}  // namespace madsfm
