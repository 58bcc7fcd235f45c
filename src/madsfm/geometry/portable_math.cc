#include "madsfm/geometry/portable_math.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace madsfm::portable {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// The double with the low `bits` mantissa bits of v cleared: k * result is exact for small integers k.
double Truncated(double v, int bits) {
  uint64_t b;
  std::memcpy(&b, &v, sizeof(b));
  b &= ~((uint64_t{1} << bits) - 1);
  std::memcpy(&v, &b, sizeof(v));
  return v;
}

// pi/2 = kPio2Hi + kPio2Mid + kPio2Lo (kPio2Hi has 26 significant bits, kPio2Mid 27, so k * both are exact for
// |k| < 2^26); M_PI_2 is the double nearest pi/2 and 6.123233995736766e-17 the rest (cos(M_PI_2)).
const double kPio2Hi = Truncated(M_PI_2, 27);
const double kPio2Mid = M_PI_2 - kPio2Hi;
constexpr double kPio2Lo = 6.123233995736766036e-17;
// ln 2 = kLn2Hi + kLn2Mid + kLn2Lo likewise (M_LN2 + 2.319046813846299558e-17).
const double kLn2Hi = Truncated(M_LN2, 32);
const double kLn2Mid = M_LN2 - kLn2Hi;
constexpr double kLn2Lo = 2.319046813846299558e-17;
constexpr double kPiLo = 1.224646799147353207e-16;  // pi - M_PI

// Rounds to the nearest integer (ties away from zero) with exact operations only.
double Round(double x) { return x >= 0.0 ? std::floor(x + 0.5) : -std::floor(0.5 - x); }

// sin and cos of |r| <= pi/4 + a little: Taylor series to r^21 / r^20 (truncation < 1e-22), Horner in double.
double SinKernel(double r) {
  const double r2 = r * r;
  double p = 1.0 / 51090942171709440000.0;  // 1/21!
  p = p * r2 - 1.0 / 121645100408832000.0;  // 1/19!
  p = p * r2 + 1.0 / 355687428096000.0;     // 1/17!
  p = p * r2 - 1.0 / 1307674368000.0;       // 1/15!
  p = p * r2 + 1.0 / 6227020800.0;          // 1/13!
  p = p * r2 - 1.0 / 39916800.0;            // 1/11!
  p = p * r2 + 1.0 / 362880.0;              // 1/9!
  p = p * r2 - 1.0 / 5040.0;                // 1/7!
  p = p * r2 + 1.0 / 120.0;                 // 1/5!
  p = p * r2 - 1.0 / 6.0;                   // 1/3!
  return r + r * (r2 * p);
}

double CosKernel(double r) {
  const double r2 = r * r;
  double p = 1.0 / 2432902008176640000.0;   // 1/20!
  p = p * r2 - 1.0 / 6402373705728000.0;    // 1/18!
  p = p * r2 + 1.0 / 20922789888000.0;      // 1/16!
  p = p * r2 - 1.0 / 87178291200.0;         // 1/14!
  p = p * r2 + 1.0 / 479001600.0;           // 1/12!
  p = p * r2 - 1.0 / 3628800.0;             // 1/10!
  p = p * r2 + 1.0 / 40320.0;               // 1/8!
  p = p * r2 - 1.0 / 720.0;                 // 1/6!
  p = p * r2 + 1.0 / 24.0;                  // 1/4!
  const double half = 0.5 * r2;
  const double w = 1.0 - half;
  // 1 - r^2/2 rounded, plus what the rounding dropped, plus the rest of the series.
  return w + (((1.0 - w) - half) + r2 * r2 * p);
}

// atan of 0 <= t <= 1: two half-angle reductions (atan t = 2 atan(t / (1 + sqrt(1 + t^2)))) to t <= tan(pi/16),
// then the series to t^25.
double AtanUnit(double t) {
  for (int i = 0; i < 2; ++i) t = t / (1.0 + std::sqrt(1.0 + t * t));
  const double t2 = t * t;
  double p = 1.0 / 25.0;
  for (int k = 23; k >= 3; k -= 2) p = p * t2 + ((k / 2) % 2 == 1 ? -1.0 : 1.0) / k;
  return 4.0 * (t + t * (t2 * p));
}

}  // namespace

double Exp(double x) {
  if (std::isnan(x)) return x;
  if (x > 709.782712893384) return kInf;
  if (x < -745.1332191019412) return 0.0;
  const double k = Round(x / M_LN2);
  const double r = ((x - k * kLn2Hi) - k * kLn2Mid) - k * kLn2Lo;  // |r| <= ln2/2 + a little
  double p = 1.0 / 355687428096000.0;  // 1/17!
  const double inv_fact[] = {1.0 / 20922789888000.0, 1.0 / 1307674368000.0, 1.0 / 87178291200.0,
                             1.0 / 6227020800.0,     1.0 / 479001600.0,     1.0 / 39916800.0,
                             1.0 / 3628800.0,        1.0 / 362880.0,        1.0 / 40320.0,
                             1.0 / 5040.0,           1.0 / 720.0,           1.0 / 120.0,
                             1.0 / 24.0,             1.0 / 6.0,             0.5};
  for (double c : inv_fact) p = p * r + c;
  const double e = 1.0 + (r + r * (r * p));
  return std::ldexp(e, static_cast<int>(k));
}

double Log(double x) {
  if (std::isnan(x) || x < 0.0) return kNaN;
  if (x == 0.0) return -kInf;
  if (std::isinf(x)) return x;
  int e = 0;
  double m = std::frexp(x, &e);  // x = m 2^e, m in [0.5, 1)
  if (m < M_SQRT1_2) {
    m *= 2.0;
    --e;
  }
  // log m = 2 atanh s, s = (m - 1) / (m + 1), |s| <= 0.1716: series to s^25.
  const double f = m - 1.0;  // exact
  const double s = f / (2.0 + f);
  const double s2 = s * s;
  double p = 1.0 / 25.0;
  for (int k = 23; k >= 3; k -= 2) p = p * s2 + 1.0 / k;
  const double hfsq = 0.5 * f * f;
  // log m = f - hfsq + s (hfsq + 2 s^2 p) (fdlibm's arrangement: f - hfsq carries most bits exactly).
  const double log_m = f - (hfsq - s * (hfsq + 2.0 * s2 * p));
  const double de = static_cast<double>(e);
  return de * kLn2Hi + (log_m + (de * kLn2Mid + de * kLn2Lo));
}

double Pow(double x, double y) {
  if (y == 0.0) return 1.0;
  if (x == 1.0) return 1.0;
  if (x == 0.0) return y > 0.0 ? 0.0 : kInf;
  if (!(x > 0.0)) return kNaN;
  return Exp(y * Log(x));
}

double PowInt(double x, int n) {
  double result = 1.0;
  for (double b = x; n > 0; n >>= 1, b *= b) {
    if (n & 1) result *= b;
  }
  return result;
}

void SinCos(double x, double* s, double* c) {
  if (!(std::abs(x) <= 1048576.0)) {
    *s = *c = kNaN;
    return;
  }
  const double k = Round(x / M_PI_2);
  const double r = ((x - k * kPio2Hi) - k * kPio2Mid) - k * kPio2Lo;
  const double sr = SinKernel(r), cr = CosKernel(r);
  switch (static_cast<int64_t>(k) & 3) {
    case 0: *s = sr; *c = cr; break;
    case 1: *s = cr; *c = -sr; break;
    case 2: *s = -sr; *c = -cr; break;
    default: *s = -cr; *c = sr; break;
  }
}

double Sin(double x) {
  double s, c;
  SinCos(x, &s, &c);
  return s;
}

double Cos(double x) {
  double s, c;
  SinCos(x, &s, &c);
  return c;
}

double Atan(double x) {
  if (std::isnan(x)) return x;
  const double a = std::abs(x);
  const double r = a <= 1.0 ? AtanUnit(a) : (M_PI_2 - AtanUnit(1.0 / a)) + kPio2Lo;
  return x < 0.0 ? -r : r;
}

double Atan2(double y, double x) {
  if (std::isnan(x) || std::isnan(y)) return kNaN;
  const double ax = std::abs(x), ay = std::abs(y);
  double a;
  if (ay == 0.0 && ax == 0.0) {
    a = 0.0;
  } else if (std::isinf(ax) || std::isinf(ay)) {
    a = std::isinf(ax) ? (std::isinf(ay) ? M_PI_4 : 0.0) : M_PI_2;
  } else if (ay <= ax) {
    a = AtanUnit(ay / ax);
  } else {
    a = (M_PI_2 - AtanUnit(ax / ay)) + kPio2Lo;
  }
  if (std::signbit(x)) a = (M_PI - a) + kPiLo;
  return std::signbit(y) ? -a : a;
}

double Acos(double x) {
  if (!(std::abs(x) <= 1.0)) return kNaN;
  return Atan2(std::sqrt((1.0 - x) * (1.0 + x)), x);
}

}  // namespace madsfm::portable
