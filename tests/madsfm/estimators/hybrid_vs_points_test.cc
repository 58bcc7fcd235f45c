// The hybrid estimator against the point-only baseline on fixed-seed synthetic sets with noise, outliers and
// monocular-depth-like priors (src/madsfm/synthetic), at the same thresholds (issue 4).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "madsfm/estimators/pair_evaluation.h"
#include "madsfm/geometry/pose_error.h"
#include "madsfm/synthetic/two_view_scene.h"

namespace madsfm {
namespace {

struct Stats {
  double median_pose_err = 0;
  double auc10 = 0;  // AUC of the pose error up to 10 deg (the accuracy target)
  double median_focal_err = 0;
};

Stats Evaluate(const std::vector<SyntheticPair>& set, CameraMode mode, const std::string& method) {
  std::vector<double> pose, focal;
  for (const SyntheticPair& s : set) {
    HybridEstimatorOptions o;
    const PairResult r = EvaluatePair(s.pair, mode, method, o);
    const double e = std::max(*r.rot_err_deg, *r.trans_err_deg);
    pose.push_back(e);
    if (r.focal_err) focal.push_back(*r.focal_err);
  }
  auto median = [](std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  return {median(pose), PoseAuc(pose, {10.0})[0], median(focal)};
}

struct Case {
  const char* preset;
  CameraMode mode;
  // Median errors are asserted only where the gap is well beyond run-to-run variation: with the local optimisation
  // over inlier subsets and the cheirality of the Sampson data (issue 12) the point-only baseline has the same
  // median pose error as the hybrid on indoor_calibrated (0.461 vs 0.467 deg) and on the hard calibrated and
  // shared-focal presets; there only AUC@10 is asserted (the hybrid leads it by 2-11 points).
  bool check_medians;
};

class HybridVsPoints : public ::testing::TestWithParam<Case> {};

// A preset with at most 600 matches per pair (the hard presets draw up to 2000): the same scenes, priors and
// outliers at a test suite's cost (these tests also run under the sanitizers).
SyntheticPairOptions TestPreset(const std::string& name) {
  SyntheticPairOptions o = *SyntheticPairPreset(name);
  o.max_num_matches = std::min(o.max_num_matches, 600);
  return o;
}

TEST_P(HybridVsPoints, HybridIsAtLeastAsAccurateAsPoints) {
  const Case c = GetParam();
  const auto set = GenerateTwoViewSet(TestPreset(c.preset), 40, 2024);
  const Stats h = Evaluate(set, c.mode, "hybrid");
  const Stats p = Evaluate(set, c.mode, "points");
  std::printf("%s: median pose error hybrid %.3f deg vs points %.3f deg; AUC@10 %.1f vs %.1f; median focal "
              "error %.2f%% vs %.2f%%\n",
              c.preset, h.median_pose_err, p.median_pose_err, 100 * h.auc10, 100 * p.auc10,
              100 * h.median_focal_err, 100 * p.median_focal_err);
  EXPECT_GE(h.auc10, p.auc10);
  if (c.check_medians) {
    EXPECT_LE(h.median_pose_err, p.median_pose_err);
    if (c.mode != CameraMode::kCalibrated) {
      EXPECT_LE(h.median_focal_err, p.median_focal_err);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Presets, HybridVsPoints,
                         ::testing::Values(Case{"indoor_calibrated", CameraMode::kCalibrated, false},
                                           Case{"indoor_shared_focal", CameraMode::kSharedFocal, false},
                                           Case{"indoor_two_focal", CameraMode::kTwoFocal, true},
                                           // The hard presets (issue 12): planes, depth edges, metric and affine
                                           // priors, 150-2000 matches, 0.5-1.5 px noise, different cameras.
                                           Case{"hard_indoor_calibrated", CameraMode::kCalibrated, false},
                                           Case{"hard_planar_calibrated", CameraMode::kCalibrated, false},
                                           Case{"hard_outdoor_shared_focal", CameraMode::kSharedFocal, false},
                                           Case{"hard_indoor_two_focal", CameraMode::kTwoFocal, true}));

// Low parallax (baselines of 0.5-3% of the depth): the hybrid pose is better than the point-only pose on the set as
// a whole, and more than 2 deg worse on few of the pairs where the latter is usable.
TEST(HybridVsPointsLowParallax, HybridIsRarelyWorseThanPoints) {
  const auto set = GenerateTwoViewSet(TestPreset("hard_low_parallax_calibrated"), 40, 2024);
  int worse = 0;
  std::vector<double> hybrid, points;
  for (const SyntheticPair& s : set) {
    HybridEstimatorOptions o;
    const PairResult h = EvaluatePair(s.pair, CameraMode::kCalibrated, "hybrid", o);
    const PairResult p = EvaluatePair(s.pair, CameraMode::kCalibrated, "points", o);
    hybrid.push_back(std::max(*h.rot_err_deg, *h.trans_err_deg));
    points.push_back(std::max(*p.rot_err_deg, *p.trans_err_deg));
    worse += hybrid.back() > points.back() + 2.0 && points.back() < 10.0;
  }
  const double auc_h = PoseAuc(hybrid, {20.0})[0], auc_p = PoseAuc(points, {20.0})[0];
  std::printf("low parallax: AUC@20 hybrid %.1f vs points %.1f; hybrid > 2 deg worse on %d of %zu pairs\n",
              100 * auc_h, 100 * auc_p, worse, set.size());
  EXPECT_GE(auc_h, auc_p);
  // Measured: 5 of 40 (seed 2024, at most 600 matches). Issue 12 asks for none; this pins today's state so that
  // it cannot get worse unnoticed (at most 15% of the pairs), it does not claim the target.
  EXPECT_LE(worse, 6);
}

// Planar scenes (one wall, often with the floor): the point solvers' twofold ambiguity and twisted pairs. The
// point-only method has to find the right pose on most pairs (cheirality of the Sampson data decides between
// decompositions), and switching the cheirality off must not do better.
TEST(PointSolversOnPlanes, PointOnlyPoseIsRightOnMostPlanarPairs) {
  const auto set = GenerateTwoViewSet(TestPreset("hard_planar_calibrated"), 40, 2024);
  auto rate = [&](bool cheirality) {
    int good = 0;
    for (const SyntheticPair& s : set) {
      HybridEstimatorOptions o;
      o.sampson_cheirality = cheirality;
      const PairResult r = EvaluatePair(s.pair, CameraMode::kCalibrated, "points", o);
      good += std::max(*r.rot_err_deg, *r.trans_err_deg) < 5.0;
    }
    return static_cast<double>(good) / set.size();
  };
  const double with = rate(true), without = rate(false);
  std::printf("planar pairs with pose error < 5 deg, point-only: %.0f%% (cheirality), %.0f%% (without)\n",
              100 * with, 100 * without);
  EXPECT_GE(with, 0.7);  // measured: 78% with, 70% without (40 pairs, seed 2024)
  EXPECT_GT(with, without);
}

}  // namespace
}  // namespace madsfm
