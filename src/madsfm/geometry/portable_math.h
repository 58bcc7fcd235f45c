// Elementary functions that give the same bits on every x86-64 CPU (docs/robustness.md, "Same results on any x86-64
// CPU"). glibc's libm picks an implementation of exp, log, pow, sin, cos, tan, atan, atan2, acos, asin at run time
// by CPU (FMA/AVX2 variants, ifunc); they differ from the baseline (SSE2) ones by 1 ulp on about 1 in 1500 inputs,
// which is enough to change an estimate in its last bits. These use only +, -, *, / and sqrt (IEEE-exact, with
// -ffp-contract=off no FMA is formed), so the estimator calls them instead of <cmath> in every path that decides
// or produces a result. Accuracy: within 1-6 ulp of <cmath>, Pow within 4 + 2 |y ln x| ulp
// (tests/madsfm/geometry/portable_math_test.cc).
#pragma once

namespace madsfm::portable {

double Exp(double x);
double Log(double x);  // x <= 0: -inf (0) or NaN (< 0), as std::log
double Pow(double x, double y);  // x > 0 (or x == 0, y > 0); other x: NaN
double PowInt(double x, int n);  // x^n by repeated squaring (n >= 0)
double Sin(double x);  // |x| <= 2^20; beyond: NaN (the estimator's angles are at most a few pi)
double Cos(double x);
void SinCos(double x, double* s, double* c);
double Atan(double x);
double Atan2(double y, double x);
double Acos(double x);  // |x| > 1: NaN

}  // namespace madsfm::portable
