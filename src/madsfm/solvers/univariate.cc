#include "madsfm/solvers/univariate.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#if defined(__AVX__)
#include <immintrin.h>
#endif

// Outline of SolveRealPolynomialRoots:
//  1. Exact zero roots are split off; leading coefficients that only add roots more than 2^50 times
//     larger than all others (rounding noise on a coefficient that should be 0) are dropped.
//  2. x = 2^e y balances |c_0| and |c_n| 2^(e n) (the roots' geometric mean becomes ~1), and a power
//     of two scales max |a_k| to ~1: exact, and it keeps intermediate values in range.
//  3. Fujiwara's bound on the roots and on their inverses gives L < |y| < U.
//  4. Sturm counts on (-U, -L) and (L, U), split at geometric means while an interval spans a factor
//     > 4 and at midpoints after that, isolate the roots (breadth first, so that the evaluations of a
//     round overlap). The counts only guide the search: an interval where p changes sign always
//     yields a root; one whose count says "roots" but where p keeps its sign is examined at the
//     extremum of p (even multiplicity, or a close pair).
//  5. When the Sturm chain's estimated error is too large (near-multiple roots, clusters, roots on
//     scales far apart), the roots are isolated by the extrema of p instead: the real roots of p'
//     (recursively) cut the line into pieces where p is monotone; a local minimum of |p| that passes
//     the residual check is a (near-)double root.
//  6. All isolated roots are polished together (4 per vector, lock step) by Laguerre / Halley steps
//     kept inside their brackets, and reported only if |p(x)| <= kResidualTol * sum_k |c_k x^k|.

namespace madsfm {
namespace {

constexpr int kMaxN = kMaxPolynomialDegree;
// Column stride of the Sturm table (>= kMaxN + 1 members, a multiple of 4 doubles).
constexpr int kStride = 24;
constexpr double kEps = 2.220446049250313e-16;
// A Sturm remainder coefficient below kChainTol times the size of the terms it was computed from
// counts as zero (degree drop; the chain ends when the whole remainder vanishes).
constexpr double kChainTol = 1e-13;
// A reported root x satisfies |p(x)| <= kResidualTol * sum_k |c_k| |x|^k.
constexpr double kResidualTol = 1e-10;
// When the estimated relative error of the Sturm chain exceeds this (near-multiple roots, clusters,
// roots on scales far apart), the roots are isolated by the extrema of p instead (recursively, up to
// kMaxFallbackDepth derivatives deep).
constexpr double kChainMaxError = 1e-2;
constexpr int kMaxFallbackDepth = 4;
// Polishing stops after a step below kStepTol (relative), or earlier when the last two steps predict
// (cubic convergence) an error below kPredictedTol after the current one.
constexpr double kStepTol = 1e-10;
constexpr double kPredictedTol = 1e-17;
constexpr int kMaxPolishIterations = 200;
// Intervals narrower than this (relative) are not split further: their roots form a cluster that
// double precision cannot separate.
constexpr double kTinyWidth = 0x1p-42;
// A count-1 interval without a sign change of p (a double root?) is split down to this relative
// width before its extremum is examined.
constexpr double kTangentWidth = 0x1p-10;
// Leading coefficients whose roots lie more than 2^kDropLog2 beyond those of the rest are dropped.
constexpr double kDropLog2 = 50.0;

// Four doubles processed in lock step (GCC / Clang vector extension). Without AVX (a build without
// -march=native) GCC and Clang warn that passing them by value has a different ABI; they never cross this file.
#if defined(__GNUC__)  // also defined by Clang, which knows the same pragma and warning
#pragma GCC diagnostic ignored "-Wpsabi"
#endif
typedef double Vec4 __attribute__((vector_size(32)));

#if defined(__FMA__)
inline double MulAdd(double a, double b, double c) { return std::fma(a, b, c); }
inline Vec4 MulAdd(Vec4 a, Vec4 b, Vec4 c) {
  Vec4 r;
  for (int l = 0; l < 4; ++l) r[l] = std::fma(a[l], b[l], c[l]);
  return r;
}
#else
inline double MulAdd(double a, double b, double c) { return a * b + c; }
inline Vec4 MulAdd(Vec4 a, Vec4 b, Vec4 c) { return a * b + c; }
#endif
inline Vec4 MulAdd(Vec4 a, double b, Vec4 c) { return MulAdd(a, Vec4{} + b, c); }

// Lane masks (all bits set or clear) of comparisons between Vec4s.
typedef long long Mask4 __attribute__((vector_size(32)));

inline Vec4 Abs(Vec4 v) { return v < 0.0 ? -v : v; }

inline Vec4 Sqrt(Vec4 v) {
#if defined(__AVX__)
  return _mm256_sqrt_pd(v);
#else
  Vec4 r;
  for (int l = 0; l < 4; ++l) r[l] = std::sqrt(v[l]);
  return r;
#endif
}

// e with 2^e <= |v| < 2^(e + 1), for finite nonzero v.
inline int Exponent(double v) {
  std::uint64_t bits;
  std::memcpy(&bits, &v, sizeof(bits));
  const int biased = static_cast<int>((bits >> 52) & 0x7ff);
  return biased != 0 ? biased - 1023 : std::ilogb(v);
}

// 2^e for -1022 <= e <= 1023.
inline double Pow2(int e) {
  const std::uint64_t bits = static_cast<std::uint64_t>(e + 1023) << 52;
  double v;
  std::memcpy(&v, &bits, sizeof(v));
  return v;
}

// kInverse[j] = 1 / j (multiplications instead of divisions in the bounds).
constexpr double kInverse[kMaxN + 1] = {0.0,      1.0,      1.0 / 2,  1.0 / 3,  1.0 / 4,  1.0 / 5,  1.0 / 6,
                                        1.0 / 7,  1.0 / 8,  1.0 / 9,  1.0 / 10, 1.0 / 11, 1.0 / 12, 1.0 / 13,
                                        1.0 / 14, 1.0 / 15, 1.0 / 16, 1.0 / 17, 1.0 / 18, 1.0 / 19, 1.0 / 20};

inline int Sign(double v) { return (v > 0.0) - (v < 0.0); }

// Split point of [lo, hi]: the geometric mean when the interval spans a factor > 4 on one side of 0.
inline double Split(double lo, double hi) {
  if (lo > 0.0 && hi > 4.0 * lo) return std::sqrt(lo * hi);
  if (hi < 0.0 && lo < 4.0 * hi) return -std::sqrt(lo * hi);
  return 0.5 * (lo + hi);
}

// p(x) and sum_k |a_k| |x|^k.
inline void Residual(const double* a, int n, double x, double* value, double* scale) {
  double v = a[n], s = std::abs(a[n]);
  const double ax = std::abs(x);
  for (int k = n - 1; k >= 0; --k) {
    v = MulAdd(v, x, a[k]);
    s = MulAdd(s, ax, std::abs(a[k]));
  }
  *value = v;
  *scale = s;
}

// Sturm sequence p = s_0, s_1 = p', s_{i+1} = -(s_{i-1} mod s_i), each member scaled by a positive
// power of two. Stored transposed, t[k * kStride + i] = coefficient of x^k in s_i, so that one
// vectorised Horner recurrence evaluates all members.
struct SturmChain {
  int degree = 0;  // of p
  int size = 0;    // number of members
  int member_degree[kMaxN + 1];
  // Estimated relative error of the members (rounding errors grow by the cancellation in each
  // remainder); infinite when a remainder vanished numerically (p and p' nearly share a root).
  double error = 0.0;
  // Beyond this |x| the members are evaluated in 1 / x (x^n could overflow).
  double forward_limit = 1.0;
  alignas(32) double t[(kMaxN + 1) * kStride];
};

// Appends sign * c (degree `degree`, zero-padded to ch->degree) to the chain.
void StoreMember(const double* c, int degree, double sign, SturmChain* ch) {
  const int i = ch->size++;
  ch->member_degree[i] = degree;
  for (int k = 0; k <= ch->degree; ++k) ch->t[k * kStride + i] = sign * c[k];
}

// Builds the Sturm chain of a (degree n >= 1, a[n] != 0, max |a_k| = O(1)).
void BuildSturmChain(const double* a, int n, SturmChain* ch) {
  ch->degree = n;
  ch->size = 0;
  ch->error = 0.0;
  double prev_error = 0.0, cur_error = kEps;
  // The working polynomials are b_i = sign_i s_i: b_{i+1} = b_{i-1} mod b_i (no negation and no
  // rescaling on the critical path), so sign_{i+1} = -sign_{i-1}. Zero-padded to degree n.
  double buffers[2][kMaxN + 2];
  double* prev = buffers[0];
  double* cur = buffers[1];
  for (int k = 0; k < n; ++k) {
    prev[k] = a[k];
    cur[k] = (k + 1) * a[k + 1];
  }
  prev[n] = a[n];
  cur[n] = 0.0;
  cur[n + 1] = prev[n + 1] = 0.0;
  double prev_sign = 1.0, cur_sign = 1.0;
  int dprev = n, dcur = n - 1;
  StoreMember(prev, dprev, 1.0, ch);
  StoreMember(cur, dcur, 1.0, ch);
  while (dcur > 0) {
    // prev <- prev mod cur, in place; mag_j = sum of the magnitudes of the terms that made r_j, the
    // scale of its rounding error.
    double mag[kMaxN + 2];
    const double inv_lead = 1.0 / cur[dcur];
    if (dprev == dcur + 1) {
      // The usual case, a linear quotient q1 x + q0: r_j = prev_j - q1 cur_{j-1} - q0 cur_j.
      const double q1 = -prev[dprev] * inv_lead;
      const double q0 = -MulAdd(q1, cur[dcur - 1], prev[dcur]) * inv_lead;
      const double a1 = std::abs(q1), a0 = std::abs(q0);
      mag[0] = MulAdd(a0, std::abs(cur[0]), std::abs(prev[0]));
      prev[0] = MulAdd(q0, cur[0], prev[0]);
      for (int j = 1; j < dcur; ++j) {
        mag[j] = MulAdd(a0, std::abs(cur[j]), MulAdd(a1, std::abs(cur[j - 1]), std::abs(prev[j])));
        prev[j] = MulAdd(q0, cur[j], MulAdd(q1, cur[j - 1], prev[j]));
      }
    } else {
      for (int j = 0; j < dcur; ++j) mag[j] = std::abs(prev[j]);
      for (int k = dprev; k >= dcur; --k) {
        const double q = -prev[k] * inv_lead;
        double* pk = prev + (k - dcur);
        for (int j = 0; j < dcur; ++j) {
          pk[j] = MulAdd(q, cur[j], pk[j]);
          if (k - dcur + j < dcur) mag[k - dcur + j] += std::abs(q * cur[j]);
        }
      }
    }
    for (int j = dcur; j <= dprev; ++j) prev[j] = 0.0;  // eliminated (zero up to rounding)
    // Coefficients at the level of their rounding error are zero: a degree drop, or the end of the
    // chain (cur divides prev numerically: it is the gcd, and p has multiple roots).
    int dr = dcur - 1;
    while (dr >= 0 && std::abs(prev[dr]) <= kChainTol * mag[dr]) prev[dr--] = 0.0;
    if (dr < 0) {
      ch->error = INFINITY;
      break;
    }
    double rmax = 0.0, mag_max = 0.0;
    for (int j = 0; j <= dr; ++j) {
      rmax = std::max(rmax, std::abs(prev[j]));
      mag_max = std::max(mag_max, mag[j]);
    }
    // A degree drop means the leading coefficient cancelled to rounding level: what is left is not
    // to be trusted either.
    const double new_error = dr < dcur - 1 ? INFINITY : (std::max(prev_error, cur_error) + kEps) * mag_max / rmax;
    ch->error = std::max(ch->error, new_error);
    prev_error = cur_error;
    cur_error = new_error;
    if (rmax < 0x1p-300 || rmax > 0x1p300) {  // keep the magnitudes in range
      const double f = Pow2(std::clamp(-Exponent(rmax), -1000, 1000));
      for (int j = 0; j <= dr; ++j) prev[j] *= f;
    }
    const double new_sign = -prev_sign;
    std::swap(prev, cur);
    prev_sign = cur_sign;
    cur_sign = new_sign;
    dprev = dcur;
    dcur = dr;
    StoreMember(cur, dcur, cur_sign, ch);
  }
  ch->forward_limit = Pow2(500 / n);
  // Zero the padding lanes read by the vectorised evaluation.
  const int lanes = (ch->size + 3) & ~3;
  for (int k = 0; k <= n; ++k) {
    for (int i = ch->size; i < lanes; ++i) ch->t[k * kStride + i] = 0.0;
  }
}

// Sign changes of the Sturm sequence at x (zeros skipped); *sign_p = sign of p(x). One Horner
// recurrence over 4 * kVecs lanes evaluates all members.
template <int kVecs>
int SignChangesImpl(const SturmChain& ch, double x, int* sign_p) {
  const int n = ch.degree;
  const double* t = ch.t;
  Vec4 v[kVecs];
  bool flip = false;
  if (std::abs(x) <= ch.forward_limit) {
    const double* row = t + n * kStride;
    for (int j = 0; j < kVecs; ++j) std::memcpy(&v[j], row + 4 * j, sizeof(Vec4));
    for (int k = n - 1; k >= 0; --k) {
      row = t + k * kStride;
#pragma GCC unroll 8
      for (int j = 0; j < kVecs; ++j) {
        Vec4 c;
        std::memcpy(&c, row + 4 * j, sizeof(Vec4));
        v[j] = MulAdd(v[j], x, c);
      }
    }
  } else {
    // Huge |x|: x^-n s_i(x) by Horner in 1/x, free of overflow. The common factor x^-n leaves the
    // sign changes alone; it flips every sign when x < 0 and n is odd.
    const double r = 1.0 / x;
    for (int j = 0; j < kVecs; ++j) std::memcpy(&v[j], t + 4 * j, sizeof(Vec4));
    for (int k = 1; k <= n; ++k) {
      const double* row = t + k * kStride;
#pragma GCC unroll 8
      for (int j = 0; j < kVecs; ++j) {
        Vec4 c;
        std::memcpy(&c, row + 4 * j, sizeof(Vec4));
        v[j] = MulAdd(v[j], r, c);
      }
    }
    flip = x < 0.0 && (n & 1);
  }
  double values[4 * kVecs];
  std::memcpy(values, v, sizeof(values));
  *sign_p = flip ? -Sign(values[0]) : Sign(values[0]);
  // Sign changes from the sign bits; exact zeros, which the count must skip, take the slow path.
  std::uint64_t bits[4 * kVecs];
  std::memcpy(bits, values, sizeof(bits));
  const int size = ch.size;
  int changes = 0, zeros = 0;
  for (int i = 0; i + 1 < size; ++i) changes += static_cast<int>((bits[i] ^ bits[i + 1]) >> 63);
  for (int i = 0; i < size; ++i) zeros += static_cast<int>((bits[i] << 1) == 0);
  if (zeros == 0) return changes;
  changes = 0;
  int prev = 0;
  for (int i = 0; i < size; ++i) {
    const int s = Sign(values[i]);
    if (s == 0) continue;
    if (prev != 0 && s != prev) ++changes;
    prev = s;
  }
  return changes;
}

int SignChanges(const SturmChain& ch, double x, int* sign_p) {
  if (ch.size <= 4) return SignChangesImpl<1>(ch, x, sign_p);
  if (ch.size <= 8) return SignChangesImpl<2>(ch, x, sign_p);
  if (ch.size <= 12) return SignChangesImpl<3>(ch, x, sign_p);
  if (ch.size <= 16) return SignChangesImpl<4>(ch, x, sign_p);
  return SignChangesImpl<kStride / 4>(ch, x, sign_p);
}

// Sign changes of a sequence of signs (zeros skipped); branch-free.
int CountChanges(const int* s, int size) {
  int changes = 0, prev = 0;
  for (int i = 0; i < size; ++i) {
    changes += static_cast<int>(s[i] * prev < 0);
    prev = s[i] != 0 ? s[i] : prev;
  }
  return changes;
}

// A root of f to polish: f(lo) has sign slo != 0, f(hi) the opposite sign; x ends up at the root.
struct Bracket {
  double lo, hi;
  int slo;
  double x;
};

// Geometric mean of 0 < a < b, approximately (averaged bit patterns, within 6%), strictly between.
inline Vec4 GeometricMean(Vec4 a, Vec4 b) {
  Mask4 ia, ib;
  std::memcpy(&ia, &a, sizeof(ia));
  std::memcpy(&ib, &b, sizeof(ib));
  const Mask4 im = (ia >> 1) + (ib >> 1);  // no overflow: the bit patterns are below 2^63
  Vec4 m;
  std::memcpy(&m, &im, sizeof(m));
  return m;
}

// Polishes up to 4 * kVecs brackets of f (degree d >= 1) in lock step, each lane of a Vec4 holding
// one root; the cost is about that of the slowest root alone. The first kLaguerreIterations
// iterations take Laguerre steps (global convergence when all roots are real), the later ones
// Halley steps (cubic convergence like Laguerre, without the square root); Newton or bisection
// (geometric on wide one-signed intervals) steps keep each lane inside its shrinking bracket. All
// per-lane decisions are selects, not branches.
constexpr int kLaguerreIterations = 2;

template <int kVecs>
void PolishLockStep(const double* f, int d, Bracket* brackets, int count) {
  constexpr int kLanes = 4 * kVecs;
  double init[5][kLanes];  // lo, hi, slo, x, done
  for (int l = 0; l < kLanes; ++l) {
    const bool used = l < count;
    const Bracket& b = brackets[used ? l : 0];
    init[0][l] = b.lo;
    init[1][l] = b.hi;
    init[2][l] = b.slo;
    init[3][l] = Split(b.lo, b.hi);
    init[4][l] = used ? 0.0 : 1.0;
  }
  Vec4 lo[kVecs], hi[kVecs], slo[kVecs], x[kVecs], last[kVecs];
  Mask4 done[kVecs];
  for (int j = 0; j < kVecs; ++j) {
    std::memcpy(&lo[j], init[0] + 4 * j, sizeof(Vec4));
    std::memcpy(&hi[j], init[1] + 4 * j, sizeof(Vec4));
    std::memcpy(&slo[j], init[2] + 4 * j, sizeof(Vec4));
    std::memcpy(&x[j], init[3] + 4 * j, sizeof(Vec4));
    Vec4 done_value;
    std::memcpy(&done_value, init[4] + 4 * j, sizeof(Vec4));
    done[j] = done_value > 0.0;
    last[j] = Vec4{};
  }
  const double dd = d, dm1 = d - 1;
  const Vec4 zero{};
  for (int it = 0; it < kMaxPolishIterations; ++it) {
    Mask4 all_done = done[0];
    for (int j = 1; j < kVecs; ++j) all_done &= done[j];
    if (all_done[0] && all_done[1] && all_done[2] && all_done[3]) break;
    // f, f', f'' / 2 and sum_k |f_k| |x|^k (the scale of the rounding error of f) at all lanes.
    Vec4 p[kVecs], dp[kVecs], hp[kVecs], size[kVecs], ax[kVecs];
    for (int j = 0; j < kVecs; ++j) {
      ax[j] = Abs(x[j]);
      p[j] = zero + f[d];
      size[j] = zero + std::abs(f[d]);
      dp[j] = zero;
      hp[j] = zero;
    }
    for (int k = d - 1; k >= 0; --k) {
      const Vec4 c = zero + f[k], abs_c = zero + std::abs(f[k]);
#pragma GCC unroll 4
      for (int j = 0; j < kVecs; ++j) {
        hp[j] = MulAdd(hp[j], x[j], dp[j]);
        dp[j] = MulAdd(dp[j], x[j], p[j]);
        p[j] = MulAdd(p[j], x[j], c);
        size[j] = MulAdd(size[j], ax[j], abs_c);
      }
    }
    const bool laguerre_iteration = it < kLaguerreIterations;
    for (int j = 0; j < kVecs; ++j) {
      const Mask4 same = (p[j] > zero) == (slo[j] > zero);
      const Vec4 new_lo = same ? x[j] : lo[j];
      const Vec4 new_hi = same ? hi[j] : x[j];
      const Vec4 dp2 = dp[j] * dp[j];
      Vec4 step;
      Mask4 cubic;
      if (laguerre_iteration) {
        // Laguerre: d p / (p' +- sqrt((d - 1) ((d - 1) p'^2 - d p p''))), the real part of it when the
        // square root is imaginary (complex roots nearby): d p p' / (p'^2 - disc).
        const Vec4 disc = dm1 * (dm1 * dp2 - 2.0 * dd * p[j] * hp[j]);
        const Vec4 root = Sqrt(disc > zero ? disc : zero);
        cubic = disc >= zero;
        step = (cubic ? dd * p[j] : dd * p[j] * dp[j]) / (cubic ? dp[j] + (dp[j] >= zero ? root : -root) : dp2 - disc);
      } else {
        // Halley: 2 p p' / (2 p'^2 - p p''); Newton where p p'' is too large for it.
        const Vec4 halley_den = dp2 - p[j] * hp[j];
        cubic = halley_den > 0.5 * dp2;
        step = (cubic ? p[j] * dp[j] : p[j]) / (cubic ? halley_den : dp[j]);
      }
      const Vec4 abs_x = Abs(x[j]), abs_step = Abs(step);
      const Vec4 xn = x[j] - step;
      const Mask4 inside = (xn > new_lo) & (xn < new_hi);
      // A step past a bracket end (towards a neighbouring root): Newton stays closer to x; failing
      // that, bisect.
      const Vec4 x_newton = x[j] - p[j] / dp[j];
      const Mask4 newton_inside = (x_newton > new_lo) & (x_newton < new_hi);
      const Mask4 positive = new_lo > zero, negative = new_hi < zero;
      const Vec4 geometric = GeometricMean(Abs(new_lo) < Abs(new_hi) ? Abs(new_lo) : Abs(new_hi),
                                           Abs(new_lo) < Abs(new_hi) ? Abs(new_hi) : Abs(new_lo));
      const Vec4 x_bisect = positive & (new_hi > 4.0 * new_lo)
                                ? geometric
                                : (negative & (new_lo < 4.0 * new_hi) ? -geometric : 0.5 * (new_lo + new_hi));
      // Done when the step is tiny, when |p| is at the level of its rounding error (a cluster: no
      // better answer exists in double precision), when the last two steps predict (cubic
      // convergence: error ~ step^4 / last^3 after this step) an error below kPredictedTol, or when
      // the bracket has collapsed.
      const Mask4 converged = (abs_step <= kStepTol * abs_x) | (Abs(p[j]) <= dd * kEps * size[j]);
      const Vec4 step2 = abs_step * abs_step, last3 = last[j] * last[j] * last[j];
      const Mask4 predicted = inside & cubic & (last[j] < 1e-2 * abs_x) & (abs_step < last[j]) &
                              (step2 * step2 <= kPredictedTol * last3 * abs_x);
      const Vec4 width_limit = 4.0 * kEps * (Abs(new_lo) > Abs(new_hi) ? Abs(new_lo) : Abs(new_hi));
      const Mask4 collapsed = (new_hi - new_lo <= width_limit) & ~inside & ~newton_inside;
      const Vec4 new_x = inside ? xn : (converged ? x[j] : (newton_inside ? x_newton : x_bisect));
      const Mask4 active = ~done[j];
      lo[j] = active ? new_lo : lo[j];
      hi[j] = active ? new_hi : hi[j];
      x[j] = active ? new_x : x[j];
      last[j] = active & inside & cubic ? abs_step : zero;
      done[j] |= converged | predicted | collapsed;
    }
  }
  double result[kLanes];
  std::memcpy(result, x, sizeof(result));
  for (int l = 0; l < count; ++l) brackets[l].x = result[l];
}

// Polishes all brackets; their roots end up in brackets[i].x.
void Polish(const double* f, int d, Bracket* brackets, int count) {
  for (int start = 0; start < count; start += 8) {
    const int num = std::min(8, count - start);
    if (num <= 4) {
      PolishLockStep<1>(f, d, brackets + start, num);
    } else {
      PolishLockStep<2>(f, d, brackets + start, num);
    }
  }
}

// The root of f (degree d >= 1) in (lo, hi), f(lo) of sign slo != 0 and f(hi) of the opposite sign.
double SolveBracketed(const double* f, int d, double lo, double hi, int slo) {
  Bracket b{lo, hi, slo, 0.0};
  PolishLockStep<1>(f, d, &b, 1);
  return b.x;
}

int RealRoots(const double* coeffs, int degree, int depth, double* roots);

// Real-root search for a polynomial a (degree n >= 3, a[0] != 0, a[n] != 0) whose real roots y
// satisfy lower < |y| < upper. Writes at most n roots, not sorted, and returns their number.
//
// Isolation is breadth first: each round splits every interval that still holds several roots, and
// the Sturm counts at all the new points are computed back to back, so that their latencies
// overlap. The isolated roots are then polished together (PolishLockStep).
class RootFinder {
 public:
  RootFinder(const double* a, int n) : a_(a), n_(n) {
    for (int k = 0; k < n; ++k) da_[k] = (k + 1) * a[k + 1];
  }

  int Solve(double lower, double upper, int depth, double* roots) {
    roots_ = roots;
    num_roots_ = 0;
    num_brackets_ = 0;
    BuildSturmChain(a_, n_, &chain_);
    if (chain_.error > kChainMaxError && depth < kMaxFallbackDepth) return SolveByExtrema(upper, depth);
    // Sign changes at 0 and +-infinity from the constant and leading coefficients; no root lies in
    // [0, lower] or beyond upper, so these are the counts at +-lower and +-upper.
    int sign_zero[kMaxN + 1], sign_pinf[kMaxN + 1], sign_minf[kMaxN + 1];
    for (int i = 0; i < chain_.size; ++i) {
      const int d = chain_.member_degree[i];
      const int lead = Sign(chain_.t[d * kStride + i]);
      sign_zero[i] = Sign(chain_.t[i]);
      sign_pinf[i] = lead;
      sign_minf[i] = (d & 1) ? -lead : lead;
    }
    const int v_zero = CountChanges(sign_zero, chain_.size);
    const int v_pinf = CountChanges(sign_pinf, chain_.size);
    const int v_minf = CountChanges(sign_minf, chain_.size);
    const int s_zero = Sign(a_[0]), s_pinf = Sign(a_[n_]), s_minf = (n_ & 1) ? -s_pinf : s_pinf;
    int budget = 60 * n_ + 100;  // Sturm evaluations
    Interval work[2][kMaxWork];
    int num_work = 0;
    work[0][num_work++] = {-upper, -lower, v_minf, v_zero, s_minf, s_zero};
    work[0][num_work++] = {lower, upper, v_zero, v_pinf, s_zero, s_pinf};
    for (int round = 0; num_work > 0; ++round) {
      const Interval* current = work[round & 1];
      Interval* next = work[(round + 1) & 1];
      // Classify; the intervals to split get their split point.
      Interval split[kMaxWork];
      double points[kMaxWork];
      int num_split = 0;
      for (int w = 0; w < num_work; ++w) {
        const Interval& iv = current[w];
        const int count = iv.vlo - iv.vhi;
        const bool sign_change = iv.slo * iv.shi < 0;
        if (!sign_change && count <= 0) continue;
        const double width = iv.hi - iv.lo;
        const double size = std::max(std::abs(iv.lo), std::abs(iv.hi));
        const bool tiny = width <= kTinyWidth * size || budget <= 0 || num_split >= kMaxWork / 2;
        if (sign_change && (count <= 1 || tiny)) {
          // A root of odd multiplicity (a count of 0 with a sign change means the chain is off).
          if (num_brackets_ < kMaxN) brackets_[num_brackets_++] = {iv.lo, iv.hi, iv.slo, 0.0};
        } else if (!sign_change && (tiny || (count == 1 && width <= kTangentWidth * size))) {
          NoSignChange(iv.lo, iv.hi, iv.slo);
        } else {
          split[num_split] = iv;
          points[num_split++] = Split(iv.lo, iv.hi);
        }
      }
      // Sturm counts at all split points (independent evaluations, overlapping in the pipeline).
      int counts[kMaxWork], signs[kMaxWork];
      for (int i = 0; i < num_split; ++i) counts[i] = SignChanges(chain_, points[i], &signs[i]);
      budget -= num_split;
      num_work = 0;
      for (int i = 0; i < num_split; ++i) {
        const Interval& iv = split[i];
        const double m = points[i];
        if (signs[i] != 0) {
          next[num_work++] = {iv.lo, m, iv.vlo, counts[i], iv.slo, signs[i]};
          next[num_work++] = {m, iv.hi, counts[i], iv.vhi, signs[i], iv.shi};
          continue;
        }
        // m is an exact root: step off it on both sides.
        AddRoot(m);
        const double h = (iv.hi - iv.lo) * 0x1p-12;
        int sl, sr;
        const int vl = SignChanges(chain_, m - h, &sl), vr = SignChanges(chain_, m + h, &sr);
        budget -= 2;
        next[num_work++] = {iv.lo, m - h, iv.vlo, vl, iv.slo, sl};
        next[num_work++] = {m + h, iv.hi, vr, iv.vhi, sr, iv.shi};
      }
    }
    Polish(a_, n_, brackets_, num_brackets_);
    // Residual check of the polished roots (independent evaluations again).
    double values[kMaxN], scales[kMaxN];
    for (int i = 0; i < num_brackets_; ++i) Residual(a_, n_, brackets_[i].x, &values[i], &scales[i]);
    for (int i = 0; i < num_brackets_; ++i) {
      if (std::abs(values[i]) <= kResidualTol * scales[i] && num_roots_ < n_) roots_[num_roots_++] = brackets_[i].x;
    }
    return num_roots_;
  }

 private:
  struct Interval {
    double lo, hi;
    int vlo, vhi;  // Sturm sign changes at lo, hi
    int slo, shi;  // signs of p at lo, hi
  };

  // (lo, hi) should hold roots, but p has the same sign slo at both ends: a root of even
  // multiplicity, or two roots too close for the Sturm chain. Looks at the extremum of p in between.
  void NoSignChange(double lo, double hi, int slo) {
    double dlo, dhi, scale;
    Residual(da_, n_ - 1, lo, &dlo, &scale);
    Residual(da_, n_ - 1, hi, &dhi, &scale);
    double xc;
    if (Sign(dlo) * Sign(dhi) < 0) {
      xc = SolveBracketed(da_, n_ - 1, lo, hi, Sign(dlo));
    } else {
      xc = Split(lo, hi);
    }
    double value;
    Residual(a_, n_, xc, &value, &scale);
    if (Sign(value) == -slo && std::abs(value) > 8.0 * (n_ + 1) * kEps * scale) {
      // p changes sign at the extremum: two simple roots.
      AddRoot(SolveBracketed(a_, n_, lo, xc, slo));
      AddRoot(SolveBracketed(a_, n_, xc, hi, -slo));
    } else {
      AddRoot(xc);  // a multiple root, or a cluster double precision cannot separate
    }
  }

  // Isolation without the Sturm chain, for when it is unreliable (near-multiple roots, or roots on
  // scales far apart, where the remainders lose their precision): the real roots of p' (found
  // recursively) split (-upper, upper) into pieces where p is monotone, each holding at most one
  // root, found by the sign of p at the ends. An extremum where |p| has a local minimum small enough
  // to pass the residual check is reported too: a double root, or a double root that rounding turned
  // into a close complex pair.
  int SolveByExtrema(double upper, int depth) {
    double points[kMaxN + 1];
    const int num_extrema = RealRoots(da_, n_ - 1, depth + 1, points + 1);
    int num_points = 1;
    for (int i = 1; i <= num_extrema; ++i) {
      if (points[i] > -upper && points[i] < upper) points[num_points++] = points[i];
    }
    points[0] = -upper;
    points[num_points++] = upper;
    double values[kMaxN + 2], scales[kMaxN + 2];
    for (int i = 0; i < num_points; ++i) Residual(a_, n_, points[i], &values[i], &scales[i]);
    for (int i = 0; i + 1 < num_points; ++i) {
      if (Sign(values[i]) * Sign(values[i + 1]) < 0 && num_brackets_ < kMaxN) {
        brackets_[num_brackets_++] = {points[i], points[i + 1], Sign(values[i]), 0.0};
      }
    }
    Polish(a_, n_, brackets_, num_brackets_);
    for (int i = 0; i < num_brackets_; ++i) AddRoot(brackets_[i].x);
    for (int i = 1; i + 1 < num_points; ++i) {
      const double x = points[i];
      double p = a_[n_], dp = 0.0, hp = 0.0;
      for (int k = n_ - 1; k >= 0; --k) {
        hp = MulAdd(hp, x, dp);
        dp = MulAdd(dp, x, p);
        p = MulAdd(p, x, a_[k]);
      }
      // Only minima of |p| (p p'' > 0): the maximum of |p| between two close roots is no root.
      if (values[i] == 0.0 || p * hp > 0.0) AddRoot(x);
    }
    return num_roots_;
  }

  void AddRoot(double x) {
    if (num_roots_ >= n_) return;
    double value, scale;
    Residual(a_, n_, x, &value, &scale);
    if (!(std::abs(value) <= kResidualTol * scale)) return;
    roots_[num_roots_++] = x;
  }

  // Each round at most doubles the number of intervals holding roots; there are at most n of those.
  static constexpr int kMaxWork = 4 * kMaxN;
  const double* a_;
  int n_;
  double da_[kMaxN];
  SturmChain chain_;
  Bracket brackets_[kMaxN];
  int num_brackets_ = 0;
  double* roots_ = nullptr;
  int num_roots_ = 0;
};

// Roots of c[0] + ... + c[n] x^n with n >= 1, c[0] != 0, c[n] != 0, all finite. Not sorted.
int SolveNonzeroEnds(const double* c, int n, int depth, double* roots) {
  if (n == 1) {
    roots[0] = -c[0] / c[1];
    return std::isfinite(roots[0]) ? 1 : 0;
  }
  if (n == 2) return SolveQuadraticReal(c[2], c[1], c[0], roots);
  // x = 2^e y with |c_0| ~ |c_n| 2^(e n), then a power of two for max |a_k| ~ 1 (both exact).
  int ex[kMaxN + 1];
  for (int k = 0; k <= n; ++k) ex[k] = c[k] != 0.0 ? Exponent(c[k]) : 0;
  const int e = static_cast<int>(std::lround((ex[0] - ex[n]) * kInverse[n]));
  int emax = ex[0];
  for (int k = 1; k <= n; ++k) {
    if (c[k] != 0.0) emax = std::max(emax, ex[k] + k * e);
  }
  const int f = -emax;
  double a[kMaxN + 1];
  if (std::max(std::abs(f), std::abs(n * e + f)) <= 1000 && std::abs(e) <= 1000) {
    const double step = Pow2(e);
    double factor = Pow2(f);
    for (int k = 0; k <= n; ++k, factor *= step) a[k] = c[k] * factor;
  } else {
    for (int k = 0; k <= n; ++k) a[k] = std::ldexp(c[k], k * e + f);
  }
  if (a[0] == 0.0 || a[n] == 0.0 || !std::isfinite(a[0]) || !std::isfinite(a[n])) return 0;
  // Fujiwara: |y| < 2 max_k |a_k / a_n|^(1 / (n - k)); the same for 1 / y from the reversed
  // polynomial. Rounded up to powers of two, plus a factor 2 of margin.
  // (A quotient rounded up makes the bound at most 2x looser, never wrong.)
  double upper_log2 = -1100.0, lower_log2 = -1100.0;
  const int ea0 = Exponent(a[0]), ean = Exponent(a[n]);
  for (int k = 0; k < n; ++k) {
    if (a[k] != 0.0) upper_log2 = std::max(upper_log2, (Exponent(a[k]) + 1 - ean) * kInverse[n - k]);
  }
  for (int k = 1; k <= n; ++k) {
    if (a[k] != 0.0) lower_log2 = std::max(lower_log2, (Exponent(a[k]) + 1 - ea0) * kInverse[k]);
  }
  const int upper_exp = std::min(static_cast<int>(std::ceil(upper_log2)) + 2, 1000);
  const int lower_exp = std::min(static_cast<int>(std::ceil(lower_log2)) + 2, 1000);
  RootFinder finder(a, n);
  const int num = finder.Solve(Pow2(-lower_exp), Pow2(upper_exp), depth, roots);
  int out = 0;
  for (int i = 0; i < num; ++i) {
    const double x = std::abs(e) <= 1000 ? roots[i] * Pow2(e) : std::ldexp(roots[i], e);
    if (std::isfinite(x)) roots[out++] = x;
  }
  return out;
}

int RealRoots(const double* coeffs, int degree, int depth, double* roots) {
  if (degree < 1 || degree > kMaxPolynomialDegree) return 0;
  for (int i = 0; i <= degree; ++i) {
    if (!std::isfinite(coeffs[i])) return 0;
  }
  int n = degree;
  while (n > 0 && coeffs[n] == 0.0) --n;
  if (n == 0) return 0;
  int low = 0;  // multiplicity of the root 0
  while (coeffs[low] == 0.0) ++low;
  const double* c = coeffs + low;
  int m = n - low;
  // Drop leading coefficients that only add roots more than 2^kDropLog2 times larger than all others.
  while (m >= 2) {
    int j = m - 1;
    while (c[j] == 0.0) --j;
    if (j == 0) break;
    // log2 of the size of the roots c_m adds, and of the root bound of the rest.
    const int ej = Exponent(c[j]);
    const double big = (ej - Exponent(c[m])) * kInverse[m - j];
    double rest = (Exponent(c[0]) - ej) * kInverse[j];
    if (big - rest <= kDropLog2) break;  // the usual case: rest can only grow
    for (int k = 1; k < j; ++k) {
      if (c[k] != 0.0) rest = std::max(rest, (Exponent(c[k]) - ej) * kInverse[j - k]);
    }
    if (big - rest <= kDropLog2) break;
    m = j;
  }
  int num = m >= 1 ? SolveNonzeroEnds(c, m, depth, roots) : 0;
  if (low > 0) roots[num++] = 0.0;
  // Ascending order, multiple roots once.
  std::sort(roots, roots + num);
  int out = 0;
  for (int i = 0; i < num; ++i) {
    if (out > 0 && roots[i] - roots[out - 1] <= 4.0 * kEps * std::abs(roots[i])) continue;
    roots[out++] = roots[i];
  }
  return out;
}

}  // namespace

int SolveQuadraticReal(double a, double b, double c, double roots[2]) {
  if (a == 0.0) {
    if (b == 0.0) return 0;
    roots[0] = -c / b;
    return std::isfinite(roots[0]) ? 1 : 0;
  }
  const double disc = b * b - 4.0 * a * c;
  if (!(disc >= 0.0)) return 0;
  const double sq = std::sqrt(disc);
  const double q = -0.5 * (b + (b >= 0 ? sq : -sq));
  if (q == 0.0) {  // b == 0 and c == 0
    roots[0] = 0.0;
    return 1;
  }
  const double r0 = q / a, r1 = c / q;
  roots[0] = std::min(r0, r1);
  roots[1] = std::max(r0, r1);
  return roots[0] == roots[1] ? 1 : 2;
}

int SolveRealPolynomialRoots(const double* coeffs, int degree, double* roots) {
  return RealRoots(coeffs, degree, 0, roots);
}

}  // namespace madsfm
