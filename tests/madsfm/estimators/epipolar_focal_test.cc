// Focal modes: where the epipolar inliers determine the focal lengths to within epipolar_focal_max_sigma, the
// estimate takes theirs instead of the joint one, which smoothly distorted priors pull off by a few percent
// (HybridEstimatorOptions::epipolar_focal_max_sigma, Engine::TakeEpipolarFocal); two focal lengths only where the
// depth priors do not reject them (most of a view's depth inliers lost).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "madsfm/estimators/estimate_relpose.h"
#include "madsfm/estimators/pair_evaluation.h"
#include "madsfm/geometry/pose_error.h"
#include "madsfm/synthetic/scene_primitives.h"
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

// Two cameras on an arc around a target, both looking at it: their optical axes meet, where the fundamental matrix
// does not determine two focal lengths (Bougnoux's formula is singular). Points in a box around the target, 0.3 px
// noise, 20% outliers, priors with their own scale and shift per view and a 6% smooth distortion. The Sampson-only
// refinement can slide along the flat valley to focal lengths 2-3x too long whose deviation still looks precise;
// the depth priors reject such a move outright (most depth inliers lost), and the estimate keeps the joint focal
// lengths (rendered arc pair of docs/benchmarks.md section 11, update of 2026-12-07 (morning)). Measured: 0 of 300
// scenes > 5 deg, as with the epipolar focal lengths off; 7 of 300 when the move was taken whatever the depth said.
struct ArcScene {
  std::vector<Eigen::Vector2d> p0, p1;
  std::vector<double> d0, d1;
  double f0 = 0, f1 = 0;
  Eigen::Matrix3d R;  // X1 = R X0 + t
  Eigen::Vector3d t;
};

Eigen::Matrix3d LookAt(const Eigen::Vector3d& c, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - c).normalized();
  const Eigen::Vector3d x = Eigen::Vector3d(0, -1, 0).cross(z).normalized();
  Eigen::Matrix3d R;  // world -> camera
  R.row(0) = x;
  R.row(1) = z.cross(x);
  R.row(2) = z;
  return R;
}

ArcScene MakeArcScene(uint64_t seed) {
  synthetic::Rng rng(seed);
  const double w = 640, h = 480, radius = 4.0;
  ArcScene s;
  s.f0 = rng.Uniform(300, 650);
  s.f1 = rng.Uniform(300, 650);
  const double a1 = rng.Uniform(0.15, 0.5) * (rng.Uniform() < 0.5 ? -1.0 : 1.0);
  const Eigen::Vector3d c0(0, 0, -radius);
  const Eigen::Vector3d c1(radius * std::sin(a1), 0.05 * rng.Normal(), -radius * std::cos(a1));
  const Eigen::Matrix3d R0 = LookAt(c0, Eigen::Vector3d::Zero()), R1 = LookAt(c1, Eigen::Vector3d::Zero());
  s.R = R1 * R0.transpose();
  s.t = R1 * (c0 - c1);
  const double kNoise = 0.3;
  const double k_scale0 = 2.0, k_shift0 = 0.5, k_scale1 = 0.7, k_shift1 = -0.3, distortion = 0.06;
  for (int i = 0; i < 4000 && s.p0.size() < 800; ++i) {
    const Eigen::Vector3d X(rng.Uniform(-3, 3), rng.Uniform(-2, 2), rng.Uniform(-1, 3));
    const Eigen::Vector3d X0 = R0 * (X - c0), X1 = R1 * (X - c1);
    if (!(X0.z() > 0.3) || !(X1.z() > 0.3)) continue;
    const Eigen::Vector2d q0 = s.f0 * X0.head<2>() / X0.z() + Eigen::Vector2d(w / 2, h / 2);
    const Eigen::Vector2d q1 = s.f1 * X1.head<2>() / X1.z() + Eigen::Vector2d(w / 2, h / 2);
    if (q0.x() < 0 || q0.x() >= w || q0.y() < 0 || q0.y() >= h || q1.x() < 0 || q1.x() >= w || q1.y() < 0 ||
        q1.y() >= h) {
      continue;
    }
    s.d0.push_back(k_scale0 * X0.z() * (1.0 + distortion * std::sin(q0.x() / 150.0)) + k_shift0);
    s.d1.push_back(k_scale1 * X1.z() * (1.0 + distortion * std::cos(q1.y() / 130.0)) + k_shift1);
    s.p0.push_back(q0 + kNoise * Eigen::Vector2d(rng.Normal(), rng.Normal()));
    s.p1.push_back(rng.Uniform() < 0.2 ? Eigen::Vector2d(rng.Uniform(0, w), rng.Uniform(0, h))
                                       : Eigen::Vector2d(q1 + kNoise * Eigen::Vector2d(rng.Normal(), rng.Normal())));
  }
  return s;
}

TEST(EpipolarFocal, TwoFocalMoveTheDepthPriorsRejectIsRefused) {
  const PinholeCamera camera{1.0, 1.0, 320.0, 240.0};
  int failed_on = 0, failed_off = 0, focal_off_on = 0, focal_off_off = 0;
  const int count = 300;
  for (int k = 0; k < count; ++k) {
    const ArcScene s = MakeArcScene(1000 + k);
    ASSERT_GE(s.p0.size(), 300u);
    HybridEstimatorOptions o;
    o.reproj_threshold = 16.0;  // madpose's two-focal thresholds
    o.epipolar_threshold = 1.0;
    const HybridEstimate on =
        EstimateRelativePose(CameraMode::kTwoFocal, s.p0, s.p1, s.d0, s.d1, camera, camera, o, 640);
    o.epipolar_focal_max_sigma = 0.0;
    const HybridEstimate off =
        EstimateRelativePose(CameraMode::kTwoFocal, s.p0, s.p1, s.d0, s.d1, camera, camera, o, 640);
    ASSERT_TRUE(on.success && off.success);
    auto pose_err = [&](const HybridEstimate& e) {
      return std::max(RotationErrorDeg(e.model.R, s.R), TranslationErrorDeg(e.model.t, s.t));
    };
    auto focal_err = [&](const HybridEstimate& e) {
      return std::max(std::abs(e.model.f0 - s.f0) / s.f0, std::abs(e.model.f1 - s.f1) / s.f1);
    };
    failed_on += pose_err(on) > 5.0;
    failed_off += pose_err(off) > 5.0;
    focal_off_on += focal_err(on) > 0.5;
    focal_off_off += focal_err(off) > 0.5;
  }
  std::printf("%d arc scenes: pose error > 5 deg %d (epipolar focal lengths off: %d), focal error > 50%% %d (%d)\n",
              count, failed_on, failed_off, focal_off_on, focal_off_off);
  EXPECT_LE(failed_on, failed_off + 2);
  EXPECT_LE(focal_off_on, focal_off_off + 2);
}

}  // namespace
}  // namespace madsfm
