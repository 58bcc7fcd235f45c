#include "madsfm/estimators/hybrid_sampling.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

namespace madsfm {
namespace {

TEST(HybridSampling, RequiredIterationsMatchesTheClassicFormula) {
  // One solver, inlier ratio 0.5, sample size 3: P = 1/8, n = log(0.01) / log(7/8) = 34.5 -> 35.
  EXPECT_EQ(RequiredIterations({1.0}, {AllInlierProbability(0.5, 3)}, 0.99, 100000), 35);
  // Two solvers drawn half/half with P = 1/8 and P = 1/32: success per iteration = (1/8 + 1/32)/2.
  const double s = 0.5 * (1.0 / 8 + 1.0 / 32);
  EXPECT_EQ(RequiredIterations({0.5, 0.5}, {1.0 / 8, 1.0 / 32}, 0.99, 100000),
            static_cast<int>(std::ceil(std::log(0.01) / std::log(1 - s))));
  // No support yet: the cap.
  EXPECT_EQ(RequiredIterations({0.5, 0.5}, {0.0, 0.0}, 0.99, 1234), 1234);
  // All inliers: one iteration.
  EXPECT_EQ(RequiredIterations({1.0}, {1.0}, 0.99, 1234), 1);
}

TEST(HybridSampling, SolverProbabilityFollowsSupport) {
  EXPECT_DOUBLE_EQ(FirstSolverProbability(0.0, 0.0), 0.5);
  EXPECT_DOUBLE_EQ(FirstSolverProbability(0.3, 0.1), 0.75);
  EXPECT_DOUBLE_EQ(FirstSolverProbability(0.0, 0.2), 0.0);
  EXPECT_DOUBLE_EQ(AllInlierProbability(0.5, 4), 0.0625);
  EXPECT_DOUBLE_EQ(AllInlierProbability(1.5, 2), 1.0);  // clamped
}

TEST(HybridSampling, SamplesAreDistinctMembersOfThePoolAndUniform) {
  IndexSampler sampler(3);
  const std::vector<int> pool = {4, 8, 15, 16, 23, 42};
  std::vector<int> counts(43, 0);
  int sample[4];
  const int kDraws = 60000;
  for (int d = 0; d < kDraws; ++d) {
    sampler.Sample(pool, 4, sample);
    std::set<int> s(sample, sample + 4);
    ASSERT_EQ(s.size(), 4u);
    for (int v : sample) {
      ASSERT_TRUE(std::find(pool.begin(), pool.end(), v) != pool.end());
      ++counts[v];
    }
  }
  // Each element appears in 4/6 of the samples.
  for (int v : pool) EXPECT_NEAR(counts[v] / static_cast<double>(kDraws), 4.0 / 6.0, 0.01);
}

}  // namespace
}  // namespace madsfm
