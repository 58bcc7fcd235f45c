#include "madsfm/solvers/affine_depth_solver_utils.h"

#include <Eigen/Geometry>
#include <cmath>

namespace madsfm {

bool HasFiniteSample(const std::vector<Eigen::Vector2d>& x0, const std::vector<Eigen::Vector2d>& x1,
                     const std::vector<double>& d0, const std::vector<double>& d1, int n) {
  if (static_cast<int>(x0.size()) < n || static_cast<int>(x1.size()) < n || static_cast<int>(d0.size()) < n ||
      static_cast<int>(d1.size()) < n) {
    return false;
  }
  for (int i = 0; i < n; ++i) {
    if (!x0[i].allFinite() || !x1[i].allFinite() || !std::isfinite(d0[i]) || !std::isfinite(d1[i])) return false;
  }
  return true;
}

double MeanAbs(const double* v, int n) {
  double s = 0.0;
  for (int i = 0; i < n; ++i) s += std::abs(v[i]);
  return s / n;
}

double RmsNorm(const Eigen::Vector2d* p, int n) {
  double s = 0.0;
  for (int i = 0; i < n; ++i) s += p[i].squaredNorm();
  return std::sqrt(s / n);
}

Eigen::Vector4d PairDistanceCoefficients(const Eigen::Vector2d& x_j, const Eigen::Vector2d& x_k, double d_j,
                                         double d_k) {
  const Eigen::Vector2d dx = x_j - x_k;
  const Eigen::Vector2d dd = d_j * x_j - d_k * x_k;
  const double dz = d_j - d_k;
  return Eigen::Vector4d(dx.squaredNorm(), 2.0 * dx.dot(dd), dd.squaredNorm(), dz * dz);
}

bool AlignCongruentTriangles(const Eigen::Vector3d* p, const Eigen::Vector3d* q, Eigen::Matrix3d* R,
                             Eigen::Vector3d* t) {
  // Frame of a triangle: e1 along the edge 0->1, e3 normal to the triangle, e2 = e3 x e1.
  auto frame = [](const Eigen::Vector3d* a, Eigen::Matrix3d* F) {
    const Eigen::Vector3d u = a[1] - a[0], v = a[2] - a[0];
    const Eigen::Vector3d n = u.cross(v);
    const double nn = n.norm(), uu = u.norm(), vv = v.norm();
    // sin of the angle at vertex 0; rejects (nearly) collinear and coincident points.
    if (!(nn > 1e-10 * uu * vv)) return false;
    F->col(0) = u / uu;
    F->col(2) = n / nn;
    F->col(1) = F->col(2).cross(F->col(0));
    return true;
  };
  Eigen::Matrix3d Fp, Fq;
  if (!frame(p, &Fp) || !frame(q, &Fq)) return false;
  const Eigen::Matrix3d Rl = Fq * Fp.transpose();
  const Eigen::Vector3d tl = (q[0] + q[1] + q[2]) / 3.0 - Rl * ((p[0] + p[1] + p[2]) / 3.0);
  if (!Rl.allFinite() || !tl.allFinite()) return false;
  *R = Rl;
  *t = tl;
  return true;
}

AffineDepthPose SwapViews(const AffineDepthPose& m) {
  AffineDepthPose s;
  s.R = m.R.transpose();
  s.t = -(m.R.transpose() * m.t) / m.scale;
  s.scale = 1.0 / m.scale;
  s.shift0 = m.shift1;
  s.shift1 = m.shift0;
  s.f0 = m.f1;
  s.f1 = m.f0;
  return s;
}

bool IsValidAffineDepthModel(const AffineDepthPose& m, const double* d0, const double* d1, int n) {
  if (!m.R.allFinite() || !m.t.allFinite() || !std::isfinite(m.scale) || !std::isfinite(m.shift0) ||
      !std::isfinite(m.shift1) || !std::isfinite(m.f0) || !std::isfinite(m.f1)) {
    return false;
  }
  if (!(m.scale > 0.0) || !(m.f0 > 0.0) || !(m.f1 > 0.0)) return false;
  for (int i = 0; i < n; ++i) {
    if (!(m.Depth0(d0[i]) > 0.0) || !(m.Depth1(d1[i]) > 0.0)) return false;
  }
  return true;
}

}  // namespace madsfm
