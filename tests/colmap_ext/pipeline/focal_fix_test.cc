// DecideFocalFix: when `madsfm mapper` repeats the seeded run with the trusted focal fixed. (a) low parallax: bundle
// adjustment moved it beyond 3 robust sigmas of the pairs over sqrt(pairs), at least 1%; (b) bundle adjustment
// determines it less well than the pairs (standard deviations) and moved it by more than the pairs' sigma.
#include <gtest/gtest.h>

#include <optional>

#include "colmap_ext/pipeline/mapper.h"

namespace madsfm {
namespace {

// 25 pairs with a robust spread (MAD of log f) of 1.5%: the pairs' sigma is 1.4826 x 1.5% / 5 = 0.445%.
FocalChange Estimate() {
  FocalChange c;
  c.camera_id = 1;
  c.updated = true;
  c.trusted = true;
  c.old_focal = 576.0;
  c.new_focal = 400.0;
  c.spread = 0.015;
  c.num_pairs = 25;
  return c;
}

std::optional<colmap::FocalUncertainty> Ba(double relative_sigma) {
  colmap::FocalUncertainty u;
  u.focal = 400.0;
  u.sigma = relative_sigma * 400.0;
  return u;
}

TEST(DecideFocalFix, LowParallaxRuleNeedsADriftBeyondOnePercent) {
  const FocalChange e = Estimate();
  const FocalFixDecision far = DecideFocalFix(e, 406.0, std::nullopt, true, false);  // 1.5% > max(1%, 0.9%)
  EXPECT_TRUE(far.fix);
  EXPECT_NEAR(far.drift, 0.015, 1e-12);
  EXPECT_NE(far.reason.find("low parallax"), std::string::npos);
  EXPECT_FALSE(DecideFocalFix(e, 403.0, std::nullopt, true, false).fix);   // 0.75%
  EXPECT_FALSE(DecideFocalFix(e, 406.0, std::nullopt, false, false).fix);  // rule off
}

TEST(DecideFocalFix, UncertainBundleAdjustmentGivesWayToThePairs) {
  const FocalChange e = Estimate();
  // Bundle adjustment's sigma 0.6% > the pairs' 0.445%, and it moved the focal by 0.75%: fixed.
  const FocalFixDecision d = DecideFocalFix(e, 403.0, Ba(0.006), false, true);
  EXPECT_TRUE(d.fix);
  EXPECT_NE(d.reason.find("determines the focal"), std::string::npos);
  // Moved by less than the pairs' sigma (0.25%): nothing to correct.
  EXPECT_FALSE(DecideFocalFix(e, 401.0, Ba(0.006), false, true).fix);
  // Bundle adjustment more precise than the pairs (0.3%): its value stands, however far it moved.
  EXPECT_FALSE(DecideFocalFix(e, 412.0, Ba(0.003), false, true).fix);
  // Its uncertainty unknown (model too large, unsupported camera) or the rule off: no rerun.
  EXPECT_FALSE(DecideFocalFix(e, 403.0, std::nullopt, false, true).fix);
  EXPECT_FALSE(DecideFocalFix(e, 403.0, Ba(0.006), false, false).fix);
}

TEST(DecideFocalFix, EitherRuleSuffices) {
  const FocalChange e = Estimate();
  // Low parallax with a precise bundle adjustment but a 1.5% drift: rule (a).
  EXPECT_TRUE(DecideFocalFix(e, 394.0, Ba(0.001), true, true).fix);
  // Low parallax with a 0.75% drift (below 1%) and an uncertain bundle adjustment: rule (b).
  EXPECT_TRUE(DecideFocalFix(e, 397.0, Ba(0.01), true, true).fix);
}

}  // namespace
}  // namespace madsfm
