// Focal lengths estimated from point samples only (7-point fundamental matrix and Bougnoux's focal lengths for two
// focal lengths, the 6-point solver for a shared one): the search runs at least min_iterations_two_focal_points /
// min_iterations_shared_focal_points iterations, because a clean minimal sample can lead to a basin with the focal
// length off and nearly all the inliers, and the adaptive stopping criterion would end there.
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

HybridEstimatorOptions WithoutExtendedSearches() {
  HybridEstimatorOptions o;
  o.min_iterations_two_focal_points = 0;
  o.min_iterations_shared_focal_points = 0;
  return o;
}

// The point method on every pair with the default options and without the extended searches: fewer runs end > 5 deg
// off with them, and more pairs end > 1 deg better than > 1 deg worse.
void ExpectFewerWrongBasins(const std::vector<SyntheticPair>& set, CameraMode mode) {
  int wrong_on = 0, wrong_off = 0, better = 0, worse = 0;
  for (const SyntheticPair& s : set) {
    const double on = PoseError(EvaluatePair(s.pair, mode, "points", HybridEstimatorOptions()));
    const double off = PoseError(EvaluatePair(s.pair, mode, "points", WithoutExtendedSearches()));
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

TEST(PointsIterations, OnlyThePointOnlyFocalSearchesAreExtended) {
  // Few outliers, so that the adaptive stop alone would come before either minimum.
  SyntheticPairOptions preset = *SyntheticPairPreset("hard_outdoor_two_focal");
  preset.min_outlier_ratio = 0.02;
  preset.max_outlier_ratio = 0.10;
  const auto set = GenerateTwoViewSet(preset, 4, 5);
  HybridEstimatorOptions o;
  ASSERT_EQ(o.min_iterations_two_focal_points, 1000);
  ASSERT_EQ(o.min_iterations_shared_focal_points, 300);
  const HybridEstimatorOptions off = WithoutExtendedSearches();
  int extended_two = 0, extended_shared = 0;
  for (const SyntheticPair& s : set) {
    const std::vector<std::pair<CameraMode, int>> extended = {{CameraMode::kTwoFocal, 1000},
                                                              {CameraMode::kSharedFocal, 300}};
    for (const auto& [mode, minimum] : extended) {
      const int with = EvaluatePair(s.pair, mode, "points", o).iterations;
      const int adaptive = EvaluatePair(s.pair, mode, "points", off).iterations;
      // The same draws up to the adaptive stop: a search the minimum does not reach is unchanged.
      EXPECT_GE(with, std::max(adaptive, minimum));
      if (adaptive >= minimum) {
        EXPECT_EQ(with, adaptive);
      }
      (mode == CameraMode::kTwoFocal ? extended_two : extended_shared) += adaptive < minimum;
    }
    // The hybrid draws affine-depth samples too, and the calibrated point search has no focal length to get
    // wrong: they keep the adaptive stop.
    const std::vector<std::pair<CameraMode, const char*>> others = {{CameraMode::kTwoFocal, "hybrid"},
                                                                      {CameraMode::kSharedFocal, "hybrid"},
                                                                      {CameraMode::kCalibrated, "points"}};
    for (const auto& [mode, method] : others) {
      const PairResult a = EvaluatePair(s.pair, mode, method, o);
      const PairResult b = EvaluatePair(s.pair, mode, method, off);
      EXPECT_EQ(a.iterations, b.iterations) << method;
      EXPECT_EQ(PoseError(a), PoseError(b)) << method;
    }
  }
  EXPECT_GE(extended_two, 1);
  EXPECT_GE(extended_shared, 1);
  // max_iterations caps them.
  o.max_iterations = 200;
  EXPECT_LE(EvaluatePair(set[0].pair, CameraMode::kTwoFocal, "points", o).iterations, 200);
  EXPECT_LE(EvaluatePair(set[0].pair, CameraMode::kSharedFocal, "points", o).iterations, 200);
}

// Accurate matches (0.1-0.2 px, as SIFT on sharp rendered images): more pairs end far from the truth when the
// point-only search stops adaptively. Since point models' depth fits are kept within the shift bound (their local
// optimisation is no longer stuck at an out-of-bound start), the adaptive search itself is better and the gain is
// smaller: 29 -> 25 of 300 pairs > 5 deg, 12 pairs better and 7 worse by > 1 deg (it was 36 -> 29, 17 / 5; on the
// first 60 pairs it is now 6 -> 6), so the test uses 300 pairs.
TEST(PointsIterations, TwoFocalFewerWrongBasinsWithAccurateMatches) {
  if (testing::kUnderSanitizer) GTEST_SKIP() << "a rate over 600 estimator runs (450 s under ASan): Release only";
  SyntheticPairOptions preset = *SyntheticPairPreset("hard_outdoor_two_focal");
  preset.min_pixel_noise = 0.1;
  preset.max_pixel_noise = 0.2;
  ExpectFewerWrongBasins(GenerateTwoViewSet(preset, 300, 11), CameraMode::kTwoFocal);
}

// One shared focal length, 6-point samples only, at inlier ratios where the adaptive stop comes right after
// min_iterations (2-10% outliers, as on the rendered pairs with SIFT matches): the extended search ends far off less
// often (measured: 14 -> 10 of 300 pairs > 5 deg, 7 pairs better and 1 worse by > 1 deg).
TEST(PointsIterations, SharedFocalFewerWrongBasinsAtHighInlierRatios) {
  if (testing::kUnderSanitizer) GTEST_SKIP() << "a rate over 600 estimator runs: Release only";
  SyntheticPairOptions preset = *SyntheticPairPreset("hard_outdoor_shared_focal");
  preset.min_outlier_ratio = 0.02;
  preset.max_outlier_ratio = 0.10;
  ExpectFewerWrongBasins(GenerateTwoViewSet(preset, 300, 11), CameraMode::kSharedFocal);
}

}  // namespace
}  // namespace madsfm
