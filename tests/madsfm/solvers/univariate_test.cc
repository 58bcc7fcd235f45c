#include "madsfm/solvers/univariate.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
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

// |p(x)| / sum_i |c_i x^i|: the residual every reported root must keep small.
double RelativeResidual(const std::vector<double>& c, double x) {
  double v = 0.0, s = 0.0, xp = 1.0;
  for (double ci : c) {
    v += ci * xp;
    s += std::abs(ci * xp);
    xp *= x;
  }
  return s > 0.0 ? std::abs(v) / s : 0.0;
}

std::vector<double> Solve(const std::vector<double>& c) {
  const int degree = static_cast<int>(c.size()) - 1;
  std::vector<double> roots(std::max(degree, 1));
  const int n = SolveRealPolynomialRoots(c.data(), degree, roots.data());
  roots.resize(n);
  return roots;
}

// True if `found` are exactly the (sorted) `expected` roots, each to `tol` relative.
bool SameRoots(std::vector<double> expected, const std::vector<double>& found, double tol) {
  std::sort(expected.begin(), expected.end());
  if (found.size() != expected.size()) return false;
  for (size_t i = 0; i < found.size(); ++i) {
    if (!(std::abs(found[i] - expected[i]) <= tol * std::abs(expected[i]))) return false;
  }
  return true;
}

// Every reported root is a root: relative residual <= 1e-10 (the documented guarantee), sorted.
void ExpectValidRoots(const std::vector<double>& c, const std::vector<double>& found) {
  for (size_t i = 0; i < found.size(); ++i) {
    EXPECT_TRUE(std::isfinite(found[i]));
    EXPECT_LE(RelativeResidual(c, found[i]), 1e-10) << "reported root " << found[i] << " is no root";
    if (i > 0) {
      EXPECT_LT(found[i - 1], found[i]);
    }
  }
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
  const double inf[5] = {1, 2, INFINITY, 1, 1};
  EXPECT_EQ(SolveRealPolynomialRoots(inf, 4, roots), 0);
  const double linear_in_disguise[4] = {-2, 1, 0, 0};  // x - 2
  ASSERT_EQ(SolveRealPolynomialRoots(linear_in_disguise, 3, roots), 1);
  EXPECT_DOUBLE_EQ(roots[0], 2.0);
  const double double_root[3] = {1, -2, 1};  // (x - 1)^2
  ASSERT_EQ(SolveRealPolynomialRoots(double_root, 2, roots), 1);
  EXPECT_NEAR(roots[0], 1.0, 1e-12);
  const double no_real[5] = {1, 0, 0, 0, 1};  // x^4 + 1
  EXPECT_EQ(SolveRealPolynomialRoots(no_real, 4, roots), 0);
  const double constant[3] = {3, 0, 0};
  EXPECT_EQ(SolveRealPolynomialRoots(constant, 2, roots), 0);
  EXPECT_EQ(SolveRealPolynomialRoots(constant, 0, roots), 0);
  EXPECT_EQ(SolveRealPolynomialRoots(constant, -1, roots), 0);
  EXPECT_EQ(SolveRealPolynomialRoots(zero, kMaxPolynomialDegree + 1, roots), 0);
  const double huge[5] = {1e300, -1e300, 1e-300, 1e300, -1e300};  // finite but extreme: no NaN, no crash
  const int n = SolveRealPolynomialRoots(huge, 4, roots);
  for (int i = 0; i < n; ++i) EXPECT_TRUE(std::isfinite(roots[i]));
}

TEST(Univariate, ExactAndMultipleRoots) {
  // Integer roots: bisection points can land exactly on them.
  EXPECT_TRUE(SameRoots({-2, -1, 1, 2, 3, 4}, Solve(FromRoots({1, 2, 3, 4, -1, -2}, {}, 1.0)), 1e-14));
  EXPECT_TRUE(SameRoots({1, 2, 4, 8}, Solve(FromRoots({1, 2, 4, 8}, {}, 1.0)), 1e-14));
  // Multiple roots are reported once.
  EXPECT_TRUE(SameRoots({-2, 1, 3}, Solve(FromRoots({1, 1, -2, 3}, {}, 1.0)), 1e-7));
  EXPECT_TRUE(SameRoots({-1, 2}, Solve(FromRoots({2, 2, 2, -1}, {}, 1.0)), 1e-5));
  // Roots at 0 (trailing zero coefficients), including a double one.
  EXPECT_TRUE(SameRoots({-1, 1}, Solve(FromRoots({1, -1}, {{0, 4}}, 2.0)), 1e-14));
  const std::vector<double> zero_roots = {0, 0, -1, 0, 1};  // x^4 - x^2 = x^2 (x - 1) (x + 1)
  const auto found = Solve(zero_roots);
  ASSERT_EQ(found.size(), 3u);
  EXPECT_NEAR(found[0], -1.0, 1e-14);
  EXPECT_EQ(found[1], 0.0);
  EXPECT_NEAR(found[2], 1.0, 1e-14);
}

TEST(Univariate, QuadraticIsStableForSmallRoots) {
  double r[2];
  ASSERT_EQ(SolveQuadraticReal(1.0, -1e8, 1.0, r), 2);
  EXPECT_NEAR(r[0], 1e-8, 1e-20);
  EXPECT_NEAR(r[1], 1e8, 1e-4);
}

// Reported by the 5-point solver: coefficients over 11 orders of magnitude. The old root finder
// returned 12.64 (where |p| ~ 5e9, a third of the sum of the terms) and missed the root near 4.508.
TEST(Univariate, FivePointSolverCase) {
  const std::vector<double> c = {-12437338.696777441, 3735178.9690098157, 1276380.4996312382, -346744.90216516762,
                                 -52140.82729387717,  9349.1372960820954, 822.53043708597943, -51.69168354383369,
                                 2.7790148282528873,  0.17150231025481477, 0.00019738373825003281};
  const auto found = Solve(c);
  ExpectValidRoots(c, found);
  // p changes sign at exactly these four places (a fine scan over [-2000, 2000] finds no others).
  const double brackets[4][2] = {{-852.0, -851.9}, {-30.3, -30.2}, {-5.1, -5.0}, {4.50, 4.52}};
  ASSERT_EQ(found.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    EXPECT_GT(found[i], brackets[i][0]);
    EXPECT_LT(found[i], brackets[i][1]);
    // A true simple root: the sign of p changes within 1e-12 (relative) of it.
    const double below = EvaluatePolynomial(c.data(), 10, found[i] - 1e-12 * std::abs(found[i]));
    const double above = EvaluatePolynomial(c.data(), 10, found[i] + 1e-12 * std::abs(found[i]));
    EXPECT_LT(below * above, 0.0) << "root " << i << " at " << found[i];
  }
}

// Roots with magnitudes spread over 1e-3 .. 1e3 (log-uniform, random signs; in a third of the
// polynomials all in 1e1 .. 1e3, in another third all in 1e-3 .. 1e-1), complex pairs likewise,
// degrees 4 .. 10, leading coefficients 1e-5 .. 1e5: coefficients spanning up to ~30 orders of
// magnitude. Asserted: all real roots found to 1e-8 (and nothing else) in >= 99% overall and in >= 99%
// of those spanning >= 20 orders; every reported root passes the residual check.
TEST(Univariate, BadlyScaledPolynomials) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0), log_lead(-5.0, 5.0);
  const int kTrials = 3000;
  int ok = 0, valid = 0, num_roots = 0, wide = 0, wide_ok = 0;
  double span_max = 0.0;
  for (int trial = 0; trial < kTrials; ++trial) {
    const int degree = 4 + 2 * (trial % 4);  // 4, 6, 8, 10
    const double log_lo = trial % 3 == 1 ? 1.0 : -3.0, log_hi = trial % 3 == 2 ? -1.0 : 3.0;
    auto magnitude = [&]() { return std::pow(10.0, log_lo + (log_hi - log_lo) * unit(rng)); };
    const int num_pairs = static_cast<int>(unit(rng) * (degree / 2 + 1)) % (degree / 2 + 1);
    std::vector<double> roots;
    while (static_cast<int>(roots.size()) < degree - 2 * num_pairs) {
      const double r = (unit(rng) < 0.5 ? -1.0 : 1.0) * magnitude();
      // Keep the roots 1% apart (relative): this test is about scaling, not clusters.
      bool close = false;
      for (double q : roots) close |= std::abs(q - r) < 0.01 * std::max(std::abs(q), std::abs(r));
      if (!close) roots.push_back(r);
    }
    std::vector<std::pair<double, double>> quads;
    for (int i = 0; i < num_pairs; ++i) {
      const double modulus = magnitude(), angle = 0.2 + 2.7 * unit(rng);
      quads.push_back({-2.0 * modulus * std::cos(angle), modulus * modulus});
    }
    const auto c = FromRoots(roots, quads, std::pow(10.0, log_lead(rng)));
    double cmin = INFINITY, cmax = 0.0;
    for (double ci : c) {
      if (ci != 0.0) cmin = std::min(cmin, std::abs(ci));
      cmax = std::max(cmax, std::abs(ci));
    }
    const double span = std::log10(cmax / cmin);
    span_max = std::max(span_max, span);
    const auto found = Solve(c);
    ExpectValidRoots(c, found);
    const bool match = SameRoots(roots, found, 1e-8);
    ok += match;
    wide += span >= 20.0;
    wide_ok += span >= 20.0 && match;
    num_roots += static_cast<int>(roots.size());
    bool all_valid = true;
    for (double x : found) all_valid &= RelativeResidual(c, x) <= 1e-10;
    valid += all_valid;
  }
  std::printf("univariate, badly scaled (roots 1e-3..1e3): all %d real roots found to 1e-8 in %.1f%% of %d "
              "polynomials, in %.1f%% of the %d whose coefficients span >= 20 orders of magnitude (%.1f at most); "
              "every reported root passes the residual check in %d / %d\n",
              num_roots, 100.0 * ok / kTrials, kTrials, 100.0 * wide_ok / std::max(wide, 1), wide, span_max, valid,
              kTrials);
  EXPECT_GE(ok, 0.99 * kTrials);
  EXPECT_GE(wide, 100);
  EXPECT_GE(wide_ok, 0.99 * wide);
  EXPECT_EQ(valid, kTrials);
}

// A root of the double-precision polynomial c, refined from `approx` by long double Newton steps, and
// the accuracy double precision can attain for it: eps * sum_k |c_k x^k| / |x p'(x)| (relative).
// Rounding the coefficients moves clustered roots by far more than 1e-8, so their ground truth is
// the polynomial actually passed, not the roots it was built from.
struct TrueRoot {
  double x;
  double attainable;
  bool converged;
};

TrueRoot RefineRoot(const std::vector<double>& c, double approx) {
  long double x = approx, p = 0.0L, dp = 0.0L, size = 0.0L;
  for (int it = 0; it < 40; ++it) {
    p = c.back();
    dp = 0.0L;
    size = std::abs(c.back());
    for (int k = static_cast<int>(c.size()) - 2; k >= 0; --k) {
      dp = dp * x + p;
      p = p * x + c[k];
      size = size * std::abs(x) + std::abs(c[k]);
    }
    if (dp == 0.0L) break;
    x -= p / dp;
  }
  const bool converged = std::abs(p) <= 1e-15L * size;
  return {static_cast<double>(x), static_cast<double>(2.2e-16L * size / std::abs(x * dp)), converged};
}

// Two real roots 1e-6 apart (relative) next to other roots, degrees 4 .. 10. Documented behaviour:
// both are reported when double precision can tell them apart; otherwise one root (or none, when
// rounding made the pair complex) is reported near the pair, checked by its residual. Asserted: in
// >= 99% of the polynomials every root is found to max(1e-8, 10x the attainable accuracy) of the
// roots of the polynomial passed, and nothing else; the pair is always represented by 1 or 2 roots
// (0 allowed only if it is complex after rounding); every reported root passes the residual check.
// Prints how often both roots of the pair are reported.
TEST(Univariate, ClusteredRoots) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-3.0, 3.0), unit(0.0, 1.0);
  const int kTrials = 1000;
  int all_found = 0, represented = 0, pair_reported = 0, pair_complex = 0, tight = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    const int degree = 4 + 2 * (trial % 4);
    const double center = (unit(rng) < 0.5 ? -1.0 : 1.0) * (0.2 + 2.8 * unit(rng));
    const double gap = 1e-6 * std::abs(center);
    std::vector<double> others;
    while (static_cast<int>(others.size()) < degree - 2 - 2 * (trial % 2)) {
      const double r = u(rng);
      bool close = std::abs(r - center) < 0.05;
      for (double q : others) close |= std::abs(q - r) < 0.05;
      if (!close) others.push_back(r);
    }
    std::vector<std::pair<double, double>> quads;
    if (trial % 2) quads.push_back({-2.0 * u(rng), 9.0 + 4.0 * unit(rng)});  // a complex pair
    std::vector<double> roots = others;
    roots.push_back(center - 0.5 * gap);
    roots.push_back(center + 0.5 * gap);
    const auto c = FromRoots(roots, quads, 1.0 + unit(rng));
    const auto found = Solve(c);
    ExpectValidRoots(c, found);
    // Ground truth for the other roots, and for the pair if it is still real and distinct.
    const TrueRoot lo = RefineRoot(c, center - 0.5 * gap), hi = RefineRoot(c, center + 0.5 * gap);
    const bool pair_real = lo.converged && hi.converged && hi.x - lo.x > 0.1 * gap;
    pair_complex += !pair_real;
    std::vector<TrueRoot> truth;
    for (double r : others) truth.push_back(RefineRoot(c, r));
    if (pair_real) {
      truth.push_back(lo);
      truth.push_back(hi);
    }
    auto near = [](double x, const TrueRoot& t) {
      return std::abs(x - t.x) <= std::max(1e-8, 10 * t.attainable) * std::abs(t.x);
    };
    // The pair region, widened by the attainable accuracy.
    const double slack = std::max(1e-8, 10 * std::max(lo.attainable, hi.attainable)) * std::abs(center);
    const double region_lo = pair_real ? std::min(lo.x, hi.x) - slack : center - 1e-4 * std::abs(center);
    const double region_hi = pair_real ? std::max(lo.x, hi.x) + slack : center + 1e-4 * std::abs(center);
    auto in_region = [&](double x) { return x >= region_lo && x <= region_hi; };
    int in_pair = 0;
    for (double x : found) in_pair += in_region(x);
    // Every true root matched by a reported root, and every reported root matching a true root; a
    // pair that double precision cannot resolve (attainable accuracy above a tenth of the gap, or
    // complex after rounding) may be reported as one root in its region (or none).
    const bool resolvable = pair_real && slack < 0.1 * gap;
    bool ok = true;
    for (const TrueRoot& t : truth) {
      bool hit = false;
      for (double x : found) hit |= near(x, t);
      ok &= hit || (!resolvable && in_region(t.x));
    }
    for (double x : found) {
      bool hit = !resolvable && in_region(x);
      for (const TrueRoot& t : truth) hit |= near(x, t);
      ok &= hit;
    }
    all_found += ok;
    bool others_found = true;
    for (double r : others) {
      const TrueRoot t = RefineRoot(c, r);
      bool hit = false;
      for (double x : found) hit |= near(x, t);
      others_found &= hit;
    }
    represented += (in_pair == 1 || in_pair == 2 || (!pair_real && in_pair == 0)) && others_found &&
                   found.size() == others.size() + in_pair;
    pair_reported += in_pair == 2;
    tight += pair_real && std::max(lo.attainable, hi.attainable) < 1e-9;
  }
  std::printf("univariate, pairs 1e-6 apart: all roots found (to max(1e-8, 10x attainable)) in %.1f%% of %d "
              "polynomials; pair represented (1 or 2 roots) in %d / %d, both pair roots reported in %d; the pair "
              "is complex after rounding in %d, resolvable to 1e-9 in %d\n",
              100.0 * all_found / kTrials, kTrials, represented, kTrials, pair_reported, pair_complex, tight);
  EXPECT_GE(all_found, 0.99 * kTrials);
  EXPECT_EQ(represented, kTrials);
}

// Leading coefficient 1e-12 relative to the others: (x / R - 1) q(x) with |R| = 1e12 and q of degree
// 3 .. 9 with roots in [-5, 5]. The root R must be found along with the others.
TEST(Univariate, TinyLeadingCoefficient) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-5.0, 5.0), unit(0.0, 1.0);
  const int kTrials = 1000;
  int ok = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    const int degree = 4 + trial % 7;  // 4 .. 10
    const double big = (trial % 2 ? 1e12 : -1e12) * (1.0 + unit(rng));
    std::vector<double> roots;
    while (static_cast<int>(roots.size()) < degree - 1 - 2 * (trial % 3 == 0)) {
      const double r = u(rng);
      bool close = false;
      for (double q : roots) close |= std::abs(q - r) < 0.05;
      if (!close) roots.push_back(r);
    }
    std::vector<std::pair<double, double>> quads;
    if (trial % 3 == 0) {
      const double re = u(rng), im = 0.5 + 3.0 * unit(rng);
      quads.push_back({-2.0 * re, re * re + im * im});
    }
    auto c = FromRoots(roots, quads, 1.0);
    // Multiply by (x / big - 1).
    std::vector<double> p(c.size() + 1, 0.0);
    for (size_t i = 0; i < c.size(); ++i) {
      p[i] -= c[i];
      p[i + 1] += c[i] / big;
    }
    roots.push_back(big);
    const auto found = Solve(p);
    ExpectValidRoots(p, found);
    ok += SameRoots(roots, found, 1e-8);
  }
  std::printf("univariate, leading coefficient 1e-12 relative: all roots (with the one near 1e12) found to 1e-8 in "
              "%.1f%% of %d polynomials\n",
              100.0 * ok / kTrials, kTrials);
  EXPECT_GE(ok, 0.99 * kTrials);
}

// Quick loop over the degrees the minimal solvers use (random polynomials as in the first test).
// Prints ns per call; no timing assertion (speed is for benchmarks), only that the loop agrees with
// a first pass.
TEST(Univariate, PrintsTimePerCall) {
  std::mt19937 rng(19);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  for (int degree : {4, 8, 10}) {
    std::vector<std::vector<double>> polys;
    int expected = 0;
    for (int i = 0; i < 500; ++i) {
      const int num_real = 1 + i % degree;
      const int num_pairs = (degree - num_real) / 2;
      std::vector<double> roots;
      for (int k = 0; k < degree - 2 * num_pairs; ++k) roots.push_back(u(rng));
      std::vector<std::pair<double, double>> quads;
      for (int k = 0; k < num_pairs; ++k) {
        const double re = u(rng), im = 0.1 + std::abs(u(rng));
        quads.push_back({-2 * re, re * re + im * im});
      }
      polys.push_back(FromRoots(roots, quads, u(rng) + 6.0));
      expected += static_cast<int>(Solve(polys.back()).size());
    }
    const int kRepeats = 200;
    double roots[kMaxPolynomialDegree];
    long found = 0;
    const auto start = std::chrono::steady_clock::now();
    for (int r = 0; r < kRepeats; ++r) {
      for (const auto& c : polys) found += SolveRealPolynomialRoots(c.data(), degree, roots);
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(found, static_cast<long>(expected) * kRepeats);
    std::printf("univariate: degree %d: %.0f ns per call (%d calls, %.2f real roots per call)\n", degree,
                1e9 * seconds / (kRepeats * polys.size()), static_cast<int>(kRepeats * polys.size()),
                static_cast<double>(expected) / polys.size());
  }
}

}  // namespace
}  // namespace madsfm
