#include "madsfm/solvers/univariate.h"

#include <algorithm>
#include <cmath>

namespace madsfm {
namespace {

struct Poly {
  int degree = -1;  // -1: the zero polynomial
  double c[kMaxPolynomialDegree + 1];
};

double Eval(const Poly& p, double x) { return p.degree < 0 ? 0.0 : EvaluatePolynomial(p.c, p.degree, x); }

// r = -(a mod b); b must have degree >= 0.
void NegRemainder(const Poly& a, const Poly& b, Poly* r) {
  double w[kMaxPolynomialDegree + 1];
  std::copy(a.c, a.c + a.degree + 1, w);
  const double lead = b.c[b.degree];
  for (int k = a.degree; k >= b.degree; --k) {
    const double q = w[k] / lead;
    for (int j = 0; j <= b.degree; ++j) w[k - b.degree + j] -= q * b.c[j];
    w[k] = 0.0;
  }
  double scale = 0.0;
  for (int j = 0; j < b.degree; ++j) scale = std::max(scale, std::abs(a.c[j]));
  scale = std::max(scale, std::abs(a.c[a.degree]));
  r->degree = b.degree - 1;
  while (r->degree >= 0 && std::abs(w[r->degree]) <= 1e-14 * scale) --r->degree;
  for (int j = 0; j <= r->degree; ++j) r->c[j] = -w[j];
}

struct Sturm {
  Poly s[kMaxPolynomialDegree + 1];
  int n = 0;
  int SignChanges(double x) const {
    int changes = 0;
    double prev = 0.0;
    for (int i = 0; i < n; ++i) {
      const double v = Eval(s[i], x);
      if (v == 0.0) continue;
      if (prev != 0.0 && ((v > 0) != (prev > 0))) ++changes;
      prev = v;
    }
    return changes;
  }
};

// Polishes the single root of p in [a, b] (p(a), p(b) of opposite sign, or a multiple root).
double Polish(const Poly& p, const Poly& dp, double a, double b) {
  double fa = Eval(p, a);
  const double fb = Eval(p, b);
  if (fa == 0.0) return a;
  if (fb == 0.0) return b;
  if ((fa > 0) == (fb > 0)) {
    // Even multiplicity: the root is a root of p' too; Newton on p from the midpoint.
    double x = 0.5 * (a + b);
    for (int it = 0; it < 60; ++it) {
      const double d = Eval(dp, x);
      if (d == 0.0) break;
      const double nx = x - Eval(p, x) / d;
      if (!(nx > a && nx < b)) break;
      if (std::abs(nx - x) <= 1e-16 * std::max(1.0, std::abs(x))) { x = nx; break; }
      x = nx;
    }
    return x;
  }
  double x = 0.5 * (a + b);
  for (int it = 0; it < 200; ++it) {
    const double fx = Eval(p, x);
    if (fx == 0.0) return x;
    if ((fx > 0) == (fa > 0)) { a = x; fa = fx; } else { b = x; }
    const double d = Eval(dp, x);
    double nx = d != 0.0 ? x - fx / d : 0.5 * (a + b);
    if (!(nx > a && nx < b)) nx = 0.5 * (a + b);
    if (std::abs(nx - x) <= 4e-16 * std::max(1.0, std::abs(x)) || b - a <= 4e-16 * std::max(1.0, std::abs(x))) return nx;
    x = nx;
  }
  return x;
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
  if (degree < 1 || degree > kMaxPolynomialDegree) return 0;
  double cmax = 0.0;
  for (int i = 0; i <= degree; ++i) {
    if (!std::isfinite(coeffs[i])) return 0;
    cmax = std::max(cmax, std::abs(coeffs[i]));
  }
  if (cmax == 0.0) return 0;
  while (degree > 0 && std::abs(coeffs[degree]) <= 1e-15 * cmax) --degree;
  if (degree == 0) return 0;
  if (degree == 1) {
    roots[0] = -coeffs[0] / coeffs[1];
    return 1;
  }
  if (degree == 2) return SolveQuadraticReal(coeffs[2], coeffs[1], coeffs[0], roots);

  Sturm st;
  Poly& p = st.s[0];
  p.degree = degree;
  for (int i = 0; i <= degree; ++i) p.c[i] = coeffs[i] / coeffs[degree];
  Poly& dp = st.s[1];
  dp.degree = degree - 1;
  for (int i = 1; i <= degree; ++i) dp.c[i - 1] = i * p.c[i];
  st.n = 2;
  while (st.n <= degree && st.s[st.n - 1].degree > 0) {
    NegRemainder(st.s[st.n - 2], st.s[st.n - 1], &st.s[st.n]);
    if (st.s[st.n].degree < 0) break;
    ++st.n;
  }

  // Cauchy bound on the magnitude of the roots of the monic p.
  double bound = 0.0;
  for (int i = 0; i < degree; ++i) bound = std::max(bound, std::abs(p.c[i]));
  bound += 1.0;

  struct Interval { double a, b; int ca, cb; int depth; };
  Interval stack[2 * kMaxPolynomialDegree * 64 + 4];
  int top = 0;
  stack[top++] = {-bound, bound, st.SignChanges(-bound), st.SignChanges(bound), 0};
  int found = 0;
  while (top > 0) {
    const Interval iv = stack[--top];
    const int count = iv.ca - iv.cb;
    if (count <= 0) continue;
    const double width = iv.b - iv.a;
    if (count == 1 || iv.depth > 60 || width <= 1e-14 * std::max(1.0, std::abs(iv.a))) {
      if (found < degree) roots[found++] = Polish(p, dp, iv.a, iv.b);
      continue;
    }
    const double m = 0.5 * (iv.a + iv.b);
    const int cm = st.SignChanges(m);
    if (top + 2 > static_cast<int>(sizeof(stack) / sizeof(stack[0]))) continue;
    stack[top++] = {m, iv.b, cm, iv.cb, iv.depth + 1};
    stack[top++] = {iv.a, m, iv.ca, cm, iv.depth + 1};
  }
  std::sort(roots, roots + found);
  return found;
}

}  // namespace madsfm
