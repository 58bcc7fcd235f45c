// HybridEstimatorOptions::focal_depth_from_joint: in the focal modes the depth corrections are fitted to the joint
// estimate (the pose and focal lengths the priors and the matches agreed on) before the last, epipolar-only refinement
// moves the pose with the focal lengths held. Outdoors, where the far points' triangulated depths follow every small
// change of the translation's direction, the corrections then come closer to the oracle, and the pose stays the
// refined one (docs/benchmarks.md section 11, update of 2026-12-08).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "madsfm/estimators/pair_evaluation.h"
#include "madsfm/synthetic/two_view_scene.h"

namespace madsfm {
namespace {

// At most 600 matches per pair (the preset draws up to 2000): the same scenes at a test suite's cost.
std::vector<SyntheticPair> OutdoorSharedFocalSet(int num_pairs, uint64_t seed) {
  SyntheticPairOptions o = *SyntheticPairPreset("hard_outdoor_shared_focal");
  o.max_num_matches = std::min(o.max_num_matches, 600);
  return GenerateTwoViewSet(o, num_pairs, seed);
}

// 40 pairs, 2 seeds each. The score is the geometric mean over the runs of the depth corrections' error relative to
// the oracle's (1: as close as the best per-view affine fit to the true depths). The generator seeds 2024-2031 give
// 1.22 / 1.35, 1.10 / 1.26, 1.26 / 1.50, 1.27 / 1.31, 1.16 / 1.23, 1.47 / 1.58, 1.16 / 1.21 and 1.19 / 1.23 (fitted to
// the joint estimate / to the final pose), with the same rotation, translation direction and focal length in 76-80
// of the 80 runs (elsewhere the scale-only fallback is tried or not: it is tried where the corrections are not
// observable). The share of runs within 1.25x of the oracle moves less evenly on sets this small: the gain comes from
// a few pairs whose far points the final pose triangulates badly.
TEST(FocalDepthFromJoint, OutdoorSharedFocalDepthCorrectionsComeCloserToTheOracle) {
  const uint64_t gen_seed = 2024;
  int runs = 0, same_pose = 0;
  double log_ratio_joint = 0.0, log_ratio_final = 0.0;
  for (const SyntheticPair& s : OutdoorSharedFocalSet(40, gen_seed)) {
    PairData pair = s.pair;
    pair.gt_depth0 = s.true_depth_map0;
    pair.gt_depth1 = s.true_depth_map1;
    for (int seed = 0; seed < 2; ++seed) {
      HybridEstimatorOptions joint;
      joint.seed = seed;
      HybridEstimatorOptions final_pose = joint;
      final_pose.focal_depth_from_joint = false;
      const PairResult a = EvaluatePair(pair, CameraMode::kSharedFocal, "hybrid", joint);
      const PairResult b = EvaluatePair(pair, CameraMode::kSharedFocal, "hybrid", final_pose);
      ASSERT_TRUE(a.depth_err && a.depth_err_oracle && b.depth_err && b.depth_err_oracle);
      ++runs;
      log_ratio_joint += std::log(*a.depth_err / *a.depth_err_oracle);
      log_ratio_final += std::log(*b.depth_err / *b.depth_err_oracle);
      same_pose += a.model.R.isApprox(b.model.R, 1e-12) && a.model.f0 == b.model.f0 &&
                   a.model.t.normalized().isApprox(b.model.t.normalized(), 1e-12);
    }
  }
  const double joint_score = std::exp(log_ratio_joint / runs), final_score = std::exp(log_ratio_final / runs);
  std::printf("outdoor shared focal (generator seed %llu), %d runs: depth corrections' error / the oracle's, geometric "
              "mean: %.3f fitted to the joint estimate, %.3f fitted to the final pose; same pose on %d runs\n",
              static_cast<unsigned long long>(gen_seed), runs, joint_score, final_score, same_pose);
  EXPECT_LT(joint_score, final_score);
  EXPECT_GE(same_pose, runs * 9 / 10);
}

}  // namespace
}  // namespace madsfm
