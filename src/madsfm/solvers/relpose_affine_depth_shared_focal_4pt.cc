#include "madsfm/solvers/relpose_affine_depth_shared_focal_4pt.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "madsfm/geometry/rigid_alignment.h"
#include "madsfm/solvers/univariate.h"

// Derivation (w = 1/f^2, g = scale^2, b0, b1 the shifts, all in normalised units, see below).
// The lifted points P0_i = (d0_i + b0) [p0_i / f; 1] and P1_i = scale (d1_i + b1) [p1_i / f; 1]
// have equal pairwise distances in both views. For a pair (j, k):
//   w Q0_jk(b0) + e0_jk = g (w Q1_jk(b1) + e1_jk),
//   Q0_jk(b0) = ||(d0_j + b0) p0_j - (d0_k + b0) p0_k||^2,   e0_jk = (d0_j - d0_k)^2   (view 1 alike).
// Each equation is linear in v = [w b0^2, w b0, w, 1] and in g u, u = [w b1^2, w b1, w, 1]. Four
// equations (the cycle of pairs (0,1), (1,2), (2,3), (3,0), which involves every point twice; the
// diagonals (0,2), (1,3) are not enforced) give M0 v = g M1 u, so v = g N u with N = M0^-1 M1.
// Writing n_i . u = w a_i(b1) + c_i (a_i quadratic in b1, c_i constant):
//   v3 = 1          ->  g = 1 / (n3 . u)
//   v2 = w          ->  E1: n2.u - w n3.u = 0                 (quadratic in w, coefficients deg <= 2 in b1)
//   v0 v2 = v1^2    ->  E2: (n0.u)(n2.u) - (n1.u)^2 = 0        (quadratic in w, coefficients deg <= 4 in b1)
// The resultant of E1 and E2 with respect to w is a polynomial of degree 8 in b1 (<= 8 solutions, the
// count of the paper); it is built by exact polynomial arithmetic on coefficient arrays and solved by
// Sturm sequences. For each real root: w is the common root of E1, E2, g = 1 / (n3.u), b0 = v1 / v2;
// then up to 3 Newton steps on the 4 enforced equations in (w, g, b0, b1) repair roots where the
// elimination is ill-conditioned. R, t by rigid alignment of the 4 lifted point pairs.
//
// Normalisation: pixel coordinates are divided by their RMS radius s (over both views), depth priors
// by the mean absolute prior m0, m1 of each view. Then f = s / sqrt(w'), shift_v = m_v b_v',
// scale = sqrt(g') m0 / m1. If M0 is worse conditioned than M1 the views are swapped for the algebra
// (g' -> 1/g', b0 <-> b1) and the solution is mapped back before the alignment.

namespace madsfm {
namespace {

constexpr int kPairs[4][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}};

// Polynomial products on coefficient arrays (lowest order first): r = a * b.
template <int NA, int NB>
void PolyMul(const double (&a)[NA], const double (&b)[NB], double (&r)[NA + NB - 1]) {
  for (int i = 0; i < NA + NB - 1; ++i) r[i] = 0.0;
  for (int i = 0; i < NA; ++i)
    for (int j = 0; j < NB; ++j) r[i + j] += a[i] * b[j];
}

// One normalised solution of the algebraic system.
struct RawSolution {
  double w, g, b0, b1;
};

// Rows [C, 2B, A, e] of the four pair equations of one view: w Q(b) + e = C w b^2 + 2B w b + A w + e.
Eigen::Matrix4d PairMatrix(const Eigen::Vector2d x[4], const double z[4]) {
  Eigen::Matrix4d M;
  for (int r = 0; r < 4; ++r) {
    const int j = kPairs[r][0], k = kPairs[r][1];
    const Eigen::Vector2d D = z[j] * x[j] - z[k] * x[k];
    const Eigen::Vector2d E = x[j] - x[k];
    const double dz = z[j] - z[k];
    // Q(b) = ||D + b E||^2 + ... : the 2-D part carries w, the z part (dz^2) does not.
    M(r, 0) = E.squaredNorm();
    M(r, 1) = 2.0 * D.dot(E);
    M(r, 2) = D.squaredNorm();
    M(r, 3) = dz * dz;
  }
  return M;
}

// Solves M0 v = g M1 u for (w, g, b0, b1); returns the number of solutions written to sols (<= 8).
// Only algebraic validity (finite, w > 0, g > 0) is checked here.
int SolveNormalised(const Eigen::Matrix4d& M0_inv, const Eigen::Matrix4d& M1, RawSolution sols[8]) {
  const Eigen::Matrix4d N = M0_inv * M1;
  if (!N.allFinite()) return 0;
  // n_i . u = w a_i(b) + c_i with a_i(b) = N(i,0) b^2 + N(i,1) b + N(i,2), c_i = N(i,3).
  double a[4][3];
  double c[4];
  for (int i = 0; i < 4; ++i) {
    a[i][0] = N(i, 2);
    a[i][1] = N(i, 1);
    a[i][2] = N(i, 0);
    c[i] = N(i, 3);
  }
  // E1 = A2 w^2 + A1 w + A0.
  const double A2[3] = {-a[3][0], -a[3][1], -a[3][2]};
  const double A1[3] = {a[2][0] - c[3], a[2][1], a[2][2]};
  const double A0 = c[2];
  // E2 = B2 w^2 + B1 w + B0.
  double a0a2[5], a1a1[5];
  PolyMul(a[0], a[2], a0a2);
  PolyMul(a[1], a[1], a1a1);
  double B2[5];
  for (int i = 0; i < 5; ++i) B2[i] = a0a2[i] - a1a1[i];
  double B1[3];
  for (int i = 0; i < 3; ++i) B1[i] = a[0][i] * c[2] + c[0] * a[2][i] - 2.0 * a[1][i] * c[1];
  const double B0 = c[0] * c[2] - c[1] * c[1];

  // Resultant: P^2 - Q S with P = A2 B0 - A0 B2, Q = A2 B1 - A1 B2, S = A1 B0 - A0 B1.
  double P[5];
  for (int i = 0; i < 5; ++i) P[i] = -A0 * B2[i] + (i < 3 ? A2[i] * B0 : 0.0);
  double A2B1[5], A1B2[7];
  PolyMul(A2, B1, A2B1);
  PolyMul(A1, B2, A1B2);
  double Q[7];
  for (int i = 0; i < 7; ++i) Q[i] = (i < 5 ? A2B1[i] : 0.0) - A1B2[i];
  double S[3];
  for (int i = 0; i < 3; ++i) S[i] = A1[i] * B0 - A0 * B1[i];
  double PP[9], QS[9];
  PolyMul(P, P, PP);
  PolyMul(Q, S, QS);
  double res[9];
  for (int i = 0; i < 9; ++i) res[i] = PP[i] - QS[i];

  double roots[8];
  const int num_roots = SolveRealPolynomialRoots(res, 8, roots);
  int num_sols = 0;
  for (int r = 0; r < num_roots; ++r) {
    const double b = roots[r];
    const double a2v = EvaluatePolynomial(A2, 2, b), a1v = EvaluatePolynomial(A1, 2, b);
    const double b2v = EvaluatePolynomial(B2, 4, b), b1v = EvaluatePolynomial(B1, 2, b);
    // w is the common root of E1 and E2 (real at a simple real root of the resultant: a shared complex
    // root would be shared with its conjugate, a double root of the resultant). Take the root of E1
    // (stable quadratic formula) that best satisfies E2; this stays accurate where the closed form
    // (A2 B0 - A0 B2) / (A1 B2 - A2 B1) divides by a tiny number. Both roots are kept if both satisfy E2.
    double w_cand[2];
    int num_w = 0;
    {
      double wr[2];
      int nw = SolveQuadraticReal(a2v, a1v, A0, wr);
      const double disc = a1v * a1v - 4.0 * a2v * A0;
      if (nw == 0 && a2v != 0.0 && disc >= -1e-10 * (a1v * a1v + std::abs(4.0 * a2v * A0))) {
        wr[0] = -0.5 * a1v / a2v;  // a double root pushed to a complex pair by rounding
        nw = 1;
      }
      double e2[2];
      for (int k = 0; k < nw; ++k) {
        const double x = wr[k];
        const double mag = (std::abs(b2v) * std::abs(x) + std::abs(b1v)) * std::abs(x) + std::abs(B0);
        e2[k] = mag > 0.0 ? std::abs((b2v * x + b1v) * x + B0) / mag : 0.0;
      }
      if (nw == 1) {
        w_cand[num_w++] = wr[0];
      } else if (nw == 2) {
        const int best = e2[1] < e2[0] ? 1 : 0;
        w_cand[num_w++] = wr[best];
        if (e2[1 - best] <= 1e-8) w_cand[num_w++] = wr[1 - best];
      }
    }
    for (int k = 0; k < num_w && num_sols < 8; ++k) {
      const double w = w_cand[k];
      if (!(w > 0.0) || !std::isfinite(w)) continue;
      const double n1u = w * EvaluatePolynomial(a[1], 2, b) + c[1];
      const double n2u = w * EvaluatePolynomial(a[2], 2, b) + c[2];
      const double n3u = w * EvaluatePolynomial(a[3], 2, b) + c[3];
      const double g = 1.0 / n3u;
      if (!(g > 0.0) || !std::isfinite(g)) continue;
      const double b0 = n1u / n2u;  // v1 / v2
      if (!std::isfinite(b0)) continue;
      sols[num_sols++] = {w, g, b0, b};
    }
  }
  return num_sols;
}

// Residuals of the 4 enforced equations w Q0_r(b0) + e0_r - g (w Q1_r(b1) + e1_r) and their Jacobian
// with respect to (w, g, b0, b1).
Eigen::Vector4d PairResiduals(const Eigen::Matrix4d& M0, const Eigen::Matrix4d& M1, const RawSolution& x,
                              Eigen::Matrix4d* J) {
  Eigen::Vector4d F;
  for (int r = 0; r < 4; ++r) {
    const double q0 = (M0(r, 0) * x.b0 + M0(r, 1)) * x.b0 + M0(r, 2);
    const double q1 = (M1(r, 0) * x.b1 + M1(r, 1)) * x.b1 + M1(r, 2);
    F(r) = x.w * q0 + M0(r, 3) - x.g * (x.w * q1 + M1(r, 3));
    if (J != nullptr) {
      (*J)(r, 0) = q0 - x.g * q1;
      (*J)(r, 1) = -(x.w * q1 + M1(r, 3));
      (*J)(r, 2) = x.w * (2.0 * M0(r, 0) * x.b0 + M0(r, 1));
      (*J)(r, 3) = -x.g * x.w * (2.0 * M1(r, 0) * x.b1 + M1(r, 1));
    }
  }
  return F;
}

// A few Newton steps on the 4 enforced equations; the elimination loses accuracy for roots where E1, E2
// or the recovery of g, b0 are ill-conditioned. A step is kept only if it reduces the residual.
void PolishSolution(const Eigen::Matrix4d& M0, const Eigen::Matrix4d& M1, RawSolution* x) {
  Eigen::Matrix4d J;
  Eigen::Vector4d F = PairResiduals(M0, M1, *x, &J);
  double norm = F.squaredNorm();
  for (int it = 0; it < 3 && norm > 0.0; ++it) {
    const Eigen::Vector4d step = J.partialPivLu().solve(F);
    if (!step.allFinite()) return;
    const RawSolution y = {x->w - step(0), x->g - step(1), x->b0 - step(2), x->b1 - step(3)};
    Eigen::Matrix4d Jy;
    const Eigen::Vector4d Fy = PairResiduals(M0, M1, y, &Jy);
    const double norm_y = Fy.squaredNorm();
    if (!(norm_y < norm)) return;
    *x = y;
    F = Fy;
    J = Jy;
    norm = norm_y;
  }
}

// 1-norm condition number estimate of a 4x4 matrix given its inverse.
double Condition1(const Eigen::Matrix4d& M, const Eigen::Matrix4d& M_inv) {
  return M.cwiseAbs().colwise().sum().maxCoeff() * M_inv.cwiseAbs().colwise().sum().maxCoeff();
}

}  // namespace

int SolveRelposeAffineDepthSharedFocal4pt(const std::vector<Eigen::Vector2d>& p0,
                                          const std::vector<Eigen::Vector2d>& p1, const std::vector<double>& d0,
                                          const std::vector<double>& d1, std::vector<AffineDepthPose>* models) {
  models->clear();
  if (p0.size() < 4 || p1.size() < 4 || d0.size() < 4 || d1.size() < 4) return 0;

  // Normalisation.
  double sq_radius = 0.0, m0 = 0.0, m1 = 0.0;
  for (int i = 0; i < 4; ++i) {
    sq_radius += p0[i].squaredNorm() + p1[i].squaredNorm();
    m0 += std::abs(d0[i]);
    m1 += std::abs(d1[i]);
  }
  const double s = std::sqrt(sq_radius / 8.0);
  m0 *= 0.25;
  m1 *= 0.25;
  if (!(s > 0.0) || !(m0 > 0.0) || !(m1 > 0.0) || !std::isfinite(s) || !std::isfinite(m0) || !std::isfinite(m1)) {
    return 0;
  }
  Eigen::Vector2d x0[4], x1[4];
  double z0[4], z1[4];
  for (int i = 0; i < 4; ++i) {
    x0[i] = p0[i] / s;
    x1[i] = p1[i] / s;
    z0[i] = d0[i] / m0;
    z1[i] = d1[i] / m1;
  }

  const Eigen::Matrix4d M0 = PairMatrix(x0, z0);
  const Eigen::Matrix4d M1 = PairMatrix(x1, z1);
  const Eigen::Matrix4d M0_inv = M0.inverse();
  const Eigen::Matrix4d M1_inv = M1.inverse();
  const double cond0 = Condition1(M0, M0_inv), cond1 = Condition1(M1, M1_inv);
  const bool ok0 = std::isfinite(cond0) && M0_inv.allFinite(), ok1 = std::isfinite(cond1) && M1_inv.allFinite();
  if (!ok0 && !ok1) return 0;
  const bool swap = !ok0 || (ok1 && cond1 < cond0);

  RawSolution sols[8];
  const int num_sols = swap ? SolveNormalised(M1_inv, M0, sols) : SolveNormalised(M0_inv, M1, sols);
  models->reserve(num_sols);
  for (int k = 0; k < num_sols; ++k) {
    RawSolution sol = sols[k];
    if (swap) sol = {sol.w, 1.0 / sol.g, sol.b1, sol.b0};
    PolishSolution(M0, M1, &sol);
    if (!(sol.w > 0.0) || !(sol.g > 0.0)) continue;
    bool positive = true;
    for (int i = 0; i < 4; ++i) positive = positive && (z0[i] + sol.b0 > 0.0) && (z1[i] + sol.b1 > 0.0);
    if (!positive) continue;

    AffineDepthPose model;
    const double f = s / std::sqrt(sol.w);
    model.f0 = model.f1 = f;
    model.shift0 = m0 * sol.b0;
    model.shift1 = m1 * sol.b1;
    model.scale = std::sqrt(sol.g) * m0 / m1;
    Eigen::Vector3d P0[4], P1[4];
    for (int i = 0; i < 4; ++i) {
      P0[i] = model.Depth0(d0[i]) * Eigen::Vector3d(p0[i].x() / f, p0[i].y() / f, 1.0);
      P1[i] = model.Depth1(d1[i]) * Eigen::Vector3d(p1[i].x() / f, p1[i].y() / f, 1.0);
    }
    if (!AlignRigid(P0, P1, 4, &model.R, &model.t)) continue;
    if (!std::isfinite(f) || !(f > 0.0) || !std::isfinite(model.scale) || !(model.scale > 0.0) ||
        !std::isfinite(model.shift0) || !std::isfinite(model.shift1) || !model.t.allFinite()) {
      continue;
    }
    models->push_back(model);
  }
  return static_cast<int>(models->size());
}

}  // namespace madsfm
