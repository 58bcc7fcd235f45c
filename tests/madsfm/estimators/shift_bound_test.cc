// HybridEstimatorOptions::max_shift_ratio: no hybrid result has |shift_i| above max_shift_ratio times the median
// prior of view i, whichever part of the search produced its depth parameters (minimal depth solvers, the depth fits
// of point models, local optimisation, the last refinements). The scenes here are noise-free and their true shifts
// are about 9x the median prior: the bounded estimator must not return them, the unbounded one recovers them.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "madsfm/estimators/hybrid_lo_msac.h"
#include "madsfm/geometry/pose_error.h"
#include "testing/median.h"

namespace madsfm {
namespace {

struct ShallowScene {
  RelposeProblem problem;
  AffineDepthPose truth;
};

// A calibrated, noise-free pair of a shallow scene (view-0 depths 10-11) whose priors are the true depths minus
// 9.5 (view 0) and minus 9 (view 1): the priors are exactly affine, with shifts of ~9x their medians.
ShallowScene MakeShallowScene(std::mt19937& rng, int num_points) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  ShallowScene s;
  AffineDepthPose& g = s.truth;
  g.R = Eigen::AngleAxisd(0.15 * u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized()).toRotationMatrix();
  g.t = Eigen::Vector3d(1.0 + 0.3 * u(rng), 0.3 * u(rng), 0.2 * u(rng));
  g.scale = 1.0;
  g.shift0 = 9.5;
  g.shift1 = 9.0;
  RelposeProblem& p = s.problem;
  p.mode = CameraMode::kCalibrated;
  p.pixel_scale0 = p.pixel_scale1 = 500.0;
  while (p.size() < num_points) {
    const double z0 = 10.5 + 0.5 * u(rng);
    const Eigen::Vector3d X(0.4 * u(rng) * z0, 0.3 * u(rng) * z0, z0);
    const Eigen::Vector3d Y = g.R * X + g.t;
    if (!(Y.z() > g.shift1 + 0.2)) continue;
    const Eigen::Vector2d x1 = Y.head<2>() / Y.z();
    if (std::abs(x1.x()) > 0.6 || std::abs(x1.y()) > 0.45) continue;
    p.x0.push_back(X.head<2>() / X.z());
    p.x1.push_back(x1);
    p.d0.push_back(z0 - g.shift0);
    p.d1.push_back(Y.z() / g.scale - g.shift1);
  }
  p.IndexDepths();
  return s;
}

TEST(ShiftBound, NoResultOutsideTheBound) {
  std::mt19937 rng(41);
  const int kTrials = 10;
  int successes = 0, pose_within_1deg = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    const ShallowScene s = MakeShallowScene(rng, 120);
    const double m0 = testing::Median(s.problem.d0), m1 = testing::Median(s.problem.d1);  // as the estimator
    ASSERT_GT(s.truth.shift0, 5.0 * m0);  // the truth is out of the default bound
    HybridEstimatorOptions o;
    o.seed = trial;
    const HybridEstimate est = EstimateHybridRelpose(s.problem, o);
    if (!est.success) continue;
    ++successes;
    EXPECT_LE(std::abs(est.model.shift0), o.max_shift_ratio * m0) << "trial " << trial;
    EXPECT_LE(std::abs(est.model.shift1), o.max_shift_ratio * m1) << "trial " << trial;
    pose_within_1deg += RotationErrorDeg(est.model.R, s.truth.R) < 1.0 &&
                        TranslationErrorDeg(est.model.t, s.truth.t) < 1.0;
  }
  std::printf("shift bound: %d/%d runs succeeded, %d with the pose within 1 deg\n", successes, kTrials,
              pose_within_1deg);
  // The epipolar evidence is exact: the pose survives the bound.
  EXPECT_EQ(successes, kTrials);
  EXPECT_GE(pose_within_1deg, kTrials * 8 / 10);
}

TEST(ShiftBound, WithoutTheBoundTheTrueShiftsAreRecovered) {
  std::mt19937 rng(41);
  const int kTrials = 10;
  int recovered = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    const ShallowScene s = MakeShallowScene(rng, 120);
    HybridEstimatorOptions o;
    o.seed = trial;
    o.max_shift_ratio = 0.0;
    const HybridEstimate est = EstimateHybridRelpose(s.problem, o);
    recovered += est.success && std::abs(est.model.shift0 - s.truth.shift0) < 1e-6 &&
                 std::abs(est.model.shift1 - s.truth.shift1) < 1e-6 &&
                 RotationErrorDeg(est.model.R, s.truth.R) < 1e-6;
  }
  std::printf("unbounded: true shifts recovered in %d/%d\n", recovered, kTrials);
  EXPECT_GE(recovered, kTrials * 9 / 10);
}

}  // namespace
}  // namespace madsfm
