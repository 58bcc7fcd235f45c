// HybridEstimatorOptions::scale_only_fallback: a hybrid result whose shifts the priors do not determine is estimated
// again with the scale-only model, which replaces it when its MSAC score is at most as high. Results whose
// corrections are observable are left alone; the replaced ones have zero shifts, stay unobservable, and on
// low-parallax pairs (where the two free shifts let the pose slide) the scale-only poses are better more often than
// worse (docs/benchmarks.md section 11, update of 2026-12-03 evening).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "madsfm/estimators/pair_evaluation.h"
#include "madsfm/synthetic/two_view_scene.h"
#include "testing/median.h"

namespace madsfm {
namespace {

using testing::Median;

struct FallbackOutcome {
  int pairs = 0, replaced = 0, better = 0, worse = 0;  // better / worse: pose error moved by more than 0.5 deg
  std::vector<double> error_on, error_off;             // pose errors of the replaced pairs, with and without
};

FallbackOutcome RunSet(const char* preset, CameraMode mode, int num_pairs, uint64_t seed) {
  FallbackOutcome out;
  for (const SyntheticPair& s : GenerateTwoViewSet(*SyntheticPairPreset(preset), num_pairs, seed)) {
    HybridEstimatorOptions o;
    const PairResult on = EvaluatePair(s.pair, mode, "hybrid", o);
    o.scale_only_fallback = false;
    const PairResult off = EvaluatePair(s.pair, mode, "hybrid", o);
    if (!on.success || !off.success) continue;
    ++out.pairs;
    if (!on.shifts_dropped) {
      // Not replaced: exactly the result without the fallback.
      EXPECT_EQ(on.model.R, off.model.R);
      EXPECT_EQ(on.model.t, off.model.t);
      EXPECT_EQ(on.model.shift0, off.model.shift0);
      continue;
    }
    // Replaced only where the corrections with shifts were not observable, by a scale-only result that scores at
    // most as high.
    EXPECT_FALSE(off.depth_observable);
    EXPECT_LE(on.score, off.score);
    EXPECT_FALSE(on.depth_observable);
    EXPECT_EQ(on.model.shift0, 0.0);
    EXPECT_EQ(on.model.shift1, 0.0);
    ++out.replaced;
    const double e_on = std::max(*on.rot_err_deg, *on.trans_err_deg);
    const double e_off = std::max(*off.rot_err_deg, *off.trans_err_deg);
    out.error_on.push_back(e_on);
    out.error_off.push_back(e_off);
    out.better += e_on < e_off - 0.5;
    out.worse += e_on > e_off + 0.5;
  }
  std::printf("%s: %d of %d pairs estimated again without shifts; pose error better on %d, worse on %d; median over "
              "them %.2f deg (with shifts %.2f)\n",
              preset, out.replaced, out.pairs, out.better, out.worse, Median(out.error_on), Median(out.error_off));
  return out;
}

// Both low-parallax presets, 120 pairs each. One calibrated set alone replaced 9-12 pairs, too few to count: over the
// ten seeds of the sweep's four low-parallax sets (docs/benchmarks.md section 11, update of 2026-12-07, night) the
// replaced runs are better / worse by more than 0.5 deg on 59 / 38 runs (madsfm-22; 61 / 39 with madsfm-21), but in
// single-seed windows of the two calibrated sets alone better > worse failed on 5 of 10 windows with either version,
// and on 2 of 10 with both presets pooled. The fallback adds 3.0 AUC@10 summed over those four sets with either
// version.
TEST(ScaleOnlyFallback, LowParallaxPairsImprove) {
  const FallbackOutcome c = RunSet("hard_low_parallax_calibrated", CameraMode::kCalibrated, 120, 2024);
  const FallbackOutcome s = RunSet("hard_low_parallax_shared_focal", CameraMode::kSharedFocal, 120, 2024);
  ASSERT_GE(c.pairs + s.pairs, 216);
  std::vector<double> on = c.error_on, off = c.error_off;
  on.insert(on.end(), s.error_on.begin(), s.error_on.end());
  off.insert(off.end(), s.error_off.begin(), s.error_off.end());
  ASSERT_GE(on.size(), 10u) << "too few pairs with undetermined shifts for the comparison";
  EXPECT_GT(c.better + s.better, c.worse + s.worse);
  EXPECT_LT(Median(on), Median(off));
}

TEST(ScaleOnlyFallback, WellDeterminedPairsAreUnchanged) {
  const FallbackOutcome o = RunSet("hard_indoor_shared_focal", CameraMode::kSharedFocal, 20, 2024);
  ASSERT_GE(o.pairs, 18);
  EXPECT_LE(o.replaced, o.pairs / 5);
}

}  // namespace
}  // namespace madsfm
