// Real roots of univariate polynomials, the common last step of the closed-form solvers.
#pragma once

namespace madsfm {

// Largest degree SolveRealPolynomialRoots accepts.
inline constexpr int kMaxPolynomialDegree = 20;

// Finds the real roots of c[0] + c[1] x + ... + c[degree] x^degree (degree <= kMaxPolynomialDegree).
// Roots are written to `roots` (room for `degree` values) in increasing order; returns how many.
// - Method: x is rescaled by a power of two that balances |c_0| and |c_n| (exact); Sturm sequences
//   isolate the roots inside Fujiwara's bounds (geometric bisection over wide ranges), and all
//   isolated roots are polished together by bracketed Laguerre / Halley steps to machine precision.
//   When the Sturm chain loses its precision (near-multiple roots, clusters, roots on scales far
//   apart) the roots are isolated by the extrema of the polynomial instead (roots of its derivative).
// - Every reported root x satisfies |p(x)| <= 1e-10 * sum_i |c_i x^i|; a root of odd multiplicity
//   is found whenever p changes sign around it, even if the Sturm counts disagree.
// - Multiple roots, and clusters that double precision cannot separate, are reported once (e.g. two
//   roots 1e-6 apart are normally both reported, as separate roots, to the accuracy the coefficients
//   allow). A double root that rounding turned into a close complex pair is still reported when it
//   passes the residual check.
// - Leading zero coefficients drop the degree, and so do leading coefficients that would only add
//   roots more than 2^50 times larger than all the others; zero trailing coefficients give the root 0.
// - Non-finite coefficients, or a zero or constant polynomial, give 0 roots.
int SolveRealPolynomialRoots(const double* coeffs, int degree, double* roots);

// Real roots of a x^2 + b x + c (a may be 0). Returns the number written to roots[0..1].
int SolveQuadraticReal(double a, double b, double c, double roots[2]);

// Evaluates c[0] + c[1] x + ... + c[degree] x^degree (Horner).
inline double EvaluatePolynomial(const double* coeffs, int degree, double x) {
  double v = coeffs[degree];
  for (int i = degree - 1; i >= 0; --i) v = v * x + coeffs[i];
  return v;
}

}  // namespace madsfm
