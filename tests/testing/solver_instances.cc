#include "testing/solver_instances.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "testing/median.h"

namespace madsfm::testing {
namespace {

double Uniform(std::mt19937& rng, double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
double LogUniform(std::mt19937& rng, double a, double b) { return std::exp(Uniform(rng, std::log(a), std::log(b))); }

Eigen::Matrix3d RandomRotation(std::mt19937& rng, double max_angle_rad) {
  Eigen::Vector3d axis(Uniform(rng, -1, 1), Uniform(rng, -1, 1), Uniform(rng, -1, 1));
  while (axis.norm() < 1e-3) axis = Eigen::Vector3d(Uniform(rng, -1, 1), Uniform(rng, -1, 1), Uniform(rng, -1, 1));
  return Eigen::AngleAxisd(Uniform(rng, 0.0, max_angle_rad), axis.normalized()).toRotationMatrix();
}

}  // namespace

SolverInstance MakeSolverInstance(std::mt19937& rng, const SolverInstanceOptions& opt) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (;;) {
    SolverInstance inst;
    const double f0 = LogUniform(rng, 200.0, 3000.0);
    const double f1 = opt.setup == CameraSetup::kTwoFocal ? LogUniform(rng, 200.0, 3000.0) : f0;
    inst.focal0 = f0;
    inst.focal1 = f1;
    const double m = LogUniform(rng, 1.0, 25.0);  // point depths in [m/2, 2m] within [0.5, 50]
    const Eigen::Matrix3d R = RandomRotation(rng, 60.0 * M_PI / 180.0);
    Eigen::Vector3d dir(gauss(rng), gauss(rng), gauss(rng));
    const Eigen::Vector3d c1 = dir.normalized() * Uniform(rng, 0.01, 0.3) * m;  // camera 1 centre
    const Eigen::Vector3d t = -R * c1;

    std::vector<Eigen::Vector3d> X0, X1;
    // At most 200 draws (4 per point beyond 50 points): a camera pair that sees too few points is drawn again.
    const int max_tries = std::max(200, 4 * opt.num_points);
    for (int tries = 0; tries < max_tries && static_cast<int>(X0.size()) < opt.num_points; ++tries) {
      const Eigen::Vector3d X(Uniform(rng, -0.6, 0.6), Uniform(rng, -0.45, 0.45), 1.0);
      const Eigen::Vector3d P0 = X * Uniform(rng, 0.5 * m, 2.0 * m);
      const Eigen::Vector3d P1 = R * P0 + t;
      if (P1.z() < 0.2 * m || std::abs(P1.x() / P1.z()) > 1.0 || std::abs(P1.y() / P1.z()) > 0.8) continue;
      X0.push_back(P0);
      X1.push_back(P1);
    }
    if (static_cast<int>(X0.size()) < opt.num_points) continue;

    const double scale = LogUniform(rng, 0.1, 10.0);
    std::vector<double> z0, z1s;
    for (int i = 0; i < opt.num_points; ++i) {
      z0.push_back(X0[i].z());
      z1s.push_back(X1[i].z() / scale);
    }
    const double med0 = Median(z0), med1 = Median(z1s);
    const double shift0 = opt.with_shift ? Uniform(rng, -0.5, 0.5) * med0 : 0.0;
    const double shift1 = opt.with_shift ? Uniform(rng, -0.5, 0.5) * med1 : 0.0;

    bool ok = true;
    for (int i = 0; i < opt.num_points && ok; ++i) {
      double d0 = z0[i] - shift0, d1 = z1s[i] - shift1;
      if (opt.depth_noise > 0) {
        d0 *= 1.0 + opt.depth_noise * gauss(rng);
        d1 *= 1.0 + opt.depth_noise * gauss(rng);
      }
      if (!(d0 > 0.02 * med0) || !(d1 > 0.02 * med1)) ok = false;
      inst.d0.push_back(d0);
      inst.d1.push_back(d1);
      const bool calibrated = opt.setup == CameraSetup::kCalibrated;
      const double u0 = calibrated ? 1.0 : f0, u1 = calibrated ? 1.0 : f1;  // solver units per normalised unit
      Eigen::Vector2d a = X0[i].hnormalized() * u0, b = X1[i].hnormalized() * u1;
      if (opt.pixel_noise > 0) {
        a += Eigen::Vector2d(gauss(rng), gauss(rng)) * opt.pixel_noise * u0 / f0;
        b += Eigen::Vector2d(gauss(rng), gauss(rng)) * opt.pixel_noise * u1 / f1;
      }
      inst.x0.push_back(a);
      inst.x1.push_back(b);
    }
    if (!ok) continue;
    inst.gt.R = R;
    inst.gt.t = t;
    inst.gt.scale = scale;
    inst.gt.shift0 = shift0;
    inst.gt.shift1 = shift1;
    inst.gt.f0 = opt.setup == CameraSetup::kCalibrated ? 1.0 : f0;
    inst.gt.f1 = opt.setup == CameraSetup::kCalibrated ? 1.0 : f1;
    inst.median_depth = med0;
    return inst;
  }
}

double ModelError(const AffineDepthPose& m, const SolverInstance& inst) {
  const AffineDepthPose& g = inst.gt;
  double err = (m.R - g.R).norm();
  err = std::max(err, (m.t - g.t).norm() / g.t.norm());
  err = std::max(err, std::abs(m.scale / g.scale - 1.0));
  err = std::max(err, std::abs(m.shift0 - g.shift0) / inst.median_depth);
  err = std::max(err, std::abs(m.shift1 - g.shift1) * g.scale / inst.median_depth);
  err = std::max(err, std::abs(m.f0 / g.f0 - 1.0));
  err = std::max(err, std::abs(m.f1 / g.f1 - 1.0));
  return std::isfinite(err) ? err : std::numeric_limits<double>::infinity();
}

double MinModelError(const std::vector<AffineDepthPose>& models, const SolverInstance& inst) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& m : models) best = std::min(best, ModelError(m, inst));
  return best;
}

}  // namespace madsfm::testing
