// Two focal lengths with point samples only (7-point fundamental matrix and Bougnoux's focal lengths): the search
// runs at least min_iterations_two_focal_points iterations, because a clean 7-point sample often leads to a basin
// with the focal lengths far off and nearly all the inliers, and the adaptive stopping criterion would end there
// (HybridEstimatorOptions::min_iterations_two_focal_points).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <utility>
#include <vector>

#include "madsfm/estimators/pair_evaluation.h"
#include "madsfm/synthetic/two_view_scene.h"
#include "testing/sanitizer.h"

namespace madsfm {
namespace {

double PoseError(const PairResult& r) { return std::max(*r.rot_err_deg, *r.trans_err_deg); }

TEST(TwoFocalPointsIterations, OnlyThePointOnlyTwoFocalSearchIsExtended) {
  const SyntheticPairOptions preset = *SyntheticPairPreset("hard_outdoor_two_focal");
  const auto set = GenerateTwoViewSet(preset, 4, 5);
  HybridEstimatorOptions o;
  ASSERT_EQ(o.min_iterations_two_focal_points, 1000);
  for (const SyntheticPair& s : set) {
    HybridEstimatorOptions off = o;
    off.min_iterations_two_focal_points = 0;
    const PairResult points = EvaluatePair(s.pair, CameraMode::kTwoFocal, "points", o);
    EXPECT_GE(points.iterations, 1000);
    EXPECT_LT(EvaluatePair(s.pair, CameraMode::kTwoFocal, "points", off).iterations, points.iterations);
    // The hybrid draws affine-depth samples too, and the calibrated and shared-focal point searches do not
    // have the weakly determined focal lengths of the 7-point solver: they keep the adaptive stop.
    const std::vector<std::pair<CameraMode, const char*>> others = {{CameraMode::kTwoFocal, "hybrid"},
                                                                      {CameraMode::kCalibrated, "points"},
                                                                      {CameraMode::kSharedFocal, "points"}};
    for (const auto& [mode, method] : others) {
      const PairResult a = EvaluatePair(s.pair, mode, method, o);
      const PairResult b = EvaluatePair(s.pair, mode, method, off);
      EXPECT_EQ(a.iterations, b.iterations) << method;
      EXPECT_EQ(PoseError(a), PoseError(b)) << method;
    }
  }
  // max_iterations caps it.
  o.max_iterations = 300;
  EXPECT_LE(EvaluatePair(set[0].pair, CameraMode::kTwoFocal, "points", o).iterations, 300);
}

// Accurate matches (0.1-0.2 px, as SIFT on sharp rendered images): more pairs end far from the truth when the
// point-only search stops adaptively. Since point models' depth fits are kept within the shift bound (their local
// optimisation is no longer stuck at an out-of-bound start), the adaptive search itself is better and the gain is
// smaller: 29 -> 25 of 300 pairs > 5 deg, 13 pairs better and 7 worse by > 1 deg (it was 36 -> 29, 17 / 5; on the
// first 60 pairs it is now 6 -> 6), so the test uses 300 pairs.
TEST(TwoFocalPointsIterations, FewerWrongBasinsWithAccurateMatches) {
  if (testing::kUnderSanitizer) GTEST_SKIP() << "a rate over 600 estimator runs (450 s under ASan): Release only";
  SyntheticPairOptions preset = *SyntheticPairPreset("hard_outdoor_two_focal");
  preset.min_pixel_noise = 0.1;
  preset.max_pixel_noise = 0.2;
  const auto set = GenerateTwoViewSet(preset, 300, 11);
  int wrong_on = 0, wrong_off = 0, better = 0, worse = 0;
  for (const SyntheticPair& s : set) {
    HybridEstimatorOptions o;
    const double on = PoseError(EvaluatePair(s.pair, CameraMode::kTwoFocal, "points", o));
    o.min_iterations_two_focal_points = 0;
    const double off = PoseError(EvaluatePair(s.pair, CameraMode::kTwoFocal, "points", o));
    wrong_on += on > 5.0;
    wrong_off += off > 5.0;
    better += on < off - 1.0;
    worse += on > off + 1.0;
  }
  std::printf("pose error > 5 deg: %d -> %d of %zu pairs; > 1 deg better %d, worse %d\n", wrong_off, wrong_on,
              set.size(), better, worse);
  EXPECT_LT(wrong_on, wrong_off);
  EXPECT_GT(better, worse);
}

}  // namespace
}  // namespace madsfm
