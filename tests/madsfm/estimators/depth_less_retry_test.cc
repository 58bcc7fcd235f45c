// A hybrid result that the depth priors do not support at all is searched once more (HybridEstimatorOptions::
// retry_depth_less): a wrong best model without depth inliers sets the depth solver's share of samples to 0 and the
// search can stop in its basin.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "madsfm/estimators/hybrid_lo_msac.h"
#include "madsfm/estimators/pair_evaluation.h"
#include "madsfm/geometry/pose_error.h"
#include "madsfm/synthetic/two_view_scene.h"

namespace madsfm {
namespace {

// Priors that carry no information (random values independent of the scene): no result has depth inliers,
// so every search is repeated once with the derived seed, its work is added, and the lower score of the two wins.
// (The case the retry was added for, a wrong basin without depth inliers reached through minimal models whose
// shifts were out of the bound, has not occurred on the held-out hard pairs since the bound is applied to every
// model: 0 of 480 runs against 2 before; docs/benchmarks.md section 11.)
TEST(DepthLessRetry, ResultsWithoutDepthInliersAreSearchedAgain) {
  std::mt19937 rng(31);
  const int kTrials = 10;
  int retried = 0, pose_ok = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    // A calibrated, noise-free pair: depths 2-8, a baseline of 1 (12-50% of the depth), priors independent of the
    // scene (log-uniform in 0.1-100).
    std::uniform_real_distribution<double> u(-1.0, 1.0), log_prior(std::log(0.1), std::log(100.0));
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(0.2 * u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized()).toRotationMatrix();
    const Eigen::Vector3d t(1.0, 0.2 * u(rng), 0.2 * u(rng));
    RelposeProblem p;
    p.pixel_scale0 = p.pixel_scale1 = 500.0;
    while (p.size() < 150) {
      const double z = 5.0 + 3.0 * u(rng);
      const Eigen::Vector3d X(0.5 * z * u(rng), 0.4 * z * u(rng), z);
      const Eigen::Vector3d Y = R * X + t;
      if (!(Y.z() > 0.5)) continue;
      p.x0.push_back(X.head<2>() / X.z());
      p.x1.push_back(Y.head<2>() / Y.z());
      p.d0.push_back(std::exp(log_prior(rng)));
      p.d1.push_back(std::exp(log_prior(rng)));
    }
    p.IndexDepths();
    HybridEstimatorOptions o;
    o.seed = trial;
    o.reproj_threshold = 2.0;  // noise-free data: tight thresholds keep chance depth inliers rare
    o.epipolar_threshold = 1.0;
    o.scale_only_fallback = false;  // the test is about the retry alone
    o.retry_depth_less = false;
    const HybridEstimate off = EstimateHybridRelpose(p, o);
    o.retry_depth_less = true;
    const HybridEstimate on = EstimateHybridRelpose(p, o);
    ASSERT_TRUE(off.success && on.success);
    const bool depth_less =
        off.num_inliers_reproj0 + off.num_inliers_reproj1 < 0.05 * off.num_inliers_sampson;
    if (!depth_less) continue;
    ++retried;
    EXPECT_GT(on.iterations, off.iterations) << "trial " << trial;  // the second search's work is counted
    EXPECT_LE(on.score, off.score) << "trial " << trial;
    pose_ok += RotationErrorDeg(on.model.R, R) < 1e-4 && TranslationErrorDeg(on.model.t, t) < 1e-3;
  }
  std::printf("priors without information: %d of %d results had no depth inliers and were searched again; pose "
              "recovered in %d\n", retried, kTrials, pose_ok);
  EXPECT_GE(retried, kTrials * 9 / 10);
  EXPECT_GE(pose_ok, retried * 9 / 10);  // the epipolar evidence is exact
}

// A result the priors support is left alone: the same result with and without the retry on every pair of a set.
TEST(DepthLessRetry, SupportedResultsAreUnchanged) {
  SyntheticPairOptions preset = *SyntheticPairPreset("hard_indoor_calibrated");
  preset.max_num_matches = std::min(preset.max_num_matches, 600);
  const auto set = GenerateTwoViewSet(preset, 10, 2024);
  for (const SyntheticPair& s : set) {
    HybridEstimatorOptions o;
    const PairResult on = EvaluatePair(s.pair, CameraMode::kCalibrated, "hybrid", o);
    o.retry_depth_less = false;
    const PairResult off = EvaluatePair(s.pair, CameraMode::kCalibrated, "hybrid", o);
    EXPECT_EQ(on.num_inliers_sampson, off.num_inliers_sampson);
    EXPECT_EQ(on.model.R, off.model.R);
    EXPECT_EQ(on.model.t, off.model.t);
  }
}

}  // namespace
}  // namespace madsfm
