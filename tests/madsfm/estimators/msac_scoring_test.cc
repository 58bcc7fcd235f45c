// The MSAC scoring of the estimator's hot path: the counting variant agrees with ScoreModel and ComputeInliers and
// only stops early when neither its score nor its count can win; the cheirality of Sampson data is judged only
// beyond the noise-aware parallax; errors computed against a cap (the search's shortcut) agree with the exact ones
// wherever the cap matters; the one-pass score and inlier selection of the local optimisation equals the two calls.
#include "madsfm/estimators/msac_scoring.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>

#include "testing/problem_from_instance.h"
#include "testing/solver_instances.h"

namespace madsfm {
namespace {

// 200 noisy correspondences of a calibrated instance, the last 60 of them replaced by random matches.
RelposeProblem NoisyProblem(std::mt19937& rng, testing::SolverInstance* inst) {
  testing::SolverInstanceOptions o;
  o.num_points = 200;
  o.pixel_noise = 0.7;
  o.depth_noise = 0.02;
  *inst = testing::MakeSolverInstance(rng, o);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  for (int i = 140; i < 200; ++i) inst->x1[i] = Eigen::Vector2d(u(rng), u(rng));
  return testing::ProblemFromInstance(*inst, testing::CameraSetup::kCalibrated);
}

TEST(ScoreModelCounting, AgreesWithScoreModelAndComputeInliers) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 20; ++trial) {
    testing::SolverInstance inst;
    const RelposeProblem p = NoisyProblem(rng, &inst);
    HybridEstimatorOptions o;
    for (ScoringMode mode : {ScoringMode::kHybrid, ScoringMode::kSampsonOnly}) {
      o.scoring = mode;
      const MsacWeights w = MsacWeights::FromOptions(o);
      InlierSets in;
      ComputeInliers(p, inst.gt, w, &in);
      int count = -1;
      const double s = ScoreModelCounting(p, inst.gt, w, std::numeric_limits<double>::infinity(), 0, &count);
      EXPECT_DOUBLE_EQ(s, ScoreModel(p, inst.gt, w));
      EXPECT_EQ(count, in.Total());
      EXPECT_GT(count, 0);
      // A score bound that is beaten at once but a count that can still be exceeded: no early stop.
      int count2 = -1;
      const double s2 = ScoreModelCounting(p, inst.gt, w, 0.0, count - 1, &count2);
      EXPECT_EQ(count2, count);
      EXPECT_DOUBLE_EQ(s2, s);
      // Neither can win: stops early with a partial count that cannot beat the bound.
      int count3 = -1;
      const double s3 = ScoreModelCounting(p, inst.gt, w, 0.0, 3 * p.size(), &count3);
      EXPECT_GT(s3, 0.0);
      EXPECT_LT(count3, count);
      EXPECT_LT(s3, s);
    }
  }
}

// The one-pass score-and-select of the local optimisation equals its two separate calls, for relaxed inlier
// thresholds, both scoring modes, perturbed models (many errors between the two thresholds) and a parallax tolerance
// that differs between the two thresholds.
TEST(ScoreModelAndComputeInliers, EqualsScoreModelThenComputeInliers) {
  std::mt19937 rng(9);
  std::normal_distribution<double> n(0.0, 1.0);
  int between = 0;
  for (int trial = 0; trial < 10; ++trial) {
    testing::SolverInstance inst;
    const RelposeProblem p = NoisyProblem(rng, &inst);
    for (int k = 0; k < 3; ++k) {
      AffineDepthPose m = inst.gt;
      if (k > 0) {
        const Eigen::Vector3d w(0.005 * k * n(rng), 0.005 * k * n(rng), 0.005 * k * n(rng));
        m.R = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() * m.R;
        m.t += 0.02 * k * Eigen::Vector3d(n(rng), n(rng), n(rng));
        m.shift0 += 0.01 * k * n(rng);
      }
      HybridEstimatorOptions o;
      o.cheirality_min_parallax = 3.0;
      for (ScoringMode mode : {ScoringMode::kHybrid, ScoringMode::kSampsonOnly}) {
        o.scoring = mode;
        const MsacWeights w = MsacWeights::FromOptions(o);
        for (const double factor : {1.0, 2.0, 5.0}) {
          const MsacWeights wi = w.Relaxed(factor);
          InlierSets separate, merged, strict;
          ComputeInliers(p, m, wi, &separate);
          ComputeInliers(p, m, w, &strict);
          const double s = ScoreModelAndComputeInliers(p, m, w, wi, &merged);
          EXPECT_EQ(s, ScoreModel(p, m, w));
          EXPECT_EQ(merged.reproj0, separate.reproj0);
          EXPECT_EQ(merged.reproj1, separate.reproj1);
          EXPECT_EQ(merged.sampson, separate.sampson);
          between += separate.Total() - strict.Total();
        }
      }
    }
  }
  EXPECT_GT(between, 100);  // the relaxed thresholds did select more inliers
}

TEST(MsacWeights, ParallelToleranceFollowsTheSampsonThresholdAngle) {
  HybridEstimatorOptions o;
  o.epipolar_threshold = 2.0;
  o.cheirality_min_parallax = 1.0;
  const MsacWeights w = MsacWeights::FromOptions(o);
  // 2 px at f = 800 px: 2.5 mrad.
  EXPECT_NEAR(w.ParallelSin2(800.0, 1000.0), std::pow(2.0 / 800.0, 2), 1e-15);
  // Long focal lengths: the fixed floor (about 0.06 deg).
  EXPECT_EQ(w.ParallelSin2(1e5, 1e5), ModelResiduals::kParallelSin2);
  o.cheirality_min_parallax = 0.0;
  EXPECT_EQ(MsacWeights::FromOptions(o).ParallelSin2(800.0, 800.0), ModelResiduals::kParallelSin2);
  o.cheirality_min_parallax = 3.0;
  EXPECT_NEAR(MsacWeights::FromOptions(o).ParallelSin2(800.0, 800.0), std::pow(6.0 / 800.0, 2), 1e-15);
}

TEST(ModelResiduals, CheiralityIsJudgedOnlyBeyondTheParallelTolerance) {
  // Camera 1 one unit to the right of camera 0 (X1 = X0 - (1, 0, 0)), no rotation.
  AffineDepthPose m;
  m.t = Eigen::Vector3d(-1.0, 0.0, 0.0);
  // A point behind both cameras: the rays of (0, 0) and (0.1, 0) meet at z = -10, where their angle is ~0.1 rad.
  const Eigen::Vector2d x0(0.0, 0.0), x1(0.1, 0.0);
  const ModelResiduals judged(m, 1000.0, 1000.0, 1e-6);
  EXPECT_EQ(judged.SampsonCheiral(x0, x1), ModelResiduals::kInvalidError);
  // With a tolerance above sin^2(0.1) the sign of its depth is not judged: the plain Sampson error.
  const ModelResiduals lenient(m, 1000.0, 1000.0, 0.02);
  EXPECT_EQ(lenient.SampsonCheiral(x0, x1), lenient.Sampson(x0, x1));
  // A point in front (rays meeting at z = +10) is never rejected.
  const Eigen::Vector2d x1_front(-0.1, 0.0);
  EXPECT_EQ(judged.SampsonCheiral(x0, x1_front), judged.Sampson(x0, x1_front));
}

// The capped errors of the search (no division, no cheirality test for errors at or above the cap) against the
// exact ones, on the true model and on perturbed ones, at caps placed exactly at and one ulp above every exact
// error: the comparison with the cap and the capped value agree in every case.
TEST(ModelResiduals, CappedErrorsAgreeWithExactOnesAtTheCap) {
  std::mt19937 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  int exact_below_cap = 0, checked = 0;
  for (int trial = 0; trial < 10; ++trial) {
    testing::SolverInstance inst;
    const RelposeProblem p = NoisyProblem(rng, &inst);
    for (int k = 0; k < 5; ++k) {
      AffineDepthPose m = inst.gt;
      if (k > 0) {  // rotation, translation and depth corrections off by a few percent
        const Eigen::Vector3d w(0.02 * k * n(rng), 0.02 * k * n(rng), 0.02 * k * n(rng));
        m.R = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() * m.R;
        m.t += 0.05 * k * Eigen::Vector3d(n(rng), n(rng), n(rng));
        m.shift0 += 0.02 * k * n(rng);
        m.shift1 += 0.02 * k * n(rng);
        m.scale *= 1.0 + 0.02 * k * n(rng);
      }
      const ModelResiduals res(m, p.pixel_scale0, p.pixel_scale1, 1e-6);
      for (int i = 0; i < p.size(); ++i) {
        const double exact[4] = {res.Sampson(p.x0[i], p.x1[i]), res.SampsonCheiral(p.x0[i], p.x1[i]),
                                 res.Reprojection01(p.x0[i], p.x1[i], p.d0[i]),
                                 res.Reprojection10(p.x0[i], p.x1[i], p.d1[i])};
        for (int j = 0; j < 4; ++j) {
          if (!(exact[j] > 0.0)) continue;  // kInvalidError included: points behind a camera
          for (const double cap : {exact[j], std::nextafter(exact[j], 2.0 * exact[j]), 0.5 * exact[j],
                                   2.0 * exact[j], 64.0, 4.0}) {
            double capped = 0.0;
            if (j == 0) capped = res.Sampson(p.x0[i], p.x1[i], cap);
            if (j == 1) capped = res.SampsonCheiral(p.x0[i], p.x1[i], cap);
            if (j == 2) capped = res.Reprojection01(p.x0[i], p.x1[i], p.d0[i], cap);
            if (j == 3) capped = res.Reprojection10(p.x0[i], p.x1[i], p.d1[i], cap);
            ASSERT_EQ(capped < cap, exact[j] < cap) << "error " << j << " point " << i << " cap " << cap;
            ASSERT_EQ(std::min(capped, cap), std::min(exact[j], cap)) << "error " << j << " point " << i;
            exact_below_cap += exact[j] < cap;
            ++checked;
          }
        }
      }
    }
  }
  // Both sides of the cap were exercised, many times.
  EXPECT_GT(exact_below_cap, checked / 10);
  EXPECT_LT(exact_below_cap, checked - checked / 10);
}

}  // namespace
}  // namespace madsfm
