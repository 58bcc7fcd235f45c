#include "madsfm/solvers/relpose_scale_depth_shared_focal_3pt.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <limits>
#include <random>
#include <vector>

#include "madsfm/geometry/pose_error.h"
#include "testing/solver_instances.h"
#include "testing/median.h"

namespace madsfm {
namespace {

using testing::CameraSetup;
using testing::MakeSolverInstance;
using testing::MinModelError;
using testing::ModelError;
using testing::SolverInstance;
using testing::SolverInstanceOptions;

constexpr int kMaxSolutions = 2;

SolverInstanceOptions ScaleOnlySharedFocalOptions(double pixel_noise = 0.0) {
  SolverInstanceOptions options;
  options.setup = CameraSetup::kSharedFocal;
  options.num_points = 3;
  options.with_shift = false;
  options.pixel_noise = pixel_noise;
  return options;
}

Eigen::Vector3d Lift0(const AffineDepthPose& m, const Eigen::Vector2d& p, double d) {
  return m.Depth0(d) * Eigen::Vector3d(p.x() / m.f0, p.y() / m.f0, 1.0);
}
Eigen::Vector3d Lift1(const AffineDepthPose& m, const Eigen::Vector2d& p, double d) {
  return m.Depth1(d) * Eigen::Vector3d(p.x() / m.f1, p.y() / m.f1, 1.0);
}

// Finite, f0 == f1 > 0, scale > 0, no shifts, a rotation, positive corrected depths of the sample.
bool IsValidModel(const AffineDepthPose& m, const std::vector<double>& d0, const std::vector<double>& d1) {
  if (!m.R.allFinite() || !m.t.allFinite() || !std::isfinite(m.scale) || !std::isfinite(m.f0) || !std::isfinite(m.f1)) {
    return false;
  }
  if (!(m.f0 > 0.0) || m.f0 != m.f1 || !(m.scale > 0.0) || m.shift0 != 0.0 || m.shift1 != 0.0) return false;
  if ((m.R.transpose() * m.R - Eigen::Matrix3d::Identity()).norm() > 1e-9 || std::abs(m.R.determinant() - 1.0) > 1e-9) {
    return false;
  }
  for (int i = 0; i < 3; ++i) {
    if (!(m.Depth0(d0[i]) > 0.0) || !(m.Depth1(d1[i]) > 0.0)) return false;
  }
  return true;
}

// Largest relative violation of the 2 enforced distance equations (pairs (0,1) and (1,2)).
double MaxEnforcedResidual(const AffineDepthPose& m, const SolverInstance& inst) {
  const int pairs[2][2] = {{0, 1}, {1, 2}};
  double worst = 0.0;
  for (const auto& pr : pairs) {
    const int j = pr[0], k = pr[1];
    const double l0 = (Lift0(m, inst.x0[j], inst.d0[j]) - Lift0(m, inst.x0[k], inst.d0[k])).norm();
    const double l1 = (Lift1(m, inst.x1[j], inst.d1[j]) - Lift1(m, inst.x1[k], inst.d1[k])).norm();
    worst = std::max(worst, std::abs(l0 - l1) / std::max(l0, l1));
  }
  return worst;
}

using testing::Median;

TEST(RelposeScaleDepthSharedFocal3pt, RecoversGroundTruthOnNoiseFreeInstances) {
  std::mt19937 rng(20240602);
  const int kInstances = 1000;
  int found = 0, total_solutions = 0, max_solutions = 0, invalid = 0, unsatisfied = 0;
  std::vector<AffineDepthPose> models;
  for (int n = 0; n < kInstances; ++n) {
    const SolverInstance inst = MakeSolverInstance(rng, ScaleOnlySharedFocalOptions());
    const int num = SolveRelposeScaleDepthSharedFocal3pt(inst.x0, inst.x1, inst.d0, inst.d1, &models);
    ASSERT_EQ(num, static_cast<int>(models.size()));
    ASSERT_LE(num, kMaxSolutions);
    total_solutions += num;
    max_solutions = std::max(max_solutions, num);
    for (const AffineDepthPose& m : models) {
      if (!IsValidModel(m, inst.d0, inst.d1)) ++invalid;
      if (!(MaxEnforcedResidual(m, inst) < 1e-6)) ++unsatisfied;
    }
    if (MinModelError(models, inst) < 1e-6) ++found;
  }
  const double rate = static_cast<double>(found) / kInstances;
  std::printf(
      "[scale-only shared-focal 3pt] ground truth found (error < 1e-6) in %d / %d = %.1f%% of noise-free "
      "instances; %.2f solutions on average, at most %d\n",
      found, kInstances, 100.0 * rate, static_cast<double>(total_solutions) / kInstances, max_solutions);
  EXPECT_GE(rate, 0.99);
  EXPECT_EQ(invalid, 0);
  EXPECT_EQ(unsatisfied, 0);
}

TEST(RelposeScaleDepthSharedFocal3pt, DegenerateInputsGiveNoNaNAndNoInvalidModels) {
  std::mt19937 rng(6);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const SolverInstance base = MakeSolverInstance(rng, ScaleOnlySharedFocalOptions());
  struct Case {
    const char* name;
    std::vector<Eigen::Vector2d> x0, x1;
    std::vector<double> d0, d1;
  };
  std::vector<Case> cases;
  auto add = [&](const char* name) -> Case& {
    cases.push_back({name, base.x0, base.x1, base.d0, base.d1});
    return cases.back();
  };
  {
    Case& c = add("two coincident points");
    c.x0[1] = c.x0[0];
    c.x1[1] = c.x1[0];
    c.d0[1] = c.d0[0];
    c.d1[1] = c.d1[0];
  }
  {
    Case& c = add("all points coincident");
    for (int i = 1; i < 3; ++i) {
      c.x0[i] = c.x0[0];
      c.x1[i] = c.x1[0];
      c.d0[i] = c.d0[0];
      c.d1[i] = c.d1[0];
    }
  }
  {
    Case& c = add("collinear image points");
    for (int i = 0; i < 3; ++i) {
      c.x0[i] = Eigen::Vector2d(100.0 * i - 150.0, 30.0 * i);
      c.x1[i] = Eigen::Vector2d(90.0 * i - 120.0, 25.0 * i + 5.0);
    }
  }
  {
    Case& c = add("collinear 3-D points");
    const AffineDepthPose& gt = base.gt;
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d X0 = Eigen::Vector3d(-0.3, -0.1, 4.0) + i * Eigen::Vector3d(0.2, 0.05, 0.5);
      const Eigen::Vector3d X1 = gt.R * X0 + gt.t;
      c.x0[i] = X0.hnormalized() * gt.f0;
      c.x1[i] = X1.hnormalized() * gt.f1;
      c.d0[i] = X0.z();
      c.d1[i] = X1.z() / gt.scale;
    }
  }
  {
    Case& c = add("equal depths in both views");
    c.d0 = {2.0, 2.0, 2.0};
    c.d1 = {3.0, 3.0, 3.0};
  }
  add("zero depth").d0[2] = 0.0;
  add("all depths zero").d1 = {0.0, 0.0, 0.0};
  add("negative depth").d1[1] = -base.d1[1];
  add("NaN depth").d0[1] = nan;
  add("infinite depth").d1[0] = inf;
  add("NaN coordinate").x1[2].x() = nan;
  add("infinite coordinate").x0[0].y() = inf;
  {
    Case& c = add("all pixels at the principal point");
    for (int i = 0; i < 3; ++i) c.x0[i] = c.x1[i] = Eigen::Vector2d::Zero();
  }
  {
    Case& c = add("two points");
    c.x0.pop_back();
    c.x1.pop_back();
    c.d0.pop_back();
    c.d1.pop_back();
  }
  {
    Case& c = add("no points");
    c.x0.clear();
    c.x1.clear();
    c.d0.clear();
    c.d1.clear();
  }
  add("mismatched sizes").x1.resize(1);
  {
    Case& c = add("identical views");
    c.x1 = c.x0;
    c.d1 = c.d0;
  }

  for (const Case& c : cases) {
    std::vector<AffineDepthPose> models(3);  // must be cleared by the solver
    const int num = SolveRelposeScaleDepthSharedFocal3pt(c.x0, c.x1, c.d0, c.d1, &models);
    EXPECT_EQ(num, static_cast<int>(models.size())) << c.name;
    EXPECT_LE(num, kMaxSolutions) << c.name;
    for (const AffineDepthPose& m : models) EXPECT_TRUE(IsValidModel(m, c.d0, c.d1)) << c.name;
    std::printf("[scale-only shared-focal 3pt] degenerate case '%s': %d solutions\n", c.name, num);
  }
}

// Random inputs without any geometric consistency, over many orders of magnitude, including negative
// priors: the solver may return anything from 0 to the maximum number of solutions, but only valid ones.
TEST(RelposeScaleDepthSharedFocal3pt, RandomInputsGiveOnlyValidModels) {
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const int kTrials = 20000;
  int with_solutions = 0, invalid = 0, too_many = 0;
  std::vector<AffineDepthPose> models;
  for (int n = 0; n < kTrials; ++n) {
    const double pixel_scale = std::pow(10.0, 4.0 * unit(rng));  // 1e-4 .. 1e4
    const double depth_scale = std::pow(10.0, 3.0 * unit(rng));
    const double depth_offset = n % 2 == 0 ? 1.2 : 0.3;  // odd trials: some priors are negative
    std::vector<Eigen::Vector2d> x0(3), x1(3);
    std::vector<double> d0(3), d1(3);
    for (int i = 0; i < 3; ++i) {
      x0[i] = pixel_scale * Eigen::Vector2d(unit(rng), unit(rng));
      x1[i] = pixel_scale * Eigen::Vector2d(unit(rng), unit(rng));
      d0[i] = depth_scale * (depth_offset + unit(rng));
      d1[i] = depth_scale * (depth_offset + unit(rng));
    }
    const int num = SolveRelposeScaleDepthSharedFocal3pt(x0, x1, d0, d1, &models);
    if (num > kMaxSolutions || num != static_cast<int>(models.size())) ++too_many;
    if (num > 0) ++with_solutions;
    for (const AffineDepthPose& m : models) {
      if (!IsValidModel(m, d0, d1)) ++invalid;
    }
  }
  std::printf("[scale-only shared-focal 3pt] random inputs: %d / %d trials with solutions, %d invalid models\n",
              with_solutions, kTrials, invalid);
  EXPECT_EQ(too_many, 0);
  EXPECT_EQ(invalid, 0);
}

TEST(RelposeScaleDepthSharedFocal3pt, SwappingTheViewsGivesTheSwappedSolutions) {
  std::mt19937 rng(78);
  const int kInstances = 200;
  int consistent = 0;
  std::vector<AffineDepthPose> models, swapped;
  for (int n = 0; n < kInstances; ++n) {
    const SolverInstance inst = MakeSolverInstance(rng, ScaleOnlySharedFocalOptions());
    SolveRelposeScaleDepthSharedFocal3pt(inst.x0, inst.x1, inst.d0, inst.d1, &models);
    SolveRelposeScaleDepthSharedFocal3pt(inst.x1, inst.x0, inst.d1, inst.d0, &swapped);
    bool ok = models.size() == swapped.size() && !models.empty();
    // (R, t, scale, f) must appear as (R^T, -R^T t / scale, 1 / scale, f) for the swapped problem.
    for (const AffineDepthPose& m : models) {
      const Eigen::Matrix3d R = m.R.transpose();
      const Eigen::Vector3d t = -m.R.transpose() * m.t / m.scale;
      bool matched = false;
      for (const AffineDepthPose& s : swapped) {
        const double err = std::max({(s.R - R).norm(), (s.t - t).norm() / std::max(t.norm(), 1e-12),
                                     std::abs(s.scale * m.scale - 1.0), std::abs(s.f0 / m.f0 - 1.0)});
        if (err < 1e-8) matched = true;
      }
      ok = ok && matched;
    }
    if (ok) ++consistent;
  }
  std::printf("[scale-only shared-focal 3pt] swapped views give the swapped solution set in %d / %d instances\n",
              consistent, kInstances);
  EXPECT_GE(consistent, kInstances * 99 / 100);
}

// Same setting and reasoning as the 4pt test: 0.5 px is 2.5e-3 .. 1.7e-4 rad per point; with 3 points and
// an unknown focal length the pose error is an amplified multiple of that, driven by the focal error.
// The bounds (median rotation error < 1 deg, median focal error < 10%) are far from a broken solver.
TEST(RelposeScaleDepthSharedFocal3pt, PixelNoiseGivesSmallErrors) {
  std::mt19937 rng(4243);
  const int kInstances = 1000;
  std::vector<double> rot_err, focal_err;
  int no_solution = 0;
  std::vector<AffineDepthPose> models;
  for (int n = 0; n < kInstances; ++n) {
    const SolverInstance inst = MakeSolverInstance(rng, ScaleOnlySharedFocalOptions(0.5));
    SolveRelposeScaleDepthSharedFocal3pt(inst.x0, inst.x1, inst.d0, inst.d1, &models);
    if (models.empty()) {
      ++no_solution;
      rot_err.push_back(std::numeric_limits<double>::infinity());
      focal_err.push_back(std::numeric_limits<double>::infinity());
      continue;
    }
    const AffineDepthPose* best = &models[0];
    for (const AffineDepthPose& m : models) {
      if (ModelError(m, inst) < ModelError(*best, inst)) best = &m;
    }
    rot_err.push_back(RotationErrorDeg(best->R, inst.gt.R));
    focal_err.push_back(std::abs(best->f0 / inst.gt.f0 - 1.0));
  }
  const double med_rot = Median(rot_err), med_focal = Median(focal_err);
  std::printf(
      "[scale-only shared-focal 3pt] 0.5 px noise, %d instances: median rotation error %.4f deg, median "
      "relative focal error %.4f, no solution in %d\n",
      kInstances, med_rot, med_focal, no_solution);
  EXPECT_LT(med_rot, 1.0);
  EXPECT_LT(med_focal, 0.1);
}

}  // namespace
}  // namespace madsfm
