// The search also optimises minimal models of another basin than the best one (HybridEstimatorOptions::
// alt_basin_lo_margin): on far-point pairs a lucky minimal model of a wrong basin can score a few percent better
// than every minimal model of the right basin, which then never reached the local optimisation. Fixed seeds; the
// assertions are counts of failed runs, with the margin off as the reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "madsfm/estimators/pair_evaluation.h"
#include "madsfm/synthetic/two_view_scene.h"

namespace madsfm {
namespace {

// Runs with a pose error above 5 deg (or no result), over pairs x seeds 0..num_seeds-1. The planar twin
// (planar_twin_min_support) is off unless asked for: it is another route out of the same wrong basins on these
// ground-plane scenes, and these tests are about the margin.
int FailedRuns(const std::vector<SyntheticPair>& set, const std::string& method, double margin, int num_seeds,
               double planar_twin_min_support = 0.0) {
  int failed = 0;
  for (const SyntheticPair& s : set) {
    for (int seed = 0; seed < num_seeds; ++seed) {
      HybridEstimatorOptions o;
      o.seed = seed;
      o.alt_basin_lo_margin = margin;
      o.planar_twin_min_support = planar_twin_min_support;
      const PairResult r = EvaluatePair(s.pair, CameraMode::kCalibrated, method, o);
      failed += !r.success || std::max(*r.rot_err_deg, *r.trans_err_deg) > 5.0;
    }
  }
  return failed;
}

// Pair 41 of `madsfm synth --preset hard_outdoor_calibrated --seed 11` (886 matches, half of them inliers, far
// points), where the failure was found: with the margin off, 2 of 10 seeds of the point method end 71 deg off in a
// basin with 433 inliers (the right one has 454); the right basin's best minimal model scored 3.7% worse.
TEST(AltBasinLocalOptimisation, FarPointPairEndsInTheRightBasinWithEverySeed) {
  const auto set = GenerateTwoViewSet(*SyntheticPairPreset("hard_outdoor_calibrated"), 42, 11);
  const std::vector<SyntheticPair> pair(set.begin() + 41, set.end());
  const int off = FailedRuns(pair, "points", 0.0, 10), on = FailedRuns(pair, "points", 0.05, 10);
  std::printf("far-point pair, point method, runs > 5 deg of 10: margin 0: %d, margin 0.05: %d\n", off, on);
  EXPECT_GE(off, 1) << "the pair no longer shows the failure this test is about";
  EXPECT_EQ(on, 0);
  // The wrong basin is the planar twin of the right one (the ground plane holds most points): the twin step alone,
  // margin off, gets every seed right too.
  EXPECT_EQ(FailedRuns(pair, "points", 0.0, 10, 0.5), 0);
}

// A whole fixed-seed set: fewer failed runs of the point method than with the margin off (measured 2 -> 0 of 120).
TEST(AltBasinLocalOptimisation, FewerFailedPointRunsOnOutdoorPairs) {
  SyntheticPairOptions preset = *SyntheticPairPreset("hard_outdoor_calibrated");
  preset.max_num_matches = std::min(preset.max_num_matches, 600);
  const auto set = GenerateTwoViewSet(preset, 40, 2024);
  const int off = FailedRuns(set, "points", 0.0, 3), on = FailedRuns(set, "points", 0.05, 3);
  std::printf("outdoor set, point method, runs > 5 deg of 120: margin 0: %d, margin 0.05: %d\n", off, on);
  EXPECT_LT(on, off);
}

}  // namespace
}  // namespace madsfm
