#include "madsfm/estimators/hybrid_lo_msac.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>

#include "madsfm/estimators/msac_scoring.h"
#include "madsfm/geometry/pose_error.h"
#include "testing/problem_from_instance.h"
#include "testing/solver_instances.h"

namespace madsfm {
namespace {

using testing::CameraSetup;

// A noise-free instance with `num_inliers` correspondences plus outliers (view-1 coordinates and
// both priors replaced by random values, redrawn until they are > 10 px from consistent under the
// ground truth in every data type, so that the inlier set is unambiguous). Returns the inlier flags.
RelposeProblem MakeProblemWithOutliers(std::mt19937& rng, CameraSetup setup, int num_inliers, double outlier_ratio,
                                       testing::SolverInstance* inst, std::vector<char>* is_inlier) {
  testing::SolverInstanceOptions opt;
  opt.setup = setup;
  const int n = static_cast<int>(std::round(num_inliers / (1.0 - outlier_ratio)));
  opt.num_points = n;
  *inst = testing::MakeSolverInstance(rng, opt);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double unit = setup == CameraSetup::kCalibrated ? 1.0 : inst->focal1;
  is_inlier->assign(n, 1);
  const double pix0 = setup == CameraSetup::kCalibrated ? inst->focal0 : 1.0;
  const double pix1 = setup == CameraSetup::kCalibrated ? inst->focal1 : 1.0;
  const ModelResiduals gt(inst->gt, pix0, pix1);
  for (int i = num_inliers; i < n; ++i) {
    const double d0 = inst->d0[i], d1 = inst->d1[i];
    const double unit0 = setup == CameraSetup::kCalibrated ? 1.0 : inst->focal0;
    do {
      // Both ends are redrawn: a point at the epipole is consistent with every match.
      inst->x0[i] = Eigen::Vector2d(0.6 * u(rng), 0.45 * u(rng)) * unit0;
      inst->x1[i] = Eigen::Vector2d(0.6 * u(rng), 0.45 * u(rng)) * unit;
      inst->d0[i] = d0 * std::exp(u(rng));
      inst->d1[i] = d1 * std::exp(u(rng));
    } while (gt.Sampson(inst->x0[i], inst->x1[i]) < 100.0 ||
             gt.Reprojection01(inst->x0[i], inst->x1[i], inst->d0[i]) < 100.0 ||
             gt.Reprojection10(inst->x0[i], inst->x1[i], inst->d1[i]) < 100.0);
    (*is_inlier)[i] = 0;
  }
  return testing::ProblemFromInstance(*inst, setup);
}

// Focal bounds for the instances of MakeProblemWithOutliers (focal modes work in pixels).
void BoundFocal(RelposeProblem* p) {
  p->min_focal = 50;
  p->max_focal = 1e5;
}

// Options for the noise-free instances: tight thresholds (2 px reprojection, 1 px Sampson) and the given seed.
HybridEstimatorOptions NoiseFreeOptions(int seed) {
  HybridEstimatorOptions o;
  o.seed = seed;
  o.reproj_threshold = 2.0;
  o.epipolar_threshold = 1.0;
  return o;
}

class HybridEstimatorTest : public ::testing::TestWithParam<CameraSetup> {};

TEST_P(HybridEstimatorTest, RecoversGroundTruthWithHalfOutliers) {
  std::mt19937 rng(21);
  const int kTrials = 30;
  int recovered = 0, exact_masks = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    testing::SolverInstance inst;
    std::vector<char> is_inlier;
    RelposeProblem p = MakeProblemWithOutliers(rng, GetParam(), 100, 0.5, &inst, &is_inlier);
    BoundFocal(&p);
    HybridEstimatorOptions o = NoiseFreeOptions(trial);
    const HybridEstimate est = EstimateHybridRelpose(p, o);
    if (!est.success) continue;
    recovered += testing::ModelError(est.model, inst) < 1e-6;
    bool exact = true;
    for (int i = 0; i < p.size(); ++i) exact &= (est.inliers_reproj0[i] != 0) == (is_inlier[i] != 0);
    exact_masks += exact;
  }
  std::printf("hybrid estimator (%d): ground truth recovered (1e-6) in %d/%d, exact inlier mask in %d/%d\n",
              static_cast<int>(GetParam()), recovered, kTrials, exact_masks, kTrials);
  EXPECT_GE(recovered, kTrials * 95 / 100);
  EXPECT_GE(exact_masks, kTrials * 90 / 100);
}

TEST_P(HybridEstimatorTest, PointOnlyBaselineRecoversPoseWithHalfOutliers) {
  std::mt19937 rng(22);
  const int kTrials = 30;
  int recovered = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    testing::SolverInstance inst;
    std::vector<char> is_inlier;
    RelposeProblem p = MakeProblemWithOutliers(rng, GetParam(), 100, 0.5, &inst, &is_inlier);
    BoundFocal(&p);
    HybridEstimatorOptions o;
    o.seed = trial;
    o.solvers = SolverChoice::kPointsOnly;
    o.scoring = ScoringMode::kSampsonOnly;
    o.epipolar_threshold = 1.0;
    const HybridEstimate est = EstimateHybridRelpose(p, o);
    if (!est.success) continue;
    recovered += RotationErrorDeg(est.model.R, inst.gt.R) < 1e-4 && TranslationErrorDeg(est.model.t, inst.gt.t) < 1e-3;
  }
  std::printf("point-only estimator (%d): pose recovered in %d/%d\n", static_cast<int>(GetParam()), recovered, kTrials);
  // The two-focal point baseline (7pt + Bougnoux) is fragile by nature; the others must be reliable.
  EXPECT_GE(recovered, GetParam() == CameraSetup::kTwoFocal ? kTrials * 70 / 100 : kTrials * 90 / 100);
}

TEST_P(HybridEstimatorTest, SameSeedGivesSameResult) {
  std::mt19937 rng(23);
  testing::SolverInstance inst;
  std::vector<char> is_inlier;
  RelposeProblem p = MakeProblemWithOutliers(rng, GetParam(), 60, 0.4, &inst, &is_inlier);
  HybridEstimatorOptions o;
  o.seed = 77;
  const HybridEstimate a = EstimateHybridRelpose(p, o);
  const HybridEstimate b = EstimateHybridRelpose(p, o);
  ASSERT_TRUE(a.success);
  EXPECT_EQ(a.model.R, b.model.R);
  EXPECT_EQ(a.model.t, b.model.t);
  EXPECT_EQ(a.model.scale, b.model.scale);
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.inliers_sampson, b.inliers_sampson);
}

// lo_skip_same_basin: new best minimal models in the optimised best's basin that score no better are not optimised;
// fewer local optimisations, the same recovery rate.
TEST_P(HybridEstimatorTest, SkippingSameBasinLocalOptimisationsKeepsTheAccuracy) {
  std::mt19937 rng(25);
  const int kTrials = 30;
  int recovered[2] = {0, 0}, num_lo[2] = {0, 0};
  for (int trial = 0; trial < kTrials; ++trial) {
    testing::SolverInstance inst;
    std::vector<char> is_inlier;
    RelposeProblem p = MakeProblemWithOutliers(rng, GetParam(), 100, 0.5, &inst, &is_inlier);
    BoundFocal(&p);
    for (int skip = 0; skip < 2; ++skip) {
      HybridEstimatorOptions o = NoiseFreeOptions(trial);
      o.lo_skip_same_basin = skip == 1;
      const HybridEstimate est = EstimateHybridRelpose(p, o);
      recovered[skip] += est.success && testing::ModelError(est.model, inst) < 1e-6;
      num_lo[skip] += est.num_lo;
    }
  }
  std::printf("lo_skip_same_basin (%d): recovered %d/%d with every LO, %d/%d skipping; local optimisations %d vs %d\n",
              static_cast<int>(GetParam()), recovered[0], kTrials, recovered[1], kTrials, num_lo[0], num_lo[1]);
  EXPECT_GE(recovered[1], kTrials * 95 / 100);
  EXPECT_GE(recovered[1] + 1, recovered[0]);
  EXPECT_LT(num_lo[1], num_lo[0]);
}

INSTANTIATE_TEST_SUITE_P(Modes, HybridEstimatorTest,
                         ::testing::Values(CameraSetup::kCalibrated, CameraSetup::kSharedFocal, CameraSetup::kTwoFocal));

TEST(HybridEstimator, FallsBackToPointsWithoutDepth) {
  std::mt19937 rng(24);
  testing::SolverInstance inst;
  std::vector<char> is_inlier;
  RelposeProblem p = MakeProblemWithOutliers(rng, CameraSetup::kCalibrated, 80, 0.3, &inst, &is_inlier);
  for (double& d : p.d1) d = std::nan("");
  p.IndexDepths();
  ASSERT_TRUE(p.with_both_depths.empty());
  HybridEstimatorOptions o;
  o.epipolar_threshold = 1.0;
  const HybridEstimate est = EstimateHybridRelpose(p, o);
  ASSERT_TRUE(est.success);
  EXPECT_EQ(est.num_depth_samples, 0);
  EXPECT_GT(est.num_point_samples, 0);
  EXPECT_LT(RotationErrorDeg(est.model.R, inst.gt.R), 1e-4);
  EXPECT_EQ(est.num_inliers_reproj1, 0);
}

TEST(HybridEstimator, TooFewCorrespondencesFailCleanly) {
  RelposeProblem p;
  p.mode = CameraMode::kCalibrated;
  p.x0 = {{0.1, 0.1}, {0.2, 0.1}};
  p.x1 = {{0.1, 0.1}, {0.2, 0.1}};
  p.d0 = {1.0, 2.0};
  p.d1 = {1.0, 2.0};
  p.IndexDepths();
  const HybridEstimate est = EstimateHybridRelpose(p, HybridEstimatorOptions());
  EXPECT_FALSE(est.success);
  EXPECT_EQ(est.iterations, 0);
}

// Guided sampling (RelposeProblem::guided): a guide of mostly true matches among 70% outliers.
class GuidedSamplingTest : public ::testing::TestWithParam<CameraSetup> {};

// The guide: every inlier plus a tenth as many outliers (COLMAP's verification lets a few through).
std::vector<int> MakeGuide(const std::vector<char>& is_inlier) {
  std::vector<int> guide;
  int outliers = 0;
  for (int i = 0; i < static_cast<int>(is_inlier.size()); ++i) {
    if (is_inlier[i] || (outliers++ % 20 == 0)) guide.push_back(i);
  }
  return guide;
}

TEST_P(GuidedSamplingTest, AGoodGuideCutsTheIterationsAndKeepsTheAccuracy) {
  std::mt19937 rng(31);
  const int kTrials = 20;
  int recovered_uniform = 0, recovered_guided = 0, score_as_good = 0;
  std::vector<int> it_uniform, it_guided;
  for (int trial = 0; trial < kTrials; ++trial) {
    testing::SolverInstance inst;
    std::vector<char> is_inlier;
    RelposeProblem p = MakeProblemWithOutliers(rng, GetParam(), 90, 0.7, &inst, &is_inlier);
    BoundFocal(&p);
    HybridEstimatorOptions o = NoiseFreeOptions(trial);
    const HybridEstimate uniform = EstimateHybridRelpose(p, o);
    p.guided = MakeGuide(is_inlier);
    const HybridEstimate guided = EstimateHybridRelpose(p, o);
    recovered_uniform += uniform.success && testing::ModelError(uniform.model, inst) < 1e-6;
    recovered_guided += guided.success && testing::ModelError(guided.model, inst) < 1e-6;
    // By the estimator's own objective (the MSAC score) the guided search does at least as well. (Two focal: a
    // model slightly off the truth can score lower on noise-free data, and either search may find it.)
    score_as_good += guided.success && guided.score <= uniform.score * (1.0 + 1e-9);
    it_uniform.push_back(uniform.iterations);
    it_guided.push_back(guided.iterations);
  }
  std::sort(it_uniform.begin(), it_uniform.end());
  std::sort(it_guided.begin(), it_guided.end());
  std::printf("guided sampling (%d): recovered %d/%d uniform, %d/%d guided; guided score as low in %d/%d; median "
              "iterations %d uniform, %d guided\n",
              static_cast<int>(GetParam()), recovered_uniform, kTrials, recovered_guided, kTrials, score_as_good,
              kTrials, it_uniform[kTrials / 2], it_guided[kTrials / 2]);
  EXPECT_GE(recovered_guided, kTrials * 90 / 100);
  EXPECT_GE(score_as_good, kTrials * 90 / 100);
  EXPECT_LT(it_guided[kTrials / 2] * 2, it_uniform[kTrials / 2]);
}

TEST_P(GuidedSamplingTest, AGuideOfOutliersDoesNotStopTheSearch) {
  std::mt19937 rng(32);
  const int kTrials = 20;
  int recovered = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    testing::SolverInstance inst;
    std::vector<char> is_inlier;
    RelposeProblem p = MakeProblemWithOutliers(rng, GetParam(), 100, 0.5, &inst, &is_inlier);
    BoundFocal(&p);
    for (int i = 0; i < p.size(); ++i) {
      if (!is_inlier[i]) p.guided.push_back(i);  // a guide that is all wrong
    }
    const HybridEstimatorOptions o = NoiseFreeOptions(trial);
    const HybridEstimate est = EstimateHybridRelpose(p, o);
    recovered += est.success && testing::ModelError(est.model, inst) < 1e-6;
  }
  std::printf("guided sampling with a wrong guide (%d): recovered %d/%d\n", static_cast<int>(GetParam()), recovered,
              kTrials);
  EXPECT_GE(recovered, kTrials * 90 / 100);
}

INSTANTIATE_TEST_SUITE_P(Modes, GuidedSamplingTest,
                         ::testing::Values(CameraSetup::kCalibrated, CameraSetup::kSharedFocal, CameraSetup::kTwoFocal));

TEST(GuidedSampling, WithoutAGuideTheFractionChangesNothing) {
  std::mt19937 rng(33);
  testing::SolverInstance inst;
  std::vector<char> is_inlier;
  RelposeProblem p = MakeProblemWithOutliers(rng, CameraSetup::kSharedFocal, 60, 0.5, &inst, &is_inlier);
  BoundFocal(&p);
  HybridEstimatorOptions o;
  o.seed = 5;
  o.guided_sampling_fraction = 0.0;
  const HybridEstimate a = EstimateHybridRelpose(p, o);
  o.guided_sampling_fraction = 0.9;
  const HybridEstimate b = EstimateHybridRelpose(p, o);
  ASSERT_TRUE(a.success);
  EXPECT_EQ(a.model.R, b.model.R);
  EXPECT_EQ(a.model.t, b.model.t);
  EXPECT_EQ(a.model.f0, b.model.f0);
  EXPECT_EQ(a.iterations, b.iterations);
}

TEST(GuidedSampling, AnUnsortedOrOutOfRangeGuideIsRejected) {
  std::mt19937 rng(34);
  testing::SolverInstance inst;
  std::vector<char> is_inlier;
  RelposeProblem p = MakeProblemWithOutliers(rng, CameraSetup::kCalibrated, 30, 0.0, &inst, &is_inlier);
  p.guided = {3, 1};
  EXPECT_THROW(EstimateHybridRelpose(p, HybridEstimatorOptions()), std::invalid_argument);
  p.guided = {1, 1};
  EXPECT_THROW(EstimateHybridRelpose(p, HybridEstimatorOptions()), std::invalid_argument);
  p.guided = {0, p.size()};
  EXPECT_THROW(EstimateHybridRelpose(p, HybridEstimatorOptions()), std::invalid_argument);
  p.guided = {-1, 2};
  EXPECT_THROW(EstimateHybridRelpose(p, HybridEstimatorOptions()), std::invalid_argument);
  p.guided = {0, 1, 2, 3, 4, 5, 6};
  EXPECT_NO_THROW(EstimateHybridRelpose(p, HybridEstimatorOptions()));
}

TEST(HybridEstimatorOptions, CheckRejectsBadValues) {
  HybridEstimatorOptions o;
  EXPECT_NO_THROW(o.Check());
  o.reproj_threshold = -1;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o = HybridEstimatorOptions();
  o.max_iterations = 10;
  o.min_iterations = 20;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o = HybridEstimatorOptions();
  o.confidence = 1.0;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o = HybridEstimatorOptions();
  o.solvers = SolverChoice::kDepthOnly;
  o.scoring = ScoringMode::kSampsonOnly;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o = HybridEstimatorOptions();
  o.alt_basin_lo_margin = -0.1;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o = HybridEstimatorOptions();
  o.guided_sampling_fraction = 1.0;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o.guided_sampling_fraction = -0.1;
  EXPECT_THROW(o.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace madsfm
