#include "madsfm/geometry/portable_math.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>

namespace madsfm::portable {
namespace {

// Distance in units in the last place between two finite doubles of the same sign (0 when equal).
int64_t UlpDistance(double a, double b) {
  if (a == b) return 0;
  int64_t ia, ib;
  std::memcpy(&ia, &a, 8);
  std::memcpy(&ib, &b, 8);
  if (ia < 0) ia = std::numeric_limits<int64_t>::min() - ia;
  if (ib < 0) ib = std::numeric_limits<int64_t>::min() - ib;
  return ia > ib ? ia - ib : ib - ia;
}

// Against <cmath> (within 1 ulp of the exact value): within `ulp` ulp, or `abs_tol` near zeros of the function.
template <typename F, typename G>
void ExpectClose(const char* name, F ours, G reference, double lo, double hi, int64_t ulp, double abs_tol = 0.0) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(lo, hi);
  int64_t worst = 0;
  for (int i = 0; i < 200000; ++i) {
    const double x = u(rng);
    const double a = ours(x), b = reference(x);
    if (std::abs(a - b) <= abs_tol) continue;
    const int64_t d = UlpDistance(a, b);
    worst = std::max(worst, d);
    ASSERT_LE(d, ulp) << name << "(" << x << "): " << a << " vs " << b;
  }
  std::printf("%s on [%g, %g]: worst %lld ulp\n", name, lo, hi, static_cast<long long>(worst));
}

TEST(PortableMath, ExpLogPowAgreeWithCmath) {
  ExpectClose("Exp", Exp, [](double x) { return std::exp(x); }, -700.0, 700.0, 2);
  ExpectClose("Exp", Exp, [](double x) { return std::exp(x); }, -1.0, 1.0, 2);
  ExpectClose("Log", Log, [](double x) { return std::log(x); }, 1e-300, 1e300, 2);
  ExpectClose("Log", Log, [](double x) { return std::log(x); }, 0.5, 2.0, 2, 1e-300);
  ExpectClose("Log", Log, [](double x) { return std::log(x); }, 0.0, 1e-3, 2);
  // Pow = Exp(y Log x): the rounding of y Log x is amplified by |y ln x| (at most 4.6 and 17.8 here), so the bound is
  // 4 + 2 |y ln x| ulp.
  ExpectClose("Pow", [](double x) { return Pow(x, 0.1); }, [](double x) { return std::pow(x, 0.1); }, 1e-20, 1e20, 14);
  ExpectClose("Pow", [](double y) { return Pow(0.7, y); }, [](double y) { return std::pow(0.7, y); }, 0.0, 50.0, 40);
}

TEST(PortableMath, TrigonometryAgreesWithCmath) {
  // Near the zeros of sin / cos the relative error grows: an absolute tolerance of 2^-60 there.
  const double near_zero = std::ldexp(1.0, -60);
  ExpectClose("Sin", Sin, [](double x) { return std::sin(x); }, -10.0, 10.0, 2, near_zero);
  ExpectClose("Cos", Cos, [](double x) { return std::cos(x); }, -10.0, 10.0, 2, near_zero);
  ExpectClose("Sin", Sin, [](double x) { return std::sin(x); }, -1e-3, 1e-3, 1);
  ExpectClose("Sin", Sin, [](double x) { return std::sin(x); }, -1e5, 1e5, 2, near_zero);
  ExpectClose("Atan", Atan, [](double x) { return std::atan(x); }, -50.0, 50.0, 4);
  ExpectClose("Atan", Atan, [](double x) { return std::atan(x); }, -1.0, 1.0, 4);
  ExpectClose("Acos", Acos, [](double x) { return std::acos(x); }, -1.0, 1.0, 6);
  ExpectClose("Atan2", [](double y) { return Atan2(y, -0.3); }, [](double y) { return std::atan2(y, -0.3); }, -5.0,
              5.0, 6);
  ExpectClose("Atan2", [](double x) { return Atan2(0.2, x); }, [](double x) { return std::atan2(0.2, x); }, -5.0,
              5.0, 6);
}

TEST(PortableMath, SpecialValues) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(Exp(0.0), 1.0);
  EXPECT_EQ(Exp(1000.0), inf);
  EXPECT_EQ(Exp(-1000.0), 0.0);
  EXPECT_TRUE(std::isnan(Exp(std::nan(""))));
  EXPECT_EQ(Log(1.0), 0.0);
  EXPECT_EQ(Log(0.0), -inf);
  EXPECT_TRUE(std::isnan(Log(-1.0)));
  EXPECT_EQ(Log(inf), inf);
  EXPECT_EQ(Pow(2.0, 0.0), 1.0);
  EXPECT_EQ(Pow(0.0, 2.0), 0.0);
  EXPECT_TRUE(std::isnan(Pow(-2.0, 0.5)));
  EXPECT_EQ(PowInt(0.5, 0), 1.0);
  EXPECT_EQ(PowInt(0.5, 7), 0.0078125);
  EXPECT_EQ(PowInt(3.0, 5), 243.0);
  EXPECT_EQ(Sin(0.0), 0.0);
  EXPECT_EQ(Cos(0.0), 1.0);
  EXPECT_TRUE(std::isnan(Sin(1e300)));
  EXPECT_EQ(Atan2(0.0, 1.0), 0.0);
  EXPECT_EQ(Atan2(0.0, -1.0), M_PI);
  EXPECT_EQ(Atan2(1.0, 0.0), M_PI_2);
  EXPECT_EQ(Atan2(-1.0, 0.0), -M_PI_2);
  EXPECT_EQ(Acos(1.0), 0.0);
  EXPECT_EQ(Acos(-1.0), M_PI);
  EXPECT_EQ(Acos(0.0), M_PI_2);
  EXPECT_TRUE(std::isnan(Acos(1.5)));
}

}  // namespace
}  // namespace madsfm::portable
