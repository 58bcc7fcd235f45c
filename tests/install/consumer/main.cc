// Calls the installed library: the relative-pose estimator on a small synthetic instance (known pose, exact depth
// priors with a known affine distortion), the JSON writer, and a COLMAP-side function of madsfm_colmap. Prints one
// JSON line; exits 1 unless the pose is recovered.
#include <Eigen/Geometry>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <random>
#include <vector>

#include "colmap_ext/camera/camera_models.h"
#include "madsfm/estimators/estimate_relpose.h"
#include "madsfm/geometry/pose_error.h"
#include "madsfm/io/json_writer.h"

int main() {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.2, Eigen::Vector3d(0.3, 1.0, 0.1).normalized()).toRotationMatrix();
  const Eigen::Vector3d t(0.5, 0.05, 0.1);
  const madsfm::PinholeCamera camera{500.0, 500.0, 320.0, 240.0};
  std::vector<Eigen::Vector2d> p0, p1;
  std::vector<double> d0, d1;
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d X0(2.0 * u(rng), 1.5 * u(rng), 4.0 + u(rng));
    const Eigen::Vector3d X1 = R * X0 + t;
    p0.emplace_back(camera.fx * X0.x() / X0.z() + camera.cx, camera.fy * X0.y() / X0.z() + camera.cy);
    p1.emplace_back(camera.fx * X1.x() / X1.z() + camera.cx, camera.fy * X1.y() / X1.z() + camera.cy);
    d0.push_back(X0.z() - 0.3);          // prior = true depth - shift0
    d1.push_back(X1.z() / 2.0 + 0.2);    // prior = true depth / scale - shift1
  }
  madsfm::HybridEstimatorOptions options;
  options.seed = 1;
  const madsfm::HybridEstimate e =
      madsfm::EstimateRelativePose(madsfm::CameraMode::kCalibrated, p0, p1, d0, d1, camera, camera, options);
  const double rot_err = madsfm::RotationErrorDeg(e.model.R, R);
  const double trans_err = madsfm::TranslationErrorDeg(e.model.t, t);
  nlohmann::json j = {{"success", e.success}, {"rot_err_deg", rot_err}, {"trans_err_deg", trans_err},
                      {"inliers", e.num_inliers_sampson}, {"camera_model", madsfm::colmap::CameraModelName(1)}};
  std::printf("%s\n", madsfm::DumpJson(j).c_str());
  const bool ok = e.success && rot_err < 1e-3 && trans_err < 1e-3 && e.num_inliers_sampson == 200 &&
                  madsfm::colmap::CameraModelName(1) == "PINHOLE";
  return ok ? 0 : 1;
}
