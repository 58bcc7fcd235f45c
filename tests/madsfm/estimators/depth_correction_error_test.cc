// MeasureDepthCorrection: the depth-correction error bench reports (issue 12) against exact and perturbed models.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "madsfm/estimators/pair_evaluation.h"

namespace madsfm {
namespace {

// Priors d = (z - b) / a per view for true depths z.
struct Data {
  std::vector<double> d0, d1, z0, z1;
  std::vector<char> use;
};

Data MakeData(double a0, double b0, double a1, double b1) {
  Data data;
  for (int i = 0; i < 50; ++i) {
    const double z0 = 1.0 + 0.1 * i, z1 = 1.5 + 0.07 * i;
    data.z0.push_back(z0);
    data.z1.push_back(z1);
    data.d0.push_back((z0 - b0) / a0);
    data.d1.push_back((z1 - b1) / a1);
    data.use.push_back(1);
  }
  return data;
}

TEST(DepthCorrectionError, ExactCorrectionsHaveNoErrorAtAnyGauge) {
  const double a0 = 2.0, b0 = 0.3, a1 = 0.5, b1 = -0.2;
  const Data data = MakeData(a0, b0, a1, b1);
  // The model's convention: z_hat0 = d0 + shift0, z_hat1 = scale (d1 + shift1), up to one common factor.
  // A model in other depth units (priors scaled by k, shifts by k) is the same correction up to the gauge.
  for (const double k : {1.0, 0.01, 37.0}) {
    Data scaled = data;
    for (double& v : scaled.d0) v *= k;
    for (double& v : scaled.d1) v *= k;
    AffineDepthPose m;
    m.shift0 = k * b0 / a0;
    m.scale = a1 / a0;
    m.shift1 = k * b1 / a1;
    const auto e = MeasureDepthCorrection(m, scaled.d0, scaled.d1, scaled.z0, scaled.z1, scaled.use);
    ASSERT_TRUE(e.has_value());
    EXPECT_EQ(e->support, 50);
    EXPECT_LT(e->estimate, 1e-12);
    EXPECT_LT(e->oracle, 1e-12);
  }
}

TEST(DepthCorrectionError, WrongShiftShowsUpAndTheOracleDoesNot) {
  const Data data = MakeData(1.0, 0.5, 1.0, 0.5);
  AffineDepthPose m;  // scale 1, shifts 0: misses the shift of 0.5 in both views
  const auto e = MeasureDepthCorrection(m, data.d0, data.d1, data.z0, data.z1, data.use);
  ASSERT_TRUE(e.has_value());
  EXPECT_GT(e->estimate, 0.02);
  EXPECT_LT(e->oracle, 1e-12);
}

TEST(DepthCorrectionError, OnlyUsableMatchesCountAndTooFewGiveNothing) {
  Data data = MakeData(1.0, 0.0, 1.0, 0.0);
  for (size_t i = 0; i < data.use.size(); ++i) data.use[i] = i < 7;
  EXPECT_FALSE(MeasureDepthCorrection(AffineDepthPose(), data.d0, data.d1, data.z0, data.z1, data.use).has_value());
  for (size_t i = 0; i < data.use.size(); ++i) data.use[i] = 1;
  data.z1[3] = std::nan("");  // unknown true depth
  data.d0[4] = std::nan("");  // no prior
  const auto e = MeasureDepthCorrection(AffineDepthPose(), data.d0, data.d1, data.z0, data.z1, data.use);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->support, 48);
}

}  // namespace
}  // namespace madsfm
