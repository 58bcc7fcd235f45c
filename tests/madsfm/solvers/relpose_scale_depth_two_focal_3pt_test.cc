#include "madsfm/solvers/relpose_scale_depth_two_focal_3pt.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <limits>
#include <random>
#include <vector>

#include "madsfm/geometry/pose_error.h"
#include "madsfm/solvers/affine_depth_solver_utils.h"
#include "testing/solver_corruptions.h"
#include "testing/solver_instances.h"
#include "testing/median.h"

namespace madsfm {
namespace {

using testing::CameraSetup;
using testing::MakeSolverInstance;
using testing::MinModelError;
using testing::SolverInstance;
using testing::SolverInstanceOptions;

using testing::Corruption;
using testing::kInf;
using testing::kNaN;

SolverInstanceOptions ScaleOnlyTwoFocalOptions() {
  SolverInstanceOptions opt;
  opt.setup = CameraSetup::kTwoFocal;
  opt.num_points = 3;
  opt.with_shift = false;
  return opt;
}

using testing::Median;

// Largest relative residual of scale d1 K1^-1 [p1;1] = R d0 K0^-1 [p0;1] + t over the sample.
double SampleResidual(const AffineDepthPose& m, const SolverInstance& in) {
  double worst = 0.0;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d P0 = m.Depth0(in.d0[i]) * Eigen::Vector3d(in.x0[i].x() / m.f0, in.x0[i].y() / m.f0, 1.0);
    const Eigen::Vector3d P1 = m.Depth1(in.d1[i]) * Eigen::Vector3d(in.x1[i].x() / m.f1, in.x1[i].y() / m.f1, 1.0);
    worst = std::max(worst, (P1 - (m.R * P0 + m.t)).norm() / P1.norm());
  }
  return worst;
}

void ExpectValidModels(const std::vector<AffineDepthPose>& models, const std::vector<double>& d0,
                       const std::vector<double>& d1) {
  for (const AffineDepthPose& m : models) {
    ASSERT_TRUE(m.R.allFinite() && m.t.allFinite() && std::isfinite(m.scale));
    ASSERT_TRUE(std::isfinite(m.f0) && std::isfinite(m.f1));
    EXPECT_GT(m.scale, 0.0);
    EXPECT_GT(m.f0, 0.0);
    EXPECT_GT(m.f1, 0.0);
    EXPECT_EQ(m.shift0, 0.0);
    EXPECT_EQ(m.shift1, 0.0);
    EXPECT_NEAR((m.R.transpose() * m.R - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-9);
    EXPECT_NEAR(m.R.determinant(), 1.0, 1e-9);
    for (int i = 0; i < 3; ++i) {
      EXPECT_GT(m.Depth0(d0[i]), 0.0);
      EXPECT_GT(m.Depth1(d1[i]), 0.0);
    }
  }
}

TEST(RelposeScaleDepthTwoFocal3pt, RecoversGroundTruth) {
  std::mt19937 rng(41);
  const SolverInstanceOptions opt = ScaleOnlyTwoFocalOptions();
  const int kTrials = 1000;
  int found = 0, consistent = 0, num_models = 0;
  double worst_residual = 0.0;
  std::vector<AffineDepthPose> models;
  for (int trial = 0; trial < kTrials; ++trial) {
    const SolverInstance inst = MakeSolverInstance(rng, opt);
    const int n = SolveRelposeScaleDepthTwoFocal3pt(inst.x0, inst.x1, inst.d0, inst.d1, &models);
    ASSERT_EQ(n, static_cast<int>(models.size()));
    ASSERT_LE(n, 1);
    ExpectValidModels(models, inst.d0, inst.d1);
    num_models += n;
    if (n == 1) {
      const double r = SampleResidual(models[0], inst);
      worst_residual = std::max(worst_residual, r);
      consistent += r < 1e-6;
    }
    if (MinModelError(models, inst) < 1e-6) ++found;
  }
  const double rate = static_cast<double>(found) / kTrials;
  std::printf(
      "[scale-only two-focal 3pt] ground truth found (error < 1e-6) in %d / %d = %.1f%%; "
      "sample satisfied (rel. residual < 1e-6) by %d / %d models, worst residual %.2e\n",
      found, kTrials, 100.0 * rate, consistent, num_models, worst_residual);
  EXPECT_GE(rate, 0.99);
  // With the 3 distances equal the sample is fitted exactly.
  EXPECT_EQ(consistent, num_models);
}

TEST(RelposeScaleDepthTwoFocal3pt, SwappingTheViewsGivesTheSwappedSolution) {
  std::mt19937 rng(43);
  const SolverInstanceOptions opt = ScaleOnlyTwoFocalOptions();
  const int kTrials = 1000;
  int consistent = 0;
  std::vector<AffineDepthPose> models, swapped;
  for (int trial = 0; trial < kTrials; ++trial) {
    const SolverInstance inst = MakeSolverInstance(rng, opt);
    SolveRelposeScaleDepthTwoFocal3pt(inst.x0, inst.x1, inst.d0, inst.d1, &models);
    SolveRelposeScaleDepthTwoFocal3pt(inst.x1, inst.x0, inst.d1, inst.d0, &swapped);
    ExpectValidModels(swapped, inst.d1, inst.d0);
    if (models.size() != 1 || swapped.size() != 1) continue;
    const AffineDepthPose back = SwapViews(swapped[0]);
    const AffineDepthPose& m = models[0];
    const double e =
        std::max({(back.R - m.R).norm(), (back.t - m.t).norm() / m.t.norm(), std::abs(back.scale / m.scale - 1.0),
                  std::abs(back.f0 / m.f0 - 1.0), std::abs(back.f1 / m.f1 - 1.0)});
    consistent += e < 1e-6;
  }
  std::printf("[scale-only two-focal 3pt] swapped views give the swapped solution in %d / %d instances\n", consistent,
              kTrials);
  EXPECT_GE(consistent, kTrials * 99 / 100);
}

TEST(RelposeScaleDepthTwoFocal3pt, DegenerateInputsGiveNoOrValidSolutions) {
  std::mt19937 rng(45);
  const SolverInstanceOptions opt = ScaleOnlyTwoFocalOptions();
  const std::vector<Corruption> corruptions = {
      {"too few points", true, [](SolverInstance* in) { in->x0.resize(2); }},
      {"mismatched sizes", true, [](SolverInstance* in) { in->d1.resize(1); }},
      {"coincident points in both views", false,
       [](SolverInstance* in) {
         in->x0[1] = in->x0[0];
         in->d0[1] = in->d0[0];
         in->x1[1] = in->x1[0];
         in->d1[1] = in->d1[0];
       }},
      {"collinear image points", false,
       [](SolverInstance* in) {
         in->x0[2] = 0.3 * in->x0[0] + 0.7 * in->x0[1];
         in->x1[2] = 0.3 * in->x1[0] + 0.7 * in->x1[1];
       }},
      {"zero depth", true, [](SolverInstance* in) { in->d0[0] = 0.0; }},
      {"negative depth", true, [](SolverInstance* in) { in->d1[2] = -in->d1[2]; }},
      {"NaN depth", true, [](SolverInstance* in) { in->d0[1] = kNaN; }},
      {"NaN coordinate", true, [](SolverInstance* in) { in->x1[2].x() = kNaN; }},
      {"all points at the principal point", false,
       [](SolverInstance* in) {
         for (auto& x : in->x0) x.setZero();
       }},
      {"constant depths", false,
       [](SolverInstance* in) {
         in->d0 = {2.0, 2.0, 2.0};
         in->d1 = {3.0, 3.0, 3.0};
       }},
      {"absurd coordinate", false, [](SolverInstance* in) { in->x0[0] *= 1e12; }},
      {"identical views", false,
       [](SolverInstance* in) {
         in->x0 = in->x1;
         in->d0 = in->d1;
       }},
      {"tiny depths", false,
       [](SolverInstance* in) {
         in->d1 = {1e-300, 1e-300, 1e-300};
       }},
  };
  std::vector<AffineDepthPose> models;
  int num_cases = 0;
  for (int trial = 0; trial < 100; ++trial) {
    const SolverInstance base = MakeSolverInstance(rng, opt);
    for (const Corruption& c : corruptions) {
      SolverInstance in = base;
      c.apply(&in);
      ++num_cases;
      const int n = SolveRelposeScaleDepthTwoFocal3pt(in.x0, in.x1, in.d0, in.d1, &models);
      ASSERT_EQ(n, static_cast<int>(models.size())) << c.name;
      ASSERT_LE(n, 1) << c.name;
      if (c.must_be_empty) {
        EXPECT_EQ(n, 0) << c.name;
      } else {
        SCOPED_TRACE(c.name);
        ExpectValidModels(models, in.d0, in.d1);
      }
    }
  }
  models.resize(1);
  EXPECT_EQ(SolveRelposeScaleDepthTwoFocal3pt({}, {}, {}, {}, &models), 0);
  EXPECT_TRUE(models.empty());
  std::printf("[scale-only two-focal 3pt] %d degenerate inputs: no NaN, no crash\n", num_cases);
}

TEST(RelposeScaleDepthTwoFocal3pt, HalfPixelNoiseGivesSmallRotationError) {
  std::mt19937 rng(46);
  SolverInstanceOptions opt = ScaleOnlyTwoFocalOptions();
  opt.pixel_noise = 0.5;
  const int kTrials = 1000;
  std::vector<double> errors;
  std::vector<AffineDepthPose> models;
  for (int trial = 0; trial < kTrials; ++trial) {
    const SolverInstance inst = MakeSolverInstance(rng, opt);
    SolveRelposeScaleDepthTwoFocal3pt(inst.x0, inst.x1, inst.d0, inst.d1, &models);
    ExpectValidModels(models, inst.d0, inst.d1);
    errors.push_back(models.empty() ? 180.0 : RotationErrorDeg(models[0].R, inst.gt.R));
  }
  const double median = Median(errors);
  std::sort(errors.begin(), errors.end());
  std::printf("[scale-only two-focal 3pt, 0.5 px noise] rotation error: median %.3f deg, 90%% %.3f deg\n", median,
              errors[kTrials * 9 / 10]);
  // As for the two-focal 4pt solver: the focal lengths come from the same noisy pixels. 2 deg bound.
  EXPECT_LT(median, 2.0);
}

}  // namespace
}  // namespace madsfm
