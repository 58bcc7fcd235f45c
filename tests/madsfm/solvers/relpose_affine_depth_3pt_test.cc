#include "madsfm/solvers/relpose_affine_depth_3pt.h"

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

constexpr int kMaxSolutions = 4;

using testing::Median;

// Largest relative residual of scale (d1 + shift1) [x1;1] = R (d0 + shift0) [x0;1] + t over the sample.
double SampleResidual(const AffineDepthPose& m, const std::vector<Eigen::Vector2d>& x0,
                      const std::vector<Eigen::Vector2d>& x1, const std::vector<double>& d0,
                      const std::vector<double>& d1) {
  double worst = 0.0;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d P0 = m.Depth0(d0[i]) * x0[i].homogeneous();
    const Eigen::Vector3d P1 = m.Depth1(d1[i]) * x1[i].homogeneous();
    worst = std::max(worst, (P1 - (m.R * P0 + m.t)).norm() / P1.norm());
  }
  return worst;
}

// Every returned model must be finite, proper and consistent with the sample's depth priors.
void ExpectValidModels(const std::vector<AffineDepthPose>& models, const std::vector<double>& d0,
                       const std::vector<double>& d1) {
  for (const AffineDepthPose& m : models) {
    ASSERT_TRUE(m.R.allFinite() && m.t.allFinite());
    ASSERT_TRUE(std::isfinite(m.scale) && std::isfinite(m.shift0) && std::isfinite(m.shift1));
    EXPECT_GT(m.scale, 0.0);
    EXPECT_EQ(m.f0, 1.0);
    EXPECT_EQ(m.f1, 1.0);
    EXPECT_NEAR((m.R.transpose() * m.R - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-9);
    EXPECT_NEAR(m.R.determinant(), 1.0, 1e-9);
    for (int i = 0; i < 3; ++i) {
      EXPECT_GT(m.Depth0(d0[i]), 0.0);
      EXPECT_GT(m.Depth1(d1[i]), 0.0);
    }
  }
}

// Relative difference of two models of the same problem (rotation, translation relative to |t_ref|,
// scale ratio, shifts relative to the view's mean prior).
double ModelDistance(const AffineDepthPose& a, const AffineDepthPose& ref, double depth_unit0, double depth_unit1) {
  double e = (a.R - ref.R).norm();
  e = std::max(e, (a.t - ref.t).norm() / std::max(ref.t.norm(), 1e-12));
  e = std::max(e, std::abs(a.scale / ref.scale - 1.0));
  e = std::max(e, std::abs(a.shift0 - ref.shift0) / depth_unit0);
  e = std::max(e, std::abs(a.shift1 - ref.shift1) / depth_unit1);
  return std::isfinite(e) ? e : std::numeric_limits<double>::infinity();
}

void RunNoiseFree(bool with_shift, unsigned seed) {
  std::mt19937 rng(seed);
  SolverInstanceOptions opt;
  opt.setup = CameraSetup::kCalibrated;
  opt.num_points = 3;
  opt.with_shift = with_shift;
  const int kTrials = 1000;
  int found = 0, max_num = 0, total = 0, consistent = 0;
  double worst_residual = 0.0;
  std::vector<AffineDepthPose> models;
  for (int trial = 0; trial < kTrials; ++trial) {
    const SolverInstance inst = MakeSolverInstance(rng, opt);
    const int n = SolveRelposeAffineDepth3pt(inst.x0, inst.x1, inst.d0, inst.d1, &models);
    ASSERT_EQ(n, static_cast<int>(models.size()));
    ASSERT_LE(n, kMaxSolutions);
    max_num = std::max(max_num, n);
    total += n;
    ExpectValidModels(models, inst.d0, inst.d1);
    bool all_ok = true;
    for (const AffineDepthPose& m : models) {
      const double r = SampleResidual(m, inst.x0, inst.x1, inst.d0, inst.d1);
      worst_residual = std::max(worst_residual, r);
      all_ok = all_ok && r < 1e-6;
    }
    consistent += all_ok;
    if (MinModelError(models, inst) < 1e-6) ++found;
  }
  const double rate = static_cast<double>(found) / kTrials;
  std::printf(
      "[calibrated 3pt, shift=%d] ground truth among the solutions (error < 1e-6) in %d / %d = %.1f%%; "
      "mean #solutions %.2f, max %d; every model satisfies the sample (rel. residual < 1e-6) in %d / %d, "
      "worst residual %.2e\n",
      with_shift, found, kTrials, 100.0 * rate, static_cast<double>(total) / kTrials, max_num, consistent, kTrials,
      worst_residual);
  EXPECT_GE(rate, 0.99);
  // Each returned model is an exact solution of the sample (the solver keeps nothing else).
  EXPECT_EQ(consistent, kTrials);
}

TEST(RelposeAffineDepth3pt, RecoversGroundTruthWithShifts) { RunNoiseFree(/*with_shift=*/true, 11); }

TEST(RelposeAffineDepth3pt, RecoversGroundTruthWithoutShifts) { RunNoiseFree(/*with_shift=*/false, 12); }

TEST(RelposeAffineDepth3pt, SwappingTheViewsGivesTheSwappedSolutions) {
  std::mt19937 rng(13);
  SolverInstanceOptions opt;
  opt.num_points = 3;
  const int kTrials = 1000;
  int consistent = 0;
  std::vector<AffineDepthPose> models, swapped;
  for (int trial = 0; trial < kTrials; ++trial) {
    const SolverInstance inst = MakeSolverInstance(rng, opt);
    SolveRelposeAffineDepth3pt(inst.x0, inst.x1, inst.d0, inst.d1, &models);
    SolveRelposeAffineDepth3pt(inst.x1, inst.x0, inst.d1, inst.d0, &swapped);
    ExpectValidModels(swapped, inst.d1, inst.d0);
    const double u0 = MeanAbs(inst.d0.data(), 3), u1 = MeanAbs(inst.d1.data(), 3);
    bool ok = models.size() == swapped.size();
    for (const AffineDepthPose& m : models) {
      double best = std::numeric_limits<double>::infinity();
      for (const AffineDepthPose& s : swapped) best = std::min(best, ModelDistance(SwapViews(s), m, u0, u1));
      ok = ok && best < 1e-6;
    }
    consistent += ok;
  }
  std::printf("[calibrated 3pt] swapped views give the swapped solution set in %d / %d instances\n", consistent,
              kTrials);
  EXPECT_GE(consistent, kTrials * 99 / 100);
}

TEST(RelposeAffineDepth3pt, SwapViewsIsAnInvolutionAndMapsTheEquation) {
  std::mt19937 rng(14);
  SolverInstanceOptions opt;
  for (int trial = 0; trial < 20; ++trial) {
    const SolverInstance inst = MakeSolverInstance(rng, opt);
    const AffineDepthPose s = SwapViews(inst.gt);
    // The swapped ground truth satisfies the swapped problem exactly.
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d P0 = s.Depth0(inst.d1[i]) * inst.x1[i].homogeneous();
      const Eigen::Vector3d P1 = s.Depth1(inst.d0[i]) * inst.x0[i].homogeneous();
      EXPECT_LT((P1 - (s.R * P0 + s.t)).norm(), 1e-9 * P1.norm());
    }
    EXPECT_LT(ModelDistance(SwapViews(s), inst.gt, 1.0, 1.0), 1e-12);
  }
}

TEST(RelposeAffineDepth3pt, DegenerateInputsGiveNoOrValidSolutions) {
  std::mt19937 rng(15);
  SolverInstanceOptions opt;
  const std::vector<Corruption> corruptions = {
      {"too few points", true, [](SolverInstance* in) { in->x0.resize(2); }},
      {"mismatched sizes", true, [](SolverInstance* in) { in->d1.resize(2); }},
      {"coincident points in both views", false,
       [](SolverInstance* in) {
         in->x0[1] = in->x0[0];
         in->d0[1] = in->d0[0];
         in->x1[1] = in->x1[0];
         in->d1[1] = in->d1[0];
       }},
      {"same pixel, other depth", false, [](SolverInstance* in) { in->x0[1] = in->x0[0]; }},
      {"collinear image points", false,
       [](SolverInstance* in) {
         in->x0[2] = 0.3 * in->x0[0] + 0.7 * in->x0[1];
         in->x1[2] = 0.3 * in->x1[0] + 0.7 * in->x1[1];
       }},
      {"zero depth", false, [](SolverInstance* in) { in->d0[0] = 0.0; }},
      {"negative depth", false, [](SolverInstance* in) { in->d1[2] = -in->d1[2]; }},
      {"NaN depth", true, [](SolverInstance* in) { in->d0[1] = kNaN; }},
      {"NaN coordinate", true, [](SolverInstance* in) { in->x1[2].x() = kNaN; }},
      {"infinite depth", true, [](SolverInstance* in) { in->d1[0] = kInf; }},
      {"constant depths in view 0 only", false,
       [](SolverInstance* in) {
         in->d0 = {2.0, 2.0, 2.0};
       }},
      {"constant depths", false,
       [](SolverInstance* in) {
         in->d0 = {2.0, 2.0, 2.0};
         in->d1 = {3.0, 3.0, 3.0};
       }},
      {"all depths zero", false,
       [](SolverInstance* in) {
         in->d0 = {0.0, 0.0, 0.0};
         in->d1 = in->d0;
       }},
      {"all points at the image centre", false,
       [](SolverInstance* in) {
         for (auto& x : in->x0) x.setZero();
         in->x1 = in->x0;
       }},
      {"all priors negative", false,
       [](SolverInstance* in) {
         in->d0 = {-1.0, -2.0, -3.0};
       }},
      {"absurd coordinate", false, [](SolverInstance* in) { in->x0[0] *= 1e12; }},
  };
  std::vector<AffineDepthPose> models;
  int num_cases = 0;
  for (int trial = 0; trial < 100; ++trial) {
    const SolverInstance base = MakeSolverInstance(rng, opt);
    for (const Corruption& c : corruptions) {
      SolverInstance in = base;
      c.apply(&in);
      ++num_cases;
      const int n = SolveRelposeAffineDepth3pt(in.x0, in.x1, in.d0, in.d1, &models);
      ASSERT_EQ(n, static_cast<int>(models.size())) << c.name;
      ASSERT_LE(n, kMaxSolutions) << c.name;
      if (c.must_be_empty) {
        EXPECT_EQ(n, 0) << c.name;
      } else {
        SCOPED_TRACE(c.name);
        ExpectValidModels(models, in.d0, in.d1);
      }
    }
  }
  std::vector<Eigen::Vector2d> empty2;
  std::vector<double> empty1;
  models.resize(3);
  EXPECT_EQ(SolveRelposeAffineDepth3pt(empty2, empty2, empty1, empty1, &models), 0);
  EXPECT_TRUE(models.empty());
  std::printf("[calibrated 3pt] %d degenerate inputs: no NaN, no crash\n", num_cases);
}

TEST(RelposeAffineDepth3pt, HalfPixelNoiseGivesSmallRotationError) {
  std::mt19937 rng(16);
  SolverInstanceOptions opt;
  opt.pixel_noise = 0.5;
  const int kTrials = 1000;
  std::vector<double> errors;
  std::vector<AffineDepthPose> models;
  for (int trial = 0; trial < kTrials; ++trial) {
    const SolverInstance inst = MakeSolverInstance(rng, opt);
    SolveRelposeAffineDepth3pt(inst.x0, inst.x1, inst.d0, inst.d1, &models);
    ASSERT_LE(static_cast<int>(models.size()), kMaxSolutions);
    ExpectValidModels(models, inst.d0, inst.d1);
    double best = 180.0;  // no solution counts as a failure
    for (const AffineDepthPose& m : models) best = std::min(best, RotationErrorDeg(m.R, inst.gt.R));
    errors.push_back(best);
  }
  const double median = Median(errors);
  std::sort(errors.begin(), errors.end());
  std::printf("[calibrated 3pt, 0.5 px noise] rotation error of the best solution: median %.3f deg, 90%% %.3f deg\n",
              median, errors[kTrials * 9 / 10]);
  // 0.5 px on 200-3000 px focal lengths is 0.01-0.14 deg of ray direction. The 3 points span a
  // small part of the field of view and sit at depths m/2..2m, so the lifted triangle is small
  // against the depth; the minimal solver amplifies the ray noise several times (the 90th
  // percentile reaches degrees), but a median above 2 deg would mean a numerical problem.
  EXPECT_LT(median, 2.0);
}

}  // namespace
}  // namespace madsfm
