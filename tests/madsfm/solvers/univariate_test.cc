#include "madsfm/solvers/univariate.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace madsfm {
namespace {

// Builds the coefficients of lead * prod (x - r_i) * prod (x^2 + b_j x + c_j) (complex pairs).
std::vector<double> FromRoots(const std::vector<double>& roots, const std::vector<std::pair<double, double>>& quads,
                              double lead) {
  std::vector<double> c = {lead};
  auto mul = [&c](const std::vector<double>& f) {
    std::vector<double> r(c.size() + f.size() - 1, 0.0);
    for (size_t i = 0; i < c.size(); ++i)
      for (size_t j = 0; j < f.size(); ++j) r[i + j] += c[i] * f[j];
    c = r;
  };
  for (double r : roots) mul({-r, 1.0});
  for (auto [b, cc] : quads) mul({cc, b, 1.0});
  return c;
}

TEST(Univariate, FindsAllRealRootsOfRandomPolynomials) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  int ok = 0, total = 0;
  const int kTrials = 1000;
  for (int trial = 0; trial < kTrials; ++trial) {
    const int num_real = 1 + trial % 8;  // 1..8 real roots
    const int num_complex = (10 - num_real) / 2 * (trial % 2);
    std::vector<double> roots;
    for (int i = 0; i < num_real; ++i) roots.push_back(u(rng));
    std::vector<std::pair<double, double>> quads;
    for (int i = 0; i < num_complex; ++i) {
      const double re = u(rng), im = 0.1 + std::abs(u(rng));
      quads.push_back({-2 * re, re * re + im * im});
    }
    const auto c = FromRoots(roots, quads, u(rng) + 6.0);
    const int degree = static_cast<int>(c.size()) - 1;
    ++total;
    std::vector<double> found(degree + 1);
    const int n = SolveRealPolynomialRoots(c.data(), degree, found.data());
    std::sort(roots.begin(), roots.end());
    // Distinct roots only (random roots can nearly coincide; count those as one).
    bool match = n == static_cast<int>(roots.size());
    for (int i = 0; match && i < n; ++i) match = std::abs(found[i] - roots[i]) < 1e-8 * (1 + std::abs(roots[i]));
    ok += match;
  }
  ASSERT_EQ(total, kTrials);
  const double rate = static_cast<double>(ok) / total;
  std::printf("univariate: all real roots found to 1e-8 in %.1f%% of %d polynomials\n", 100 * rate, total);
  EXPECT_GE(rate, 0.99);
}

TEST(Univariate, HandlesDegenerateInput) {
  double roots[8];
  const double zero[5] = {0, 0, 0, 0, 0};
  EXPECT_EQ(SolveRealPolynomialRoots(zero, 4, roots), 0);
  const double nan[3] = {1, NAN, 1};
  EXPECT_EQ(SolveRealPolynomialRoots(nan, 2, roots), 0);
  const double linear_in_disguise[4] = {-2, 1, 0, 0};  // x - 2
  ASSERT_EQ(SolveRealPolynomialRoots(linear_in_disguise, 3, roots), 1);
  EXPECT_DOUBLE_EQ(roots[0], 2.0);
  const double double_root[3] = {1, -2, 1};  // (x - 1)^2
  ASSERT_EQ(SolveRealPolynomialRoots(double_root, 2, roots), 1);
  EXPECT_NEAR(roots[0], 1.0, 1e-12);
  const double no_real[5] = {1, 0, 0, 0, 1};  // x^4 + 1
  EXPECT_EQ(SolveRealPolynomialRoots(no_real, 4, roots), 0);
}

TEST(Univariate, QuadraticIsStableForSmallRoots) {
  double r[2];
  ASSERT_EQ(SolveQuadraticReal(1.0, -1e8, 1.0, r), 2);
  EXPECT_NEAR(r[0], 1e-8, 1e-20);
  EXPECT_NEAR(r[1], 1e8, 1e-4);
}

}  // namespace
}  // namespace madsfm
