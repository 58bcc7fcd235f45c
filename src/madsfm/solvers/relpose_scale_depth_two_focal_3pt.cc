#include "madsfm/solvers/relpose_scale_depth_two_focal_3pt.h"

#include <Eigen/LU>
#include <cmath>

#include "madsfm/solvers/affine_depth_solver_utils.h"

// Method. With shifts 0, w0 = 1/f0^2, w1 = 1/f1^2 and g = scale^2, pair (j, k) gives
//   w0 C0_jk + E0_jk = g (w1 C1_jk + E1_jk),   C = ||d_j p_j - d_k p_k||^2, E = (d_j - d_k)^2,
// linear in y = (w0, g w1, g): [C0, -C1, -E1] y = -E0. The pairs (0,1), (0,2), (1,2) give a 3x3
// system with one solution; then f0 = 1/sqrt(w0), f1 = 1/sqrt(y1 / y2), scale = sqrt(y2). All 3
// distances then agree, so the lifted triangles are congruent and R, t follow exactly from two
// orthonormal triangle frames (AlignCongruentTriangles: the same result as AlignRigid, cheaper).
// Pixels are divided by each view's RMS radius and depths by each view's mean beforehand.

namespace madsfm {

int SolveRelposeScaleDepthTwoFocal3pt(const std::vector<Eigen::Vector2d>& p0, const std::vector<Eigen::Vector2d>& p1,
                                      const std::vector<double>& d0, const std::vector<double>& d1,
                                      std::vector<AffineDepthPose>* models) {
  models->clear();
  if (!HasFiniteSample(p0, p1, d0, d1, 3)) return 0;
  for (int i = 0; i < 3; ++i) {
    if (!(d0[i] > 0.0) || !(d1[i] > 0.0)) return 0;  // no shift can make a prior positive here
  }
  const double s0 = MeanAbs(d0.data(), 3), s1 = MeanAbs(d1.data(), 3);
  const double r0 = RmsNorm(p0.data(), 3), r1 = RmsNorm(p1.data(), 3);
  if (!(r0 > 0.0) || !(r1 > 0.0)) return 0;
  double dn0[3], dn1[3];
  Eigen::Vector2d pn0[3], pn1[3];
  for (int i = 0; i < 3; ++i) {
    dn0[i] = d0[i] / s0;
    dn1[i] = d1[i] / s1;
    pn0[i] = p0[i] / r0;
    pn1[i] = p1[i] / r1;
  }
  static constexpr int kPairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  Eigen::Matrix3d A;
  Eigen::Vector3d rhs;
  for (int r = 0; r < 3; ++r) {
    const int j = kPairs[r][0], k = kPairs[r][1];
    const Eigen::Vector4d e0 = PairDistanceCoefficients(pn0[j], pn0[k], dn0[j], dn0[k]);
    const Eigen::Vector4d e1 = PairDistanceCoefficients(pn1[j], pn1[k], dn1[j], dn1[k]);
    A.row(r) << e0(2), -e1(2), -e1(3);
    rhs(r) = -e0(3);
  }
  constexpr double kMinHadamardRatio = 1e-12;
  if (!(HadamardRatio<3>(A) > kMinHadamardRatio)) return 0;
  const Eigen::Vector3d y = A.inverse() * rhs;
  if (!(y(0) > 0.0) || !(y(1) > 0.0) || !(y(2) > 0.0) || !y.allFinite()) return 0;
  const double f0n = 1.0 / std::sqrt(y(0)), f1n = std::sqrt(y(2) / y(1)), a = std::sqrt(y(2));

  Eigen::Vector3d P0[3], P1[3];
  for (int i = 0; i < 3; ++i) {
    const double z0 = dn0[i], z1 = a * dn1[i];
    P0[i] = Eigen::Vector3d(z0 * pn0[i](0) / f0n, z0 * pn0[i](1) / f0n, z0);
    P1[i] = Eigen::Vector3d(z1 * pn1[i](0) / f1n, z1 * pn1[i](1) / f1n, z1);
  }
  AffineDepthPose m;
  if (!AlignCongruentTriangles(P0, P1, &m.R, &m.t)) return 0;
  m.t *= s0;
  m.scale = a * s0 / s1;
  m.f0 = f0n * r0;
  m.f1 = f1n * r1;
  if (!IsValidAffineDepthModel(m, d0.data(), d1.data(), 3)) return 0;
  models->push_back(m);
  return 1;
}

}  // namespace madsfm
