#include "madsfm/estimators/relpose_problem.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace madsfm {

CameraMode ParseCameraMode(const std::string& name) {
  if (name == "calibrated") return CameraMode::kCalibrated;
  if (name == "shared_focal") return CameraMode::kSharedFocal;
  if (name == "two_focal") return CameraMode::kTwoFocal;
  throw std::invalid_argument("unknown camera mode '" + name + "' (expected calibrated, shared_focal or two_focal)");
}

std::string CameraModeName(CameraMode mode) {
  switch (mode) {
    case CameraMode::kCalibrated: return "calibrated";
    case CameraMode::kSharedFocal: return "shared_focal";
    case CameraMode::kTwoFocal: return "two_focal";
  }
  return "unknown";
}

void RelposeProblem::IndexDepths() {
  with_depth0.clear();
  with_depth1.clear();
  with_both_depths.clear();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int i = 0; i < size(); ++i) {
    const bool v0 = std::isfinite(d0[i]) && d0[i] > 0.0;
    const bool v1 = std::isfinite(d1[i]) && d1[i] > 0.0;
    if (!v0) d0[i] = nan;
    if (!v1) d1[i] = nan;
    if (v0) with_depth0.push_back(i);
    if (v1) with_depth1.push_back(i);
    if (v0 && v1) with_both_depths.push_back(i);
  }
}

RelposeProblem MakeRelposeProblem(CameraMode mode, const std::vector<Eigen::Vector2d>& p0,
                                  const std::vector<Eigen::Vector2d>& p1, const std::vector<double>& d0,
                                  const std::vector<double>& d1, const PinholeCamera& camera0,
                                  const PinholeCamera& camera1) {
  if (p0.size() != p1.size() || d0.size() != p0.size() || d1.size() != p0.size()) {
    throw std::invalid_argument("MakeRelposeProblem: p0, p1, d0, d1 must have the same length");
  }
  RelposeProblem problem;
  problem.mode = mode;
  const size_t n = p0.size();
  problem.x0.resize(n);
  problem.x1.resize(n);
  for (size_t i = 0; i < n; ++i) {
    if (mode == CameraMode::kCalibrated) {
      problem.x0[i] = Eigen::Vector2d((p0[i].x() - camera0.cx) / camera0.fx, (p0[i].y() - camera0.cy) / camera0.fy);
      problem.x1[i] = Eigen::Vector2d((p1[i].x() - camera1.cx) / camera1.fx, (p1[i].y() - camera1.cy) / camera1.fy);
    } else {
      problem.x0[i] = Eigen::Vector2d(p0[i].x() - camera0.cx, p0[i].y() - camera0.cy);
      problem.x1[i] = Eigen::Vector2d(p1[i].x() - camera1.cx, p1[i].y() - camera1.cy);
    }
  }
  if (mode == CameraMode::kCalibrated) {
    problem.pixel_scale0 = std::sqrt(camera0.fx * camera0.fy);
    problem.pixel_scale1 = std::sqrt(camera1.fx * camera1.fy);
  }
  problem.d0 = d0;
  problem.d1 = d1;
  problem.IndexDepths();
  return problem;
}

}  // namespace madsfm
