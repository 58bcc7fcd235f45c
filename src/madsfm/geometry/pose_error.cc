#include "madsfm/geometry/pose_error.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "madsfm/geometry/portable_math.h"

namespace madsfm {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

}  // namespace

double RotationErrorDeg(const Eigen::Matrix3d& R_est, const Eigen::Matrix3d& R_gt) {
  const Eigen::Matrix3d D = R_est * R_gt.transpose();
  // cos = (trace - 1) / 2, sin = |axial vector of the skew part|; atan2 is accurate at 0 and 180 deg.
  const double c = 0.5 * (D.trace() - 1.0);
  const double s = 0.5 * Eigen::Vector3d(D(2, 1) - D(1, 2), D(0, 2) - D(2, 0), D(1, 0) - D(0, 1)).norm();
  const double angle = portable::Atan2(s, c) * kRadToDeg;  // not std::atan2: same bits on every CPU
  return std::isfinite(angle) ? angle : 180.0;
}

double TranslationErrorDeg(const Eigen::Vector3d& t_est, const Eigen::Vector3d& t_gt) {
  if (!t_est.allFinite() || !t_gt.allFinite()) return 180.0;
  const double n_est = t_est.norm(), n_gt = t_gt.norm();
  if (!(n_est > 0.0) || !(n_gt > 0.0)) return 180.0;
  const Eigen::Vector3d a = t_est / n_est, b = t_gt / n_gt;
  const double theta = portable::Atan2(a.cross(b).norm(), a.dot(b)) * kRadToDeg;
  if (!std::isfinite(theta)) return 180.0;
  return std::min(theta, 180.0 - theta);
}

std::vector<double> PoseAuc(std::vector<double> errors, const std::vector<double>& thresholds) {
  // As SuperGlue's pose_auc: recall (i + 1) / n at the i-th sorted error, the curve starts at
  // (0, 0) and is extended flat from the last error below the threshold to the threshold.
  for (double& e : errors) {
    if (!(e >= 0.0)) e = std::numeric_limits<double>::infinity();  // NaN / failures never count
  }
  std::sort(errors.begin(), errors.end());
  const double n = static_cast<double>(errors.size());
  std::vector<double> aucs;
  aucs.reserve(thresholds.size());
  for (const double threshold : thresholds) {
    if (errors.empty() || !(threshold > 0.0)) {
      aucs.push_back(0.0);
      continue;
    }
    double area = 0.0, prev_error = 0.0, prev_recall = 0.0;
    for (size_t i = 0; i < errors.size() && errors[i] < threshold; ++i) {
      const double recall = static_cast<double>(i + 1) / n;
      area += 0.5 * (errors[i] - prev_error) * (recall + prev_recall);
      prev_error = errors[i];
      prev_recall = recall;
    }
    area += (threshold - prev_error) * prev_recall;
    aucs.push_back(area / threshold);
  }
  return aucs;
}

}  // namespace madsfm
