// HybridEstimatorOptions::depth_fit_regression_in_bound: where the last depth fit's regression of the triangulated
// depths on the priors would put a shift beyond max_shift_ratio, it is fitted on the bound's edge instead of being
// dropped. On planar scenes one view's prior often barely follows the true depth; its best affine correction is
// nearly flat, with a large shift, and the edge keeps most of that benefit (docs/benchmarks.md section 11, update of
// 2026-12-07, late night).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "madsfm/estimators/pair_evaluation.h"
#include "madsfm/synthetic/two_view_scene.h"

namespace madsfm {
namespace {

// At most 600 matches per pair (the hard presets draw up to 2000): the same scenes at a test suite's cost.
std::vector<SyntheticPair> TestSet(const std::string& preset, int num_pairs, uint64_t seed) {
  SyntheticPairOptions o = *SyntheticPairPreset(preset);
  o.max_num_matches = std::min(o.max_num_matches, 600);
  return GenerateTwoViewSet(o, num_pairs, seed);
}

struct Counts {
  int measured = 0, within = 0;  // runs with depth corrections; those within 1.25x of the oracle's error
};

void Count(const PairResult& r, Counts* c) {
  if (!r.depth_err || !r.depth_err_oracle) return;
  ++c->measured;
  c->within += *r.depth_err <= 1.25 * *r.depth_err_oracle;
}

// 20 pairs of each planar preset, 2 seeds. The generator seeds 2024-2031 give 55/51, 58/53, 47/45, 57/57, 56/53,
// 59/50, 59/56 and 69/64 runs within 1.25x (on the bound / dropped): never fewer, one tie.
TEST(DepthFitInBound, PlanarDepthCorrectionsComeCloserToTheOracle) {
  const uint64_t gen_seed = 2024;
  Counts on, off;
  int changed = 0, runs = 0;
  const std::vector<std::pair<std::string, CameraMode>> presets = {
      {"hard_planar_calibrated", CameraMode::kCalibrated}, {"hard_planar_shared_focal", CameraMode::kSharedFocal}};
  for (const auto& [preset, mode] : presets) {
    for (const SyntheticPair& s : TestSet(preset, 20, gen_seed)) {
      PairData pair = s.pair;
      pair.gt_depth0 = s.true_depth_map0;
      pair.gt_depth1 = s.true_depth_map1;
      for (int seed = 0; seed < 2; ++seed) {
        HybridEstimatorOptions o;
        o.seed = seed;
        HybridEstimatorOptions dropped = o;
        dropped.depth_fit_regression_in_bound = false;
        const PairResult a = EvaluatePair(pair, mode, "hybrid", o);
        const PairResult b = EvaluatePair(pair, mode, "hybrid", dropped);
        Count(a, &on);
        Count(b, &off);
        ++runs;
        changed += a.model.shift0 != b.model.shift0 || a.model.shift1 != b.model.shift1;
      }
    }
  }
  std::printf("planar calibrated + shared focal (seed %llu), %d runs: depth corrections within 1.25x of the oracle's "
              "error on %d / %d runs with the regression on the bound, %d / %d with it dropped; %d runs changed\n",
              static_cast<unsigned long long>(gen_seed), runs, on.within, on.measured, off.within, off.measured,
              changed);
  EXPECT_EQ(on.measured, off.measured);
  EXPECT_GT(on.within, off.within);
}

}  // namespace
}  // namespace madsfm
