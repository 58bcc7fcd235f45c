// HybridEstimate::sigma_focal0/1: the focal lengths' standard deviations at the final model with pose, scale and shifts
// free. focal_estimator lets a pair's focal count towards a prior only when it is small, so it has to (a) be
// finite and follow the actual error on ordinary pairs, (b) grow where the data leave the focal open (a small
// baseline with little rotation), and (c) be absent when nothing is estimated (calibrated).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "madsfm/estimators/estimate_relpose.h"
#include "madsfm/estimators/pair_evaluation.h"
#include "madsfm/synthetic/two_view_scene.h"
#include "testing/median.h"

namespace madsfm {
namespace {

struct SigmaSet {
  std::vector<double> sigma0, sigma1, error_over_sigma;
  int calibrated_nan = 0, runs = 0;
};

using testing::Median;

SigmaSet Estimate(const SyntheticPairOptions& options, CameraMode mode, uint64_t first_seed, int num_pairs) {
  SigmaSet out;
  for (int k = 0; k < num_pairs; ++k) {
    const SyntheticPair s = GenerateTwoViewPair(options, first_seed + k);
    const PairData& pair = s.pair;
    std::vector<double> d0, d1;
    SamplePairDepths(pair, &d0, &d1);
    const PinholeCamera cam0{pair.K0(0, 0), pair.K0(1, 1), pair.K0(0, 2), pair.K0(1, 2)};
    const PinholeCamera cam1{pair.K1(0, 0), pair.K1(1, 1), pair.K1(0, 2), pair.K1(1, 2)};
    HybridEstimatorOptions o;
    o.seed = k;
    const HybridEstimate est = EstimateRelativePose(mode, pair.p0, pair.p1, d0, d1, cam0, cam1, o);
    if (!est.success) continue;
    ++out.runs;
    if (mode == CameraMode::kCalibrated) {
      out.calibrated_nan += std::isnan(est.sigma_focal0) && std::isnan(est.sigma_focal1);
      continue;
    }
    if (!(est.sigma_focal0 > 0.0) || !(est.sigma_focal1 > 0.0)) continue;  // counted as missing below
    out.sigma0.push_back(est.sigma_focal0);
    out.sigma1.push_back(est.sigma_focal1);
    out.error_over_sigma.push_back(std::abs(est.model.f0 / s.focal0 - 1.0) / est.sigma_focal0);
  }
  return out;
}

TEST(FocalSigma, FollowsTheErrorOnOrdinaryPairsAndIsAbsentWhenCalibrated) {
  const SyntheticPairOptions shared = *SyntheticPairPreset("hard_indoor_shared_focal");
  const SigmaSet s = Estimate(shared, CameraMode::kSharedFocal, 700, 30);
  std::printf("shared focal, baselines 5-30%%: %zu of %d with sigma, median sigma %.3f%%, median |err| / sigma %.2f\n",
              s.sigma0.size(), s.runs, 100 * Median(s.sigma0), Median(s.error_over_sigma));
  ASSERT_GE(s.runs, 28);
  EXPECT_EQ(static_cast<int>(s.sigma0.size()), s.runs);
  for (size_t i = 0; i < s.sigma0.size(); ++i) EXPECT_EQ(s.sigma0[i], s.sigma1[i]);  // one focal
  EXPECT_LT(Median(s.sigma0), 0.02);
  // A standard deviation, not an arbitrary number: the typical error is of its order (a normal error has a median
  // |err| / sigma of 0.67; the priors' distortion adds a bias the sigma does not know of).
  EXPECT_GT(Median(s.error_over_sigma), 0.2);
  EXPECT_LT(Median(s.error_over_sigma), 5.0);

  const SigmaSet two = Estimate(*SyntheticPairPreset("hard_indoor_two_focal"), CameraMode::kTwoFocal, 700, 20);
  ASSERT_GE(two.runs, 18);
  EXPECT_EQ(static_cast<int>(two.sigma0.size()), two.runs);
  int differ = 0;
  for (size_t i = 0; i < two.sigma0.size(); ++i) differ += two.sigma0[i] != two.sigma1[i];
  EXPECT_GE(differ, two.runs * 9 / 10);  // one per focal

  const SigmaSet calib = Estimate(*SyntheticPairPreset("hard_indoor_calibrated"), CameraMode::kCalibrated, 700, 10);
  ASSERT_GE(calib.runs, 9);
  EXPECT_EQ(calib.calibrated_nan, calib.runs);
}

TEST(FocalSigma, GrowsWhereASmallBaselineLeavesTheFocalOpen) {
  SyntheticPairOptions wide = *SyntheticPairPreset("hard_indoor_shared_focal");
  wide.max_rotation_deg = 20.0;
  SyntheticPairOptions small = wide;
  small.baseline_min = small.baseline_max = 0.01;  // 1% of the depth
  small.max_rotation_deg = 2.0;
  const SigmaSet w = Estimate(wide, CameraMode::kSharedFocal, 800, 20);
  const SigmaSet n = Estimate(small, CameraMode::kSharedFocal, 800, 20);
  std::printf("median focal sigma: baselines 5-30%% %.3f%%, baseline 1%% with <= 2 deg of rotation %.3f%%\n",
              100 * Median(w.sigma0), 100 * Median(n.sigma0));
  ASSERT_GE(w.sigma0.size(), 18u);
  ASSERT_GE(n.sigma0.size(), 15u);
  EXPECT_GT(Median(n.sigma0), 3.0 * Median(w.sigma0));
}

}  // namespace
}  // namespace madsfm
