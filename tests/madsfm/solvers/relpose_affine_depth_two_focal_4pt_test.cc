#include "madsfm/solvers/relpose_affine_depth_two_focal_4pt.h"

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

constexpr int kMaxSolutions = 4;

SolverInstanceOptions TwoFocalOptions() {
  SolverInstanceOptions opt;
  opt.setup = CameraSetup::kTwoFocal;
  opt.num_points = 4;
  return opt;
}

using testing::Median;

Eigen::Vector3d Lift(const Eigen::Vector2d& p, double f, double depth) {
  return depth * Eigen::Vector3d(p.x() / f, p.y() / f, 1.0);
}

// How many of the 6 pairwise distance equations the model satisfies to `tol` (relative).
int NumDistanceEquationsHeld(const AffineDepthPose& m, const SolverInstance& in, double tol) {
  Eigen::Vector3d P0[4], P1[4];
  for (int i = 0; i < 4; ++i) {
    P0[i] = Lift(in.x0[i], m.f0, m.Depth0(in.d0[i]));
    P1[i] = Lift(in.x1[i], m.f1, m.Depth1(in.d1[i]));
  }
  int held = 0;
  for (int j = 0; j < 4; ++j) {
    for (int k = j + 1; k < 4; ++k) {
      const double a = (P0[j] - P0[k]).squaredNorm(), b = (P1[j] - P1[k]).squaredNorm();
      held += std::abs(a - b) <= tol * std::max(a, b);
    }
  }
  return held;
}

void ExpectValidModels(const std::vector<AffineDepthPose>& models, const std::vector<double>& d0,
                       const std::vector<double>& d1) {
  for (const AffineDepthPose& m : models) {
    ASSERT_TRUE(m.R.allFinite() && m.t.allFinite());
    ASSERT_TRUE(std::isfinite(m.scale) && std::isfinite(m.shift0) && std::isfinite(m.shift1));
    ASSERT_TRUE(std::isfinite(m.f0) && std::isfinite(m.f1));
    EXPECT_GT(m.scale, 0.0);
    EXPECT_GT(m.f0, 0.0);
    EXPECT_GT(m.f1, 0.0);
    EXPECT_NEAR((m.R.transpose() * m.R - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-9);
    EXPECT_NEAR(m.R.determinant(), 1.0, 1e-9);
    for (int i = 0; i < 4; ++i) {
      EXPECT_GT(m.Depth0(d0[i]), 0.0);
      EXPECT_GT(m.Depth1(d1[i]), 0.0);
    }
  }
}

double ModelDistance(const AffineDepthPose& a, const AffineDepthPose& ref, double depth_unit0, double depth_unit1) {
  double e = (a.R - ref.R).norm();
  e = std::max(e, (a.t - ref.t).norm() / std::max(ref.t.norm(), 1e-12));
  e = std::max(e, std::abs(a.scale / ref.scale - 1.0));
  e = std::max(e, std::abs(a.shift0 - ref.shift0) / depth_unit0);
  e = std::max(e, std::abs(a.shift1 - ref.shift1) / depth_unit1);
  e = std::max(e, std::abs(a.f0 / ref.f0 - 1.0));
  e = std::max(e, std::abs(a.f1 / ref.f1 - 1.0));
  return std::isfinite(e) ? e : std::numeric_limits<double>::infinity();
}

void RunNoiseFree(bool with_shift, unsigned seed) {
  std::mt19937 rng(seed);
  SolverInstanceOptions opt = TwoFocalOptions();
  opt.with_shift = with_shift;
  const int kTrials = 1000;
  int found = 0, max_num = 0, total = 0, consistent = 0;
  std::vector<AffineDepthPose> models;
  for (int trial = 0; trial < kTrials; ++trial) {
    const SolverInstance inst = MakeSolverInstance(rng, opt);
    const int n = SolveRelposeAffineDepthTwoFocal4pt(inst.x0, inst.x1, inst.d0, inst.d1, &models);
    ASSERT_EQ(n, static_cast<int>(models.size()));
    ASSERT_LE(n, kMaxSolutions);
    max_num = std::max(max_num, n);
    total += n;
    ExpectValidModels(models, inst.d0, inst.d1);
    bool all_ok = true;
    for (const AffineDepthPose& m : models) all_ok = all_ok && NumDistanceEquationsHeld(m, inst, 1e-6) >= 5;
    consistent += all_ok;
    if (MinModelError(models, inst) < 1e-6) ++found;
  }
  const double rate = static_cast<double>(found) / kTrials;
  std::printf(
      "[two-focal 4pt, shift=%d] ground truth among the solutions (error < 1e-6) in %d / %d = %.1f%%; "
      "mean #solutions %.2f, max %d; every model satisfies >= 5 of the 6 distance equations "
      "(rel. 1e-6) in %d / %d\n",
      with_shift, found, kTrials, 100.0 * rate, static_cast<double>(total) / kTrials, max_num, consistent, kTrials);
  EXPECT_GE(rate, 0.99);
  // Every returned model solves the 5 equations the solver uses.
  EXPECT_EQ(consistent, kTrials);
}

TEST(RelposeAffineDepthTwoFocal4pt, RecoversGroundTruthWithShifts) { RunNoiseFree(/*with_shift=*/true, 31); }

TEST(RelposeAffineDepthTwoFocal4pt, RecoversGroundTruthWithoutShifts) { RunNoiseFree(/*with_shift=*/false, 32); }

TEST(RelposeAffineDepthTwoFocal4pt, SwappingTheViewsGivesTheSwappedSolutions) {
  std::mt19937 rng(33);
  const SolverInstanceOptions opt = TwoFocalOptions();
  const int kTrials = 1000;
  int consistent = 0;
  std::vector<AffineDepthPose> models, swapped;
  for (int trial = 0; trial < kTrials; ++trial) {
    const SolverInstance inst = MakeSolverInstance(rng, opt);
    SolveRelposeAffineDepthTwoFocal4pt(inst.x0, inst.x1, inst.d0, inst.d1, &models);
    SolveRelposeAffineDepthTwoFocal4pt(inst.x1, inst.x0, inst.d1, inst.d0, &swapped);
    ExpectValidModels(swapped, inst.d1, inst.d0);
    const double u0 = MeanAbs(inst.d0.data(), 4), u1 = MeanAbs(inst.d1.data(), 4);
    bool ok = models.size() == swapped.size();
    for (const AffineDepthPose& m : models) {
      double best = std::numeric_limits<double>::infinity();
      for (const AffineDepthPose& s : swapped) best = std::min(best, ModelDistance(SwapViews(s), m, u0, u1));
      ok = ok && best < 1e-6;
    }
    consistent += ok;
  }
  std::printf("[two-focal 4pt] swapped views give the swapped solution set in %d / %d instances\n", consistent,
              kTrials);
  EXPECT_GE(consistent, kTrials * 99 / 100);
}

TEST(RelposeAffineDepthTwoFocal4pt, DegenerateInputsGiveNoOrValidSolutions) {
  std::mt19937 rng(35);
  const SolverInstanceOptions opt = TwoFocalOptions();
  const std::vector<Corruption> corruptions = {
      {"too few points", true, [](SolverInstance* in) { in->x1.resize(3); }},
      {"mismatched sizes", true, [](SolverInstance* in) { in->d0.resize(3); }},
      {"coincident points in both views", false,
       [](SolverInstance* in) {
         in->x0[1] = in->x0[0];
         in->d0[1] = in->d0[0];
         in->x1[1] = in->x1[0];
         in->d1[1] = in->d1[0];
       }},
      {"same pixel, other depth", false, [](SolverInstance* in) { in->x1[3] = in->x1[2]; }},
      {"collinear image points", false,
       [](SolverInstance* in) {
         for (auto* x : {&in->x0, &in->x1}) {
           (*x)[2] = 0.3 * (*x)[0] + 0.7 * (*x)[1];
           (*x)[3] = -0.5 * (*x)[0] + 1.5 * (*x)[1];
         }
       }},
      {"zero depth", false, [](SolverInstance* in) { in->d0[3] = 0.0; }},
      {"negative depth", false, [](SolverInstance* in) { in->d1[2] = -in->d1[2]; }},
      {"NaN depth", true, [](SolverInstance* in) { in->d0[1] = kNaN; }},
      {"NaN coordinate", true, [](SolverInstance* in) { in->x1[3].y() = kNaN; }},
      {"infinite coordinate", true, [](SolverInstance* in) { in->x0[0].x() = kInf; }},
      {"constant depths in view 0 only", false,
       [](SolverInstance* in) {
         in->d0 = {2.0, 2.0, 2.0, 2.0};
       }},
      {"constant depths", false,
       [](SolverInstance* in) {
         in->d0 = {2.0, 2.0, 2.0, 2.0};
         in->d1 = {3.0, 3.0, 3.0, 3.0};
       }},
      {"all depths zero", false,
       [](SolverInstance* in) {
         in->d0 = {0.0, 0.0, 0.0, 0.0};
         in->d1 = in->d0;
       }},
      {"all points at the principal point", false,
       [](SolverInstance* in) {
         for (auto& x : in->x0) x.setZero();
       }},
      {"all priors negative", false,
       [](SolverInstance* in) {
         in->d1 = {-1.0, -2.0, -3.0, -4.0};
       }},
      {"absurd coordinate", false, [](SolverInstance* in) { in->x0[0] *= 1e12; }},
      {"identical views", false,
       [](SolverInstance* in) {
         in->x0 = in->x1;
         in->d0 = in->d1;
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
      const int n = SolveRelposeAffineDepthTwoFocal4pt(in.x0, in.x1, in.d0, in.d1, &models);
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
  EXPECT_EQ(SolveRelposeAffineDepthTwoFocal4pt(empty2, empty2, empty1, empty1, &models), 0);
  EXPECT_TRUE(models.empty());
  std::printf("[two-focal 4pt] %d degenerate inputs: no NaN, no crash\n", num_cases);
}

TEST(RelposeAffineDepthTwoFocal4pt, HalfPixelNoiseGivesSmallRotationError) {
  std::mt19937 rng(36);
  SolverInstanceOptions opt = TwoFocalOptions();
  opt.pixel_noise = 0.5;
  const int kTrials = 1000;
  std::vector<double> rot_errors, focal_errors;
  std::vector<AffineDepthPose> models;
  for (int trial = 0; trial < kTrials; ++trial) {
    const SolverInstance inst = MakeSolverInstance(rng, opt);
    SolveRelposeAffineDepthTwoFocal4pt(inst.x0, inst.x1, inst.d0, inst.d1, &models);
    ASSERT_LE(static_cast<int>(models.size()), kMaxSolutions);
    ExpectValidModels(models, inst.d0, inst.d1);
    double best = 180.0, best_focal = std::numeric_limits<double>::infinity();  // no solution: failure
    for (const AffineDepthPose& m : models) {
      const double e = RotationErrorDeg(m.R, inst.gt.R);
      if (e < best) {
        best = e;
        best_focal = std::max(std::abs(m.f0 / inst.gt.f0 - 1.0), std::abs(m.f1 / inst.gt.f1 - 1.0));
      }
    }
    rot_errors.push_back(best);
    focal_errors.push_back(best_focal);
  }
  const double median = Median(rot_errors);
  std::sort(rot_errors.begin(), rot_errors.end());
  std::printf(
      "[two-focal 4pt, 0.5 px noise] rotation error of the best solution: median %.3f deg, 90%% %.3f deg; "
      "its relative focal error: median %.4f\n",
      median, rot_errors[kTrials * 9 / 10], Median(focal_errors));
  // 0.5 px on 200-3000 px focal lengths is 0.01-0.14 deg of ray direction; the focal lengths are
  // estimated from the same noisy pixels and scale the lifted points, which amplifies the rotation
  // error more than in the calibrated case. 2 deg is the bound.
  EXPECT_LT(median, 2.0);
}

}  // namespace
}  // namespace madsfm
