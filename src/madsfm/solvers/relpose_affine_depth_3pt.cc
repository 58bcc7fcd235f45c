#include "madsfm/solvers/relpose_affine_depth_3pt.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "madsfm/solvers/affine_depth_solver_utils.h"
#include "madsfm/solvers/univariate.h"

// Method. Lifted points P0_i = (d0_i + b0) u0_i, P1_i = a (d1_i + b1) u1_i with u = [x; 1]. For each
// pair (j, k) the squared distances agree: ||P0_j - P0_k||^2 = ||P1_j - P1_k||^2, i.e. with g = a^2
//   m0_jk . [b0^2, b0, 1] = g m1_jk . [b1^2, b1, 1],  m_jk = (A, B, C + E) of PairDistanceCoefficients.
// The pairs (0,1), (0,2), (1,2) give M0 [b0^2, b0, 1]^T = g M1 [b1^2, b1, 1]^T. With N = M0^-1 M1 and
// w = [b1^2, b1, 1]: b0^2 = g n0.w, b0 = g n1.w, 1 = g n2.w, hence g = 1 / n2.w, b0 = n1.w / n2.w and
// (n1.w)^2 - (n0.w)(n2.w) = 0, a quartic in b1 (at most 4 solutions, as in the paper). If M1 is
// better conditioned than M0 the same steps run on the view-swapped problem and the solutions are
// mapped back. With the 3 distances equal the lifted triangles are congruent and R, t follow exactly
// from two orthonormal triangle frames. Depths are divided by each view's mean |d| beforehand.

namespace madsfm {
namespace {

struct ShiftSolution {
  double b0, b1, g;
};

// Solutions of M0 [b0^2, b0, 1] = g M1 [b1^2, b1, 1] with g > 0 (M0 invertible). Returns the count.
int SolveShifts(const Eigen::Matrix3d& M0, const Eigen::Matrix3d& M1, ShiftSolution* out) {
  const Eigen::Matrix3d N = M0.inverse() * M1;
  if (!N.allFinite()) return 0;
  // n_i.w as polynomials in b1, ascending coefficients.
  double p[3][3];
  for (int i = 0; i < 3; ++i) {
    p[i][0] = N(i, 2);
    p[i][1] = N(i, 1);
    p[i][2] = N(i, 0);
  }
  // Quartic (p1)^2 - p0 p2.
  double c[5];
  for (int k = 0; k < 5; ++k) c[k] = 0.0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) c[i + j] += p[1][i] * p[1][j] - p[0][i] * p[2][j];
  }
  double roots[4];
  const int num_roots = SolveRealPolynomialRoots(c, 4, roots);
  int n = 0;
  for (int r = 0; r < num_roots; ++r) {
    const double b1 = roots[r];
    const double q1 = EvaluatePolynomial(p[1], 2, b1);
    const double q2 = EvaluatePolynomial(p[2], 2, b1);
    const double g = 1.0 / q2;
    if (!(g > 0.0) || !std::isfinite(g)) continue;
    out[n++] = {q1 / q2, b1, g};
  }
  return n;
}

}  // namespace

int SolveRelposeAffineDepth3pt(const std::vector<Eigen::Vector2d>& x0, const std::vector<Eigen::Vector2d>& x1,
                               const std::vector<double>& d0, const std::vector<double>& d1,
                               std::vector<AffineDepthPose>* models) {
  models->clear();
  if (!HasFiniteSample(x0, x1, d0, d1, 3)) return 0;
  const double s0 = MeanAbs(d0.data(), 3), s1 = MeanAbs(d1.data(), 3);
  if (!(s0 > 0.0) || !(s1 > 0.0)) return 0;
  double dn0[3], dn1[3];
  for (int i = 0; i < 3; ++i) {
    dn0[i] = d0[i] / s0;
    dn1[i] = d1[i] / s1;
  }

  static constexpr int kPairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  Eigen::Matrix3d M0, M1;
  for (int r = 0; r < 3; ++r) {
    const int j = kPairs[r][0], k = kPairs[r][1];
    const Eigen::Vector4d c0 = PairDistanceCoefficients(x0[j], x0[k], dn0[j], dn0[k]);
    const Eigen::Vector4d c1 = PairDistanceCoefficients(x1[j], x1[k], dn1[j], dn1[k]);
    M0.row(r) << c0(0), c0(1), c0(2) + c0(3);
    M1.row(r) << c1(0), c1(1), c1(2) + c1(3);
  }
  const double h0 = HadamardRatio<3>(M0), h1 = HadamardRatio<3>(M1);
  // Both singular: equal depths in both views, coincident or non-finite points (a family of solutions).
  constexpr double kMinHadamardRatio = 1e-12;
  if (!(std::max(h0, h1) > kMinHadamardRatio)) return 0;

  ShiftSolution sol[4];
  int num_sol;
  if (h0 >= h1) {
    num_sol = SolveShifts(M0, M1, sol);
  } else {
    num_sol = SolveShifts(M1, M0, sol);
    for (int i = 0; i < num_sol; ++i) sol[i] = {sol[i].b1, sol[i].b0, 1.0 / sol[i].g};
  }

  models->reserve(num_sol);
  for (int s = 0; s < num_sol; ++s) {
    const double b0 = sol[s].b0, b1 = sol[s].b1, a = std::sqrt(sol[s].g);
    Eigen::Vector3d P0[3], P1[3];
    bool positive = true;
    for (int i = 0; i < 3; ++i) {
      const double z0 = dn0[i] + b0, z1 = dn1[i] + b1;
      if (!(z0 > 0.0) || !(z1 > 0.0)) positive = false;
      P0[i] = Eigen::Vector3d(z0 * x0[i](0), z0 * x0[i](1), z0);
      const double az1 = a * z1;
      P1[i] = Eigen::Vector3d(az1 * x1[i](0), az1 * x1[i](1), az1);
    }
    if (!positive) continue;
    AffineDepthPose m;
    if (!AlignCongruentTriangles(P0, P1, &m.R, &m.t)) continue;
    m.t *= s0;
    m.scale = a * s0 / s1;
    m.shift0 = b0 * s0;
    m.shift1 = b1 * s1;
    if (!IsValidAffineDepthModel(m, d0.data(), d1.data(), 3)) continue;
    models->push_back(m);
  }
  return static_cast<int>(models->size());
}

}  // namespace madsfm
