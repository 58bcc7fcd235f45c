// Real roots of univariate polynomials, the common last step of the closed-form solvers.
#pragma once

namespace madsfm {

// Largest degree SolveRealPolynomialRoots accepts.
inline constexpr int kMaxPolynomialDegree = 20;

// Finds the real roots of c[0] + c[1] x + ... + c[degree] x^degree by Sturm sequences (root
// isolation by bisection on the Sturm count, then safeguarded Newton / bisection polishing to
// machine precision). Leading zero coefficients are allowed (the degree drops). Roots are
// written to `roots` (room for `degree` values) in increasing order; returns how many. Multiple
// roots are reported once. Non-finite coefficients give 0 roots.
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
