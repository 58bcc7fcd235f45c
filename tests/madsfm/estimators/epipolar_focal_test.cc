// Focal modes: where the epipolar inliers determine the focal lengths to within epipolar_focal_max_sigma, the
// estimate takes theirs instead of the joint one, which smoothly distorted priors pull off by a few percent
// (HybridEstimatorOptions::epipolar_focal_max_sigma, Engine::TakeEpipolarFocal).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <vector>

#include "madsfm/estimators/pair_evaluation.h"
#include "madsfm/synthetic/two_view_scene.h"
#include "testing/median.h"

namespace madsfm {
namespace {

using testing::Median;

struct Outcome {
  double median_focal_err = 0.0;
  double median_pose_err = 0.0;
  int focal_better = 0, focal_worse = 0;  // pairs whose focal error moved by more than 0.5% of the focal
};

// Median focal and pose errors with the rule off (*off) and at its default (*on) over a set.
void Compare(const SyntheticPairOptions& preset, int count, uint64_t seed, CameraMode mode, Outcome* off,
             Outcome* on) {
  const auto set = GenerateTwoViewSet(preset, count, seed);
  std::vector<double> f_off, f_on, e_off, e_on;
  for (const SyntheticPair& s : set) {
    HybridEstimatorOptions o;
    ASSERT_GT(o.epipolar_focal_max_sigma, 0.0);
    const PairResult a = EvaluatePair(s.pair, mode, "hybrid", o);
    o.epipolar_focal_max_sigma = 0.0;
    const PairResult b = EvaluatePair(s.pair, mode, "hybrid", o);
    ASSERT_TRUE(a.focal_err && b.focal_err);
    f_on.push_back(*a.focal_err);
    f_off.push_back(*b.focal_err);
    e_on.push_back(std::max(*a.rot_err_deg, *a.trans_err_deg));
    e_off.push_back(std::max(*b.rot_err_deg, *b.trans_err_deg));
    if (*a.focal_err < *b.focal_err - 0.005) ++on->focal_better;
    if (*a.focal_err > *b.focal_err + 0.005) ++on->focal_worse;
  }
  off->median_focal_err = Median(f_off);
  on->median_focal_err = Median(f_on);
  off->median_pose_err = Median(e_off);
  on->median_pose_err = Median(e_on);
}

// Accurate matches (0.1-0.2 px, as SIFT on sharp images) and priors with a 15% smooth distortion: the joint focal
// follows the distortion, the epipolar one does not.
TEST(EpipolarFocal, AccurateMatchesSetTheFocalLengths) {
  for (const char* name : {"hard_indoor_shared_focal", "hard_indoor_two_focal"}) {
    SyntheticPairOptions preset = *SyntheticPairPreset(name);
    preset.min_pixel_noise = 0.1;
    preset.max_pixel_noise = 0.2;
    preset.prior.distortion = 0.15;
    preset.prior.max_distortion = 0.0;
    preset.max_num_matches = std::min(preset.max_num_matches, 800);
    const CameraMode mode = preset.camera_setup == SyntheticCameraSetup::kTwoFocal ? CameraMode::kTwoFocal
                                                                                  : CameraMode::kSharedFocal;
    Outcome off, on;
    Compare(preset, 30, 41, mode, &off, &on);
    std::printf("%s, 0.1-0.2 px: median focal error %.2f%% -> %.2f%% (%d pairs better, %d worse), median pose error "
                "%.2f -> %.2f deg\n",
                name, 100 * off.median_focal_err, 100 * on.median_focal_err, on.focal_better, on.focal_worse,
                off.median_pose_err, on.median_pose_err);
    EXPECT_LT(on.median_focal_err, 0.85 * off.median_focal_err) << name;
    EXPECT_GE(on.focal_better, 3 * std::max(1, on.focal_worse)) << name;
    EXPECT_LE(on.median_pose_err, off.median_pose_err * 1.05 + 0.02) << name;
  }
}

// Noisy matches (1-1.5 px): the epipolar focal is rarely precise enough to be taken, and the estimate stays as good.
TEST(EpipolarFocal, NoisyMatchesKeepTheJointFocalLengths) {
  SyntheticPairOptions preset = *SyntheticPairPreset("hard_indoor_shared_focal");
  preset.min_pixel_noise = 1.0;
  preset.max_pixel_noise = 1.5;
  preset.max_num_matches = std::min(preset.max_num_matches, 800);
  Outcome off, on;
  Compare(preset, 20, 43, CameraMode::kSharedFocal, &off, &on);
  std::printf("1-1.5 px: median focal error %.2f%% -> %.2f%% (%d pairs better, %d worse), median pose error %.2f -> "
              "%.2f deg\n",
              100 * off.median_focal_err, 100 * on.median_focal_err, on.focal_better, on.focal_worse,
              off.median_pose_err, on.median_pose_err);
  EXPECT_LE(on.focal_worse, 2);
  EXPECT_LE(on.median_focal_err, 1.1 * off.median_focal_err + 0.001);
  EXPECT_LE(on.median_pose_err, off.median_pose_err * 1.05 + 0.02);
}

// Pair 7 of the held-out hard_indoor_shared_focal set (`madsfm synth --seed 7`): its epipolar focal length is
// precise (deviation below 1%) and within 3 deviations of the joint one, but the Sampson-only pose slides 3 deg
// further from the truth (2.5 -> 5.4 deg when it was taken). A joint estimate the epipolar evidence does not reject
// is kept.
TEST(EpipolarFocal, JointFocalWithinTheEpipolarNoiseIsKept) {
  const auto set = GenerateTwoViewSet(*SyntheticPairPreset("hard_indoor_shared_focal"), 8, 7);
  const PairData& pair = set[7].pair;
  for (uint64_t seed : {0, 1, 2}) {
    HybridEstimatorOptions o;
    o.seed = seed;
    const PairResult on = EvaluatePair(pair, CameraMode::kSharedFocal, "hybrid", o);
    o.epipolar_focal_max_sigma = 0.0;
    const PairResult off = EvaluatePair(pair, CameraMode::kSharedFocal, "hybrid", o);
    const double e_on = std::max(*on.rot_err_deg, *on.trans_err_deg);
    const double e_off = std::max(*off.rot_err_deg, *off.trans_err_deg);
    std::printf("seed %d: pose error %.2f deg (rule off %.2f), focal error %.2f%% (%.2f%%)\n", static_cast<int>(seed),
                e_on, e_off, 100 * *on.focal_err, 100 * *off.focal_err);
    EXPECT_LE(e_on, e_off + 0.1);
  }
}

}  // namespace
}  // namespace madsfm
