// The planar twin of the point method's result (HybridEstimatorOptions::planar_twin_min_support): on scenes that see
// one dominant plane both decompositions of its homography explain the plane's points, and the search can end in the
// wrong one when its minimal models happen to score better there.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "madsfm/estimators/pair_evaluation.h"
#include "madsfm/geometry/pose_error.h"
#include "madsfm/synthetic/two_view_scene.h"
#include "testing/sanitizer.h"

namespace madsfm {
namespace {

SyntheticPairOptions CappedPreset(const std::string& name) {
  SyntheticPairOptions o = *SyntheticPairPreset(name);
  o.max_num_matches = std::min(o.max_num_matches, 600);
  return o;
}

double PoseError(const PairResult& r) { return std::max(*r.rot_err_deg, *r.trans_err_deg); }

// Planar scenes (one wall, often the floor too), calibrated and shared unknown focal, 120 pairs x 3 seeds each: with
// the twin step the point method ends more than 1 deg better on more runs than it ends more than 1 deg worse, and its
// AUC@10 does not drop (measured: calibrated 8 / 2 runs, 64.56 vs 63.49; shared focal 11 / 3, 51.69 vs 51.02).
// (Where the scene is exactly one plane the twins tie and either can win: the rate, not every run, improves.)
void ExpectTwinGains(const char* preset, CameraMode mode, int min_iterations_shared_focal_points) {
  const auto set = GenerateTwoViewSet(CappedPreset(preset), 120, 2024);
  int better = 0, worse = 0;
  std::vector<double> with, without;
  for (const SyntheticPair& s : set) {
    for (uint64_t seed = 0; seed < 3; ++seed) {
      HybridEstimatorOptions o;
      o.seed = seed;
      o.min_iterations_shared_focal_points = min_iterations_shared_focal_points;
      const double on = PoseError(EvaluatePair(s.pair, mode, "points", o));
      o.planar_twin_min_support = 0.0;
      const double off = PoseError(EvaluatePair(s.pair, mode, "points", o));
      better += on < off - 1.0;
      worse += on > off + 1.0;
      with.push_back(on);
      without.push_back(off);
    }
  }
  const double auc_with = PoseAuc(with, {10.0})[0], auc_without = PoseAuc(without, {10.0})[0];
  std::printf("%s, points: twin better by > 1 deg in %d runs, worse in %d; AUC@10 %.2f vs %.2f\n", preset, better,
              worse, 100 * auc_with, 100 * auc_without);
  EXPECT_GT(better, worse);
  EXPECT_GE(auc_with, auc_without);
}

TEST(PlanarTwin, PointMethodGainsOnPlanarScenes) {
  if (testing::kUnderSanitizer) GTEST_SKIP() << "a rate over 1440 estimator runs: Release only";
  ExpectTwinGains("hard_planar_calibrated", CameraMode::kCalibrated, 0);
  // With a shared focal length the default search runs at least min_iterations_shared_focal_points (300) and then
  // finds the twin's basin itself about as often as the step does (measured: 3 runs better, 4 worse, AUC@10 51.31
  // against 51.55 without the step); the step is for the search that stops adaptively.
  ExpectTwinGains("hard_planar_shared_focal", CameraMode::kSharedFocal, 0);
}

// The step belongs to the Sampson-only score: the hybrid's depth terms tell the twins apart, so its results do not
// depend on the option at all.
TEST(PlanarTwin, HybridResultsDoNotDependOnIt) {
  const auto set = GenerateTwoViewSet(CappedPreset("hard_planar_calibrated"), 8, 7);
  for (const SyntheticPair& s : set) {
    HybridEstimatorOptions o;
    const PairResult a = EvaluatePair(s.pair, CameraMode::kCalibrated, "hybrid", o);
    o.planar_twin_min_support = 0.0;
    const PairResult b = EvaluatePair(s.pair, CameraMode::kCalibrated, "hybrid", o);
    ASSERT_TRUE(a.success && b.success);
    EXPECT_EQ((a.model.R - b.model.R).norm(), 0.0);
    EXPECT_EQ((a.model.t - b.model.t).norm(), 0.0);
    EXPECT_EQ(a.score, b.score);
  }
}

TEST(PlanarTwin, OptionIsChecked) {
  HybridEstimatorOptions o;
  o.planar_twin_min_support = 1.5;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o.planar_twin_min_support = -0.1;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o.planar_twin_min_support = 1.0;
  EXPECT_NO_THROW(o.Check());
}

}  // namespace
}  // namespace madsfm
