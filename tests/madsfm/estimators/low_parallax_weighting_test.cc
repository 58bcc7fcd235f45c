// HybridEstimatorOptions::low_parallax_sampson_factor: a lower Sampson weight where the best model shows little
// parallax, and low_parallax_final_reprojection_weight: depth terms in the last refinement of such calibrated pairs,
// on fixed-seed synthetic sets (src/madsfm/synthetic) with noise, outliers and monocular-depth-like priors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "madsfm/estimators/pair_evaluation.h"
#include "madsfm/geometry/pose_error.h"
#include "madsfm/synthetic/two_view_scene.h"

namespace madsfm {
namespace {

// At most 600 matches per pair (the hard presets draw up to 2000): the same scenes at a test suite's cost.
std::vector<SyntheticPair> TestSet(const std::string& preset, int num_pairs) {
  SyntheticPairOptions o = *SyntheticPairPreset(preset);
  o.max_num_matches = std::min(o.max_num_matches, 600);
  return GenerateTwoViewSet(o, num_pairs, 2024);
}

constexpr int kSeeds = 3;

struct SetResult {
  double auc10 = 0.0;
  int weighted = 0;  // runs with the low-parallax weighting
  int depth_measured = 0, depth_within_125 = 0;  // runs with depth corrections; those within 1.25x of the oracle's
};

SetResult RunSet(const std::vector<SyntheticPair>& set, CameraMode mode, double factor,
                 double final_reprojection_weight = HybridEstimatorOptions().low_parallax_final_reprojection_weight,
                 bool depth_from_triangulation = true) {
  SetResult out;
  std::vector<double> errors;
  for (const SyntheticPair& s : set) {
    for (int seed = 0; seed < kSeeds; ++seed) {
      HybridEstimatorOptions o;
      o.seed = seed;
      o.low_parallax_sampson_factor = factor;
      o.low_parallax_final_reprojection_weight = final_reprojection_weight;
      o.mixed_refinement_depth_from_triangulation = depth_from_triangulation;
      PairData pair = s.pair;
      pair.gt_depth0 = s.true_depth_map0;  // for the depth-correction errors
      pair.gt_depth1 = s.true_depth_map1;
      const PairResult r = EvaluatePair(pair, mode, "hybrid", o);
      const double t = *r.trans_err_deg;
      errors.push_back(std::max(*r.rot_err_deg, std::min(t, 180.0 - t)));
      out.weighted += r.low_parallax_weighting;
      if (r.depth_err && r.depth_err_oracle) {
        ++out.depth_measured;
        out.depth_within_125 += *r.depth_err <= 1.25 * *r.depth_err_oracle;
      }
    }
  }
  out.auc10 = PoseAuc(errors, {10.0})[0];
  return out;
}

// Baselines of 0.5-3% of the depth: the weighting is taken on most runs and raises the accuracy of the set. Measured
// (40 pairs x 3 seeds, at most 600 matches): AUC@10 25.9 vs 24.3 calibrated (25.5 without the depth terms in the last
// refinement), 34.5 vs 25.9 shared focal (30.1 before its last refinement kept depth terms); taken on 114 and 109 of
// 120 runs. With all matches the gain is 4-5 AUC@10 (docs/benchmarks.md section 11).
TEST(LowParallaxWeighting, RaisesLowParallaxAccuracy) {
  for (const auto& [preset, mode] : {std::pair<const char*, CameraMode>{"hard_low_parallax_calibrated",
                                                                        CameraMode::kCalibrated},
                                     {"hard_low_parallax_shared_focal", CameraMode::kSharedFocal}}) {
    const auto set = TestSet(preset, 40);
    const SetResult on = RunSet(set, mode, 0.35), off = RunSet(set, mode, 1.0);
    std::printf("%s: AUC@10 %.1f with the low-parallax weighting (taken on %d of %zu runs), %.1f without\n", preset,
                100 * on.auc10, on.weighted, kSeeds * set.size(), 100 * off.auc10);
    EXPECT_EQ(off.weighted, 0);
    EXPECT_GE(on.weighted, static_cast<int>(kSeeds * set.size() * 8 / 10));
    EXPECT_GT(on.auc10, off.auc10);
  }
}

// Calibrated low-parallax pairs that take the switch: the epipolar-only last refinement lets the translation's
// direction slide along the flat epipolar cost; with the depth terms kept at 0.3 it slides less. Measured (the set of
// RaisesLowParallaxAccuracy, 40 pairs x 3 seeds): AUC@10 25.9 with them, 25.5 without. It was 27.1 while the depth
// corrections started from the joint refinement's values (see the next test); on the sweep sets every pose that
// changed with that did so through the scale-only fallback, which the depth parameters' deviations trigger. With all
// matches +0.6 and +1.0 on the two synthetic sets; rendered pairs with real SIFT at 0.05 and 0.2 px: +6.5 and +8.6
// (docs/benchmarks.md section 11, updates of 2026-12-07).
TEST(LowParallaxWeighting, DepthTermsInTheLastRefinementRaiseCalibratedAccuracy) {
  const auto set = TestSet("hard_low_parallax_calibrated", 40);
  const double off_weight = HybridEstimatorOptions().final_reprojection_weight;
  const SetResult on = RunSet(set, CameraMode::kCalibrated, 0.35),
                  off = RunSet(set, CameraMode::kCalibrated, 0.35, off_weight);
  std::printf("hard_low_parallax_calibrated: AUC@10 %.1f with depth terms in the last refinement, %.1f without; "
              "depth corrections within 1.25x of the oracle's error on %d / %d and %d / %d runs\n",
              100 * on.auc10, 100 * off.auc10, on.depth_within_125, on.depth_measured, off.depth_within_125,
              off.depth_measured);
  EXPECT_GT(on.auc10, off.auc10);
}

// The depth corrections after that refinement start from the fit of the priors to the triangulated epipolar inliers,
// not from the joint refinement's scale and shifts, which drift along the flat directions of a small baseline
// (HybridEstimatorOptions::mixed_refinement_depth_from_triangulation), compared on the same runs. Measured on this set
// (the held-out set of docs/benchmarks.md section 11: seed 7, all matches), corrections within 1.25x of the oracle's
// error: 53 against 45 of these 120 runs; over 30 seeds 46.0% against 41.2%, more in each of the ten 3-seed windows
// (by 1-8 runs of 120). The share itself moves by 50-59 of 120 between 3-seed windows, so it is not asserted.
TEST(LowParallaxWeighting, DepthCorrectionsAfterTheMixedLastRefinementStartFromTheTriangulation) {
  const auto set = GenerateTwoViewSet(*SyntheticPairPreset("hard_low_parallax_calibrated"), 40, 7);
  const double weight = HybridEstimatorOptions().low_parallax_final_reprojection_weight;
  const SetResult on = RunSet(set, CameraMode::kCalibrated, 0.35, weight, true),
                  off = RunSet(set, CameraMode::kCalibrated, 0.35, weight, false);
  std::printf("held-out hard_low_parallax_calibrated: depth corrections within 1.25x of the oracle's error on %d / %d "
              "runs from the triangulation fit, %d / %d from the refinement's values\n", on.depth_within_125,
              on.depth_measured, off.depth_within_125, off.depth_measured);
  EXPECT_EQ(on.depth_measured, static_cast<int>(kSeeds * set.size()));
  EXPECT_EQ(off.depth_measured, on.depth_measured);
  EXPECT_GT(on.depth_within_125, off.depth_within_125);
}

// After the switch the depth corrections are the reprojection fit's: the regression of the triangulated depths on the
// priors (depth_fit_regression) is skipped, as if it were off; low_parallax_depth_fit_regression takes it there too,
// which changes some of these runs. Measured on the four low-parallax sets of docs/benchmarks.md section 11 (10 seeds,
// seed offset 0): corrections within 1.25x of the oracle's error on 47.0% of the runs without the regression there,
// 44.1% with it (30 reweighting rounds).
TEST(LowParallaxWeighting, NoDepthRegressionAfterTheSwitch) {
  const auto set = TestSet("hard_low_parallax_calibrated", 10);
  int weighted = 0, same_as_off = 0, changed_with_regression = 0;
  for (const SyntheticPair& s : set) {
    for (int seed = 0; seed < kSeeds; ++seed) {
      HybridEstimatorOptions o;
      o.seed = seed;
      HybridEstimatorOptions no_regression = o, regression_there = o;
      no_regression.depth_fit_regression = false;
      regression_there.low_parallax_depth_fit_regression = true;
      const PairResult r = EvaluatePair(s.pair, CameraMode::kCalibrated, "hybrid", o);
      if (!r.success || !r.low_parallax_weighting) continue;
      ++weighted;
      const PairResult a = EvaluatePair(s.pair, CameraMode::kCalibrated, "hybrid", no_regression);
      const PairResult b = EvaluatePair(s.pair, CameraMode::kCalibrated, "hybrid", regression_there);
      same_as_off += a.model.scale == r.model.scale && a.model.shift0 == r.model.shift0 &&
                     a.model.shift1 == r.model.shift1 && a.model.t == r.model.t;
      changed_with_regression += b.model.scale != r.model.scale || b.model.shift0 != r.model.shift0 ||
                                 b.model.shift1 != r.model.shift1;
    }
  }
  std::printf("hard_low_parallax_calibrated: %d runs with the switch; depth corrections the same as without the "
              "regression on %d, changed by the regression there on %d\n", weighted, same_as_off,
              changed_with_regression);
  EXPECT_GE(weighted, static_cast<int>(kSeeds * set.size() / 2));
  EXPECT_EQ(same_as_off, weighted);
  EXPECT_GT(changed_with_regression, 0);
}

// Ordinary baselines: the weighting is rarely taken (measured: 0 of 60 runs), and without it the search is the same.
TEST(LowParallaxWeighting, RarelyTakenWithOrdinaryParallax) {
  const auto set = TestSet("hard_outdoor_calibrated", 20);
  const SetResult on = RunSet(set, CameraMode::kCalibrated, 0.35), off = RunSet(set, CameraMode::kCalibrated, 1.0);
  std::printf("hard_outdoor_calibrated: low-parallax weighting taken on %d of %zu runs; AUC@10 %.1f vs %.1f\n",
              on.weighted, kSeeds * set.size(), 100 * on.auc10, 100 * off.auc10);
  EXPECT_LE(on.weighted, static_cast<int>(kSeeds * set.size() / 10));
  if (on.weighted == 0) {
    EXPECT_EQ(on.auc10, off.auc10);
  }
}

}  // namespace
}  // namespace madsfm
