// The last refinement's Cauchy loss (HybridEstimatorOptions::final_cauchy_ratio, scale = ratio x the epipolar
// inliers' robust noise level). Real matches (SIFT) are accurate with a tail of mislocalised ones that the 2 px
// threshold still admits; least squares lets that tail pull the pose, most of all the translation direction of a
// small baseline. With matches of 0.15 px plus 15% displaced by 0.7-1.8 px, the robust refinement must lower the
// pose error on most pairs, for the hybrid and the point method; with uniformly noisy matches (0.5-1.5 px, the
// synthetic presets) it must not cost accuracy.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "madsfm/estimators/pair_evaluation.h"
#include "madsfm/synthetic/two_view_scene.h"
#include "testing/median.h"

namespace madsfm {
namespace {

using testing::Median;

struct Comparison {
  int better = 0, worse = 0, total = 0;  // pairs whose pose error moved by more than 10% (and 0.02 deg)
  double median_ls = 0.0, median_cauchy = 0.0;
  // Focal modes: median focal error (relative, the worse of f0 / f1) and pairs whose focal error moved by more than
  // 10% (and 0.05%).
  double median_focal_ls = 0.0, median_focal_cauchy = 0.0;
  int focal_better = 0, focal_worse = 0;
};

Comparison Compare(const std::vector<SyntheticPair>& set, CameraMode mode, const char* method) {
  Comparison c;
  std::vector<double> ls, cauchy, focal_ls, focal_cauchy;
  for (const SyntheticPair& s : set) {
    HybridEstimatorOptions o;
    o.final_cauchy_ratio = 2.0;
    const PairResult a = EvaluatePair(s.pair, mode, method, o);
    o.final_cauchy_ratio = 0.0;
    const PairResult b = EvaluatePair(s.pair, mode, method, o);
    if (!a.success || !b.success) continue;
    const double ea = std::max(*a.rot_err_deg, *a.trans_err_deg), eb = std::max(*b.rot_err_deg, *b.trans_err_deg);
    cauchy.push_back(ea);
    ls.push_back(eb);
    ++c.total;
    if (ea < eb - std::max(0.02, 0.1 * eb)) ++c.better;
    if (ea > eb + std::max(0.02, 0.1 * eb)) ++c.worse;
    if (mode == CameraMode::kCalibrated) continue;
    const double fa = *a.focal_err, fb = *b.focal_err;
    focal_cauchy.push_back(fa);
    focal_ls.push_back(fb);
    if (fa < fb - std::max(5e-4, 0.1 * fb)) ++c.focal_better;
    if (fa > fb + std::max(5e-4, 0.1 * fb)) ++c.focal_worse;
  }
  c.median_ls = Median(ls);
  c.median_cauchy = Median(cauchy);
  if (!focal_ls.empty()) {
    c.median_focal_ls = Median(focal_ls);
    c.median_focal_cauchy = Median(focal_cauchy);
  }
  return c;
}

// Accurate matches with a tail inside the threshold: every inlier of the generator gets 0.15 px of noise, then 15%
// of them are moved by 0.7-1.8 px in a random direction (fixed seed).
std::vector<SyntheticPair> AccurateWithATail(const char* preset_name, int count, uint64_t seed) {
  SyntheticPairOptions preset = *SyntheticPairPreset(preset_name);
  preset.min_pixel_noise = preset.max_pixel_noise = 0.15;
  std::vector<SyntheticPair> set = GenerateTwoViewSet(preset, count, seed);
  std::mt19937 rng(static_cast<uint32_t>(seed));
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (SyntheticPair& s : set) {
    for (size_t i = 0; i < s.pair.p1.size(); ++i) {
      if (!s.is_inlier[i] || u(rng) >= 0.15) continue;
      const double angle = 2.0 * M_PI * u(rng), r = 0.7 + 1.1 * u(rng);
      s.pair.p1[i] += Eigen::Vector2d(r * std::cos(angle), r * std::sin(angle));
    }
  }
  return set;
}

TEST(FinalCauchy, MislocalisedMatchesPullLess) {
  const std::vector<SyntheticPair> set = AccurateWithATail("hard_indoor_calibrated", 30, 910);
  for (const char* method : {"hybrid", "points"}) {
    const Comparison c = Compare(set, CameraMode::kCalibrated, method);
    std::printf("%s, 0.15 px + 15%% at 0.7-1.8 px: median pose error %.3f -> %.3f deg, %d better, %d worse of %d\n",
                method, c.median_ls, c.median_cauchy, c.better, c.worse, c.total);
    ASSERT_GE(c.total, 28);
    EXPECT_LT(c.median_cauchy, 0.8 * c.median_ls);
    EXPECT_GE(c.better, 2 * c.worse);  // at least twice as many pairs improve as get worse
  }
}

// The focal lengths of the epipolar evidence (taken where it determines them and rejects the joint ones) come from
// the same robust refinement: with a tail of mislocalised matches, least squares lets the tail bias them too.
TEST(FinalCauchy, EpipolarFocalLengthsPulledLess) {
  const std::vector<SyntheticPair> set = AccurateWithATail("hard_indoor_shared_focal", 60, 930);
  const Comparison c = Compare(set, CameraMode::kSharedFocal, "hybrid");
  std::printf("hybrid, shared focal, 0.15 px + 15%% at 0.7-1.8 px: median focal error %.3f%% -> %.3f%%, %d better, "
              "%d worse of %d\n",
              100 * c.median_focal_ls, 100 * c.median_focal_cauchy, c.focal_better, c.focal_worse, c.total);
  ASSERT_GE(c.total, 57);
  EXPECT_LT(c.median_focal_cauchy, 0.9 * c.median_focal_ls);
  EXPECT_GE(c.focal_better, 2 * c.focal_worse);
}

// 120 pairs: whether the Cauchy loss moves a pair's error by 10% is close to a coin flip under uniform noise. With 30
// pairs the count of worse minus better pairs (bound 5) varied between ten 30-pair windows of the same generator (300
// pairs, seed 920) by -3 to +7 before "madsfm-21" and by -1 to +6 with it; over those 300 pairs it is 17 (hybrid) and
// 19 (points), 11 and 11 before, against the bound 50 (docs/benchmarks.md section 11, update of 2026-12-07, evening).
TEST(FinalCauchy, UniformNoiseCostsNothing) {
  const std::vector<SyntheticPair> set = GenerateTwoViewSet(*SyntheticPairPreset("hard_indoor_calibrated"), 120, 920);
  for (const char* method : {"hybrid", "points"}) {
    const Comparison c = Compare(set, CameraMode::kCalibrated, method);
    std::printf("%s, 0.5-1.5 px: median pose error %.3f -> %.3f deg, %d better, %d worse of %d\n", method,
                c.median_ls, c.median_cauchy, c.better, c.worse, c.total);
    ASSERT_GE(c.total, 112);
    EXPECT_LT(c.median_cauchy, 1.1 * c.median_ls);
    EXPECT_LE(c.worse, c.better + c.total / 6);
  }
}

}  // namespace
}  // namespace madsfm
