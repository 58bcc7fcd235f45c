#include "madsfm/solvers/relpose_affine_depth_two_focal_4pt.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "madsfm/geometry/rigid_alignment.h"
#include "madsfm/solvers/affine_depth_solver_utils.h"
#include "madsfm/solvers/univariate.h"

// Method. With w0 = 1/f0^2, w1 = 1/f1^2 and g = scale^2, the squared distance of lifted points j, k
// is w0 (A0 b0^2 + B0 b0 + C0) + E0 in view 0 and g (w1 (A1 b1^2 + B1 b1 + C1) + E1) in view 1
// (PairDistanceCoefficients). Each equation is linear in v = [w0 b0^2, w0 b0, w0, 1] and
// u = [w1 b1^2, w1 b1, w1, 1]: c0 . v = g c1 . u with c = (A, B, C, E).
// Equations used: pairs (0,1), (0,2), (0,3), (1,2) form M0 v = g M1 u, pair (1,3) is the 5th
// equation; pair (2,3) is not enforced. With N = M0^-1 M1, v = g N u and the 5th equation gives
// h . u = 0 with h = N^T c0 - c1, i.e. w1 = -h3 / (h0 b1^2 + h1 b1 + h2). Scaling u by
// hb = h0 b1^2 + h1 b1 + h2 gives U = [-h3 b1^2, -h3 b1, -h3, hb], quadratic in b1, and with
// P_i = n_i . U: g = hb / P3, w0 = P2 / P3, b0 = P1 / P2, while v0 v2 = v1^2 becomes the quartic
// P0 P2 - P1^2 = 0 (at most 4 solutions, as in the paper). If M1 is better conditioned than M0 the
// same steps run with the views swapped and the solutions are mapped back; one guarded Newton step
// on the 5 equations polishes each solution. Pixel coordinates are divided by each view's RMS
// radius and depths by each view's mean |d| beforehand. R, t come from the least-squares rigid
// alignment of the 4 lifted points (the 6th distance is not enforced).

namespace madsfm {
namespace {

struct FocalShiftSolution {
  double w0, b0, w1, b1, g;
};

constexpr int kPairs[5][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}};

// Solutions of M0 v = g M1 u and c0 . v = g c1 . u (M0 invertible) with g, w0, w1 > 0.
int SolveFocalsAndShifts(const Eigen::Matrix4d& M0, const Eigen::Matrix4d& M1, const Eigen::Vector4d& c0,
                         const Eigen::Vector4d& c1, FocalShiftSolution* out) {
  const Eigen::Matrix4d N = M0.inverse() * M1;
  const Eigen::Vector4d h = N.transpose() * c0 - c1;
  if (!N.allFinite() || !h.allFinite()) return 0;
  const double h_scale = h.cwiseAbs().maxCoeff();
  // h3 = 0: w1 cannot be recovered (the 5th equation does not involve it).
  if (!(std::abs(h(3)) > 1e-12 * h_scale)) return 0;
  // U_j(b) as ascending quadratic coefficients; P_i = sum_j N(i, j) U_j.
  const double U[4][3] = {{0.0, 0.0, -h(3)}, {0.0, -h(3), 0.0}, {-h(3), 0.0, 0.0}, {h(2), h(1), h(0)}};
  double P[4][3];
  for (int i = 0; i < 4; ++i) {
    for (int k = 0; k < 3; ++k) {
      P[i][k] = N(i, 0) * U[0][k] + N(i, 1) * U[1][k] + N(i, 2) * U[2][k] + N(i, 3) * U[3][k];
    }
  }
  double c[5] = {0.0, 0.0, 0.0, 0.0, 0.0};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) c[i + j] += P[0][i] * P[2][j] - P[1][i] * P[1][j];
  }
  double roots[4];
  const int num_roots = SolveRealPolynomialRoots(c, 4, roots);
  int n = 0;
  for (int r = 0; r < num_roots; ++r) {
    const double b1 = roots[r];
    const double hb = (h(0) * b1 + h(1)) * b1 + h(2);
    const double p1 = EvaluatePolynomial(P[1], 2, b1);
    const double p2 = EvaluatePolynomial(P[2], 2, b1);
    const double p3 = EvaluatePolynomial(P[3], 2, b1);
    const FocalShiftSolution s = {p2 / p3, p1 / p2, -h(3) / hb, b1, hb / p3};
    if (!(s.w0 > 0.0) || !(s.w1 > 0.0) || !(s.g > 0.0)) continue;
    if (!std::isfinite(s.w0) || !std::isfinite(s.w1) || !std::isfinite(s.g) || !std::isfinite(s.b0)) continue;
    out[n++] = s;
  }
  return n;
}

// Residuals F_r = w0 Q0_r(b0) + E0_r - g (w1 Q1_r(b1) + E1_r) of the 5 equations and, if J is not
// null, their Jacobian with respect to (w0, b0, w1, b1, g). rows.row(r) = (c0_r, c1_r).
void EvaluateEquations(const Eigen::Matrix<double, 5, 8>& rows, const FocalShiftSolution& s,
                       Eigen::Matrix<double, 5, 1>* F, Eigen::Matrix<double, 5, 5>* J) {
  for (int r = 0; r < 5; ++r) {
    const double q0 = (rows(r, 0) * s.b0 + rows(r, 1)) * s.b0 + rows(r, 2);
    const double q1 = (rows(r, 4) * s.b1 + rows(r, 5)) * s.b1 + rows(r, 6);
    (*F)(r) = s.w0 * q0 + rows(r, 3) - s.g * (s.w1 * q1 + rows(r, 7));
    if (J == nullptr) continue;
    (*J)(r, 0) = q0;
    (*J)(r, 1) = s.w0 * (2.0 * rows(r, 0) * s.b0 + rows(r, 1));
    (*J)(r, 2) = -s.g * q1;
    (*J)(r, 3) = -s.g * s.w1 * (2.0 * rows(r, 4) * s.b1 + rows(r, 5));
    (*J)(r, 4) = -(s.w1 * q1 + rows(r, 7));
  }
}

// One Newton step on the 5 equations, kept only if it lowers the residual: the closed form loses
// accuracy when N is badly conditioned (worst relative residual ~1e-6 without, ~1e-9 with it).
void Polish(const Eigen::Matrix<double, 5, 8>& rows, FocalShiftSolution* s) {
  Eigen::Matrix<double, 5, 1> F, F_new;
  Eigen::Matrix<double, 5, 5> J;
  EvaluateEquations(rows, *s, &F, &J);
  const Eigen::Matrix<double, 5, 1> dx = J.partialPivLu().solve(F);
  if (!dx.allFinite()) return;
  const FocalShiftSolution n = {s->w0 - dx(0), s->b0 - dx(1), s->w1 - dx(2), s->b1 - dx(3), s->g - dx(4)};
  EvaluateEquations(rows, n, &F_new, nullptr);
  if (F_new.squaredNorm() < F.squaredNorm()) *s = n;
}

}  // namespace

int SolveRelposeAffineDepthTwoFocal4pt(const std::vector<Eigen::Vector2d>& p0, const std::vector<Eigen::Vector2d>& p1,
                                       const std::vector<double>& d0, const std::vector<double>& d1,
                                       std::vector<AffineDepthPose>* models) {
  models->clear();
  if (!HasFiniteSample(p0, p1, d0, d1, 4)) return 0;
  const double s0 = MeanAbs(d0.data(), 4), s1 = MeanAbs(d1.data(), 4);
  const double r0 = RmsNorm(p0.data(), 4), r1 = RmsNorm(p1.data(), 4);
  if (!(s0 > 0.0) || !(s1 > 0.0) || !(r0 > 0.0) || !(r1 > 0.0)) return 0;
  double dn0[4], dn1[4];
  Eigen::Vector2d pn0[4], pn1[4];
  for (int i = 0; i < 4; ++i) {
    dn0[i] = d0[i] / s0;
    dn1[i] = d1[i] / s1;
    pn0[i] = p0[i] / r0;
    pn1[i] = p1[i] / r1;
  }

  Eigen::Matrix4d M0, M1;
  Eigen::Vector4d c0, c1;
  Eigen::Matrix<double, 5, 8> rows;
  for (int r = 0; r < 5; ++r) {
    const int j = kPairs[r][0], k = kPairs[r][1];
    const Eigen::Vector4d e0 = PairDistanceCoefficients(pn0[j], pn0[k], dn0[j], dn0[k]);
    const Eigen::Vector4d e1 = PairDistanceCoefficients(pn1[j], pn1[k], dn1[j], dn1[k]);
    rows.row(r) << e0.transpose(), e1.transpose();
    if (r < 4) {
      M0.row(r) = e0.transpose();
      M1.row(r) = e1.transpose();
    } else {
      c0 = e0;
      c1 = e1;
    }
  }
  const double q0 = HadamardRatio<4>(M0), q1 = HadamardRatio<4>(M1);
  constexpr double kMinHadamardRatio = 1e-12;
  if (!(std::max(q0, q1) > kMinHadamardRatio)) return 0;

  FocalShiftSolution sol[4];
  int num_sol;
  if (q0 >= q1) {
    num_sol = SolveFocalsAndShifts(M0, M1, c0, c1, sol);
  } else {
    num_sol = SolveFocalsAndShifts(M1, M0, c1, c0, sol);
    for (int i = 0; i < num_sol; ++i) sol[i] = {sol[i].w1, sol[i].b1, sol[i].w0, sol[i].b0, 1.0 / sol[i].g};
  }

  models->reserve(num_sol);
  for (int s = 0; s < num_sol; ++s) {
    Polish(rows, &sol[s]);
    if (!(sol[s].w0 > 0.0) || !(sol[s].w1 > 0.0) || !(sol[s].g > 0.0)) continue;
    const double f0n = 1.0 / std::sqrt(sol[s].w0), f1n = 1.0 / std::sqrt(sol[s].w1), a = std::sqrt(sol[s].g);
    Eigen::Vector3d P0[4], P1[4];
    bool positive = true;
    for (int i = 0; i < 4; ++i) {
      const double z0 = dn0[i] + sol[s].b0, z1 = a * (dn1[i] + sol[s].b1);
      if (!(z0 > 0.0) || !(z1 > 0.0)) positive = false;
      P0[i] = Eigen::Vector3d(z0 * pn0[i](0) / f0n, z0 * pn0[i](1) / f0n, z0);
      P1[i] = Eigen::Vector3d(z1 * pn1[i](0) / f1n, z1 * pn1[i](1) / f1n, z1);
    }
    if (!positive) continue;
    AffineDepthPose m;
    if (!AlignRigid(P0, P1, 4, &m.R, &m.t)) continue;
    m.t *= s0;
    m.scale = a * s0 / s1;
    m.shift0 = sol[s].b0 * s0;
    m.shift1 = sol[s].b1 * s1;
    m.f0 = f0n * r0;
    m.f1 = f1n * r1;
    if (!IsValidAffineDepthModel(m, d0.data(), d1.data(), 4)) continue;
    models->push_back(m);
  }
  return static_cast<int>(models->size());
}

}  // namespace madsfm
