#include "madsfm/estimators/pair_evaluation.h"

#include <Eigen/LU>
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

namespace {

double MedianOf(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + mid, v.end());
  const double hi = v[mid];
  if (v.size() % 2 == 1) return hi;
  return 0.5 * (hi + *std::max_element(v.begin(), v.begin() + mid));
}

// Relative least-squares affine fit z ~ a d + b: minimises sum ((a d + b) / z - 1)^2; appends |(a d + b) / z - 1|.
void AffineFitErrors(const std::vector<double>& d, const std::vector<double>& z, std::vector<double>* errors) {
  double s11 = 0, s12 = 0, s22 = 0, r1 = 0, r2 = 0;
  for (size_t i = 0; i < d.size(); ++i) {
    const double u = d[i] / z[i], v = 1.0 / z[i];
    s11 += u * u, s12 += u * v, s22 += v * v, r1 += u, r2 += v;
  }
  const double det = s11 * s22 - s12 * s12;
  double a, b;
  if (std::abs(det) > 1e-12 * (s11 * s22 + 1e-300)) {
    a = (r1 * s22 - r2 * s12) / det;
    b = (s11 * r2 - s12 * r1) / det;
  } else {  // degenerate (constant d): scale only
    a = s11 > 0 ? r1 / s11 : 0.0;
    b = 0.0;
  }
  for (size_t i = 0; i < d.size(); ++i) errors->push_back(std::abs((a * d[i] + b) / z[i] - 1.0));
}

}  // namespace

std::optional<DepthCorrectionError> MeasureDepthCorrection(const AffineDepthPose& m, const std::vector<double>& d0,
                                                           const std::vector<double>& d1, const std::vector<double>& z0,
                                                           const std::vector<double>& z1, const std::vector<char>& use) {
  std::vector<double> ratio;  // z_hat / z over both views
  std::vector<double> pd0, pz0, pd1, pz1;
  for (size_t i = 0; i < use.size(); ++i) {
    if (!use[i] || !(d0[i] > 0.0) || !(d1[i] > 0.0) || !(z0[i] > 0.0) || !(z1[i] > 0.0)) continue;
    pd0.push_back(d0[i]), pz0.push_back(z0[i]), pd1.push_back(d1[i]), pz1.push_back(z1[i]);
    ratio.push_back(m.Depth0(d0[i]) / z0[i]);
    ratio.push_back(m.Depth1(d1[i]) / z1[i]);
  }
  if (pd0.size() < 8) return std::nullopt;
  // Gauge: argmin_g sum (g r - 1)^2.
  double sr = 0.0, srr = 0.0;
  for (double r : ratio) sr += r, srr += r * r;
  const double g = srr > 0.0 ? sr / srr : 0.0;
  std::vector<double> errors;
  errors.reserve(ratio.size());
  for (double r : ratio) errors.push_back(std::abs(g * r - 1.0));
  DepthCorrectionError out;
  out.support = static_cast<int>(pd0.size());
  out.estimate = MedianOf(errors);
  std::vector<double> oracle;
  AffineFitErrors(pd0, pz0, &oracle);
  AffineFitErrors(pd1, pz1, &oracle);
  out.oracle = MedianOf(oracle);
  return out;
}

void AppendEstimateNotes(const HybridEstimate& estimate, std::vector<std::string>* notes) {
  if (estimate.shifts_dropped) {
    notes->push_back("the priors do not determine the shifts: estimated again without shifts (scale only)");
  }
  if (estimate.scale_reset) {
    notes->push_back("the fitted scale drifted without bound: replaced by the ratio of the views' median priors");
  }
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
    std::vector<double> v0, v1;
    for (size_t i = 0; i < d0.size(); ++i) {
      if (d0[i] > 0.0) v0.push_back(d0[i]);
      if (d1[i] > 0.0) v1.push_back(d1[i]);
    }
    if (!v0.empty() && !v1.empty() && r.num_with_depth > 0) {
      r.absurd_shift = std::abs(r.model.shift0) > 10.0 * MedianOf(v0) || std::abs(r.model.shift1) > 10.0 * MedianOf(v1);
    }
    r.num_inliers_reproj0 = est.num_inliers_reproj0;
    r.num_inliers_reproj1 = est.num_inliers_reproj1;
    r.num_inliers_sampson = est.num_inliers_sampson;
    r.depth_observable = est.depth_observable;
    r.shifts_dropped = est.shifts_dropped;
    r.scale_reset = est.scale_reset;
    r.low_parallax_weighting = est.low_parallax_weighting;
    r.score = est.score;
    AppendEstimateNotes(est, &r.notes);
    r.sigma_scale = est.sigma_scale;
    r.sigma_shift0 = est.sigma_shift0;
    r.sigma_shift1 = est.sigma_shift1;
    r.sigma_focal0 = est.sigma_focal0;
    r.sigma_focal1 = est.sigma_focal1;
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
    if (r.success && pair.gt_depth0 && pair.gt_depth1 && r.num_with_depth > 0) {
      // True inliers: the true depth of p0 lifted with the true pose lands within 2 px of p1 and agrees with the
      // true depth at p1 (5%).
      const std::vector<double> z0 = SampleDepths(*pair.gt_depth0, pair.p0, pair.width0, pair.height0);
      const std::vector<double> z1 = SampleDepths(*pair.gt_depth1, pair.p1, pair.width1, pair.height1);
      const Eigen::Matrix3d K0_inv = pair.K0.inverse();
      std::vector<char> use(pair.p0.size(), 0);
      for (size_t i = 0; i < pair.p0.size(); ++i) {
        if (!(z0[i] > 0.0) || !(z1[i] > 0.0)) continue;
        const Eigen::Vector3d X1 = R_gt * (z0[i] * (K0_inv * Eigen::Vector3d(pair.p0[i].x(), pair.p0[i].y(), 1.0))) + t_gt;
        if (!(X1.z() > 0.0) || std::abs(X1.z() - z1[i]) > 0.05 * z1[i]) continue;
        const Eigen::Vector3d h = pair.K1 * X1;
        use[i] = (h.head<2>() / h.z() - pair.p1[i]).norm() < 2.0;
      }
      const auto e = MeasureDepthCorrection(r.model, d0, d1, z0, z1, use);
      if (e) {
        r.depth_err = e->estimate;
        r.depth_err_oracle = e->oracle;
        r.depth_support = e->support;
      }
    }
  }
  return r;
}

}  // namespace madsfm
