// The hybrid estimator against the point-only baseline on fixed-seed synthetic sets with noise, outliers and
// monocular-depth-like priors (src/madsfm/synthetic), at the same thresholds (issue 4).
#include <gtest/gtest.h>

#include <algorithm>

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
  // Median errors are asserted only where the gap is well beyond run-to-run variation (e.g. FMA vs no FMA
  // builds): on indoor_shared_focal the two methods have the same median pose error within noise (1.76 vs
  // 1.77 deg with -march=native) and the same focal error (1.0% vs 1.05%); there only AUC@10 is asserted.
  bool check_medians;
};

class HybridVsPoints : public ::testing::TestWithParam<Case> {};

TEST_P(HybridVsPoints, HybridIsAtLeastAsAccurateAsPoints) {
  const Case c = GetParam();
  const auto set = GenerateTwoViewSet(*SyntheticPairPreset(c.preset), 40, 2024);
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
                         ::testing::Values(Case{"indoor_calibrated", CameraMode::kCalibrated, true},
                                           Case{"indoor_shared_focal", CameraMode::kSharedFocal, false},
                                           Case{"indoor_two_focal", CameraMode::kTwoFocal, true}));

}  // namespace
}  // namespace madsfm
