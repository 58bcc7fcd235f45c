#include "madsfm/geometry/essential_matrix.h"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

#include "madsfm/geometry/triangulation.h"

namespace madsfm {
namespace {

// Unit null vector of a rank-2 matrix given by three rows: the longest cross product of two rows.
Eigen::Vector3d NullFromRows(const Eigen::Vector3d& r0, const Eigen::Vector3d& r1, const Eigen::Vector3d& r2) {
  Eigen::Vector3d best = r0.cross(r1);
  double best_norm = best.squaredNorm();
  const Eigen::Vector3d c02 = r0.cross(r2), c12 = r1.cross(r2);
  if (c02.squaredNorm() > best_norm) {
    best = c02;
    best_norm = c02.squaredNorm();
  }
  if (c12.squaredNorm() > best_norm) {
    best = c12;
    best_norm = c12.squaredNorm();
  }
  return best_norm > 0.0 ? Eigen::Vector3d(best / std::sqrt(best_norm)) : Eigen::Vector3d::Zero();
}

// Bougnoux's squared focal of the camera whose image points p satisfy [q;1]^T G [p;1] = 0 (the
// principal points at the origin): e = null(G^T) is the epipole in the other image, and
//   f^2 = -(c^T [e]_x I~ G p p^T G^T c) / (c^T [e]_x I~ G I~ G^T c),  p = c = (0, 0, 1), I~ = diag(1, 1, 0).
double BougnouxSquaredFocal(const Eigen::Matrix3d& G) {
  const Eigen::Vector3d e = NullFromRows(G.col(0), G.col(1), G.col(2));
  // w = ([e]_x^T c) = c x e = (-e_y, e_x, 0) for c = (0, 0, 1).
  const Eigen::Vector3d w(-e.y(), e.x(), 0.0);
  // w^T I~ G p: p = (0, 0, 1) -> G.col(2); p^T G^T c = G(2, 2).
  const double num = (w.x() * G(0, 2) + w.y() * G(1, 2)) * G(2, 2);
  // w^T I~ G I~ G^T c = sum_{i,j < 2} w_i G(i, j) G(2, j).
  const double den = w.x() * (G(0, 0) * G(2, 0) + G(0, 1) * G(2, 1)) + w.y() * (G(1, 0) * G(2, 0) + G(1, 1) * G(2, 1));
  return -num / den;
}

}  // namespace

Eigen::Matrix3d CrossProductMatrix(const Eigen::Vector3d& t) {
  Eigen::Matrix3d m;
  m << 0.0, -t.z(), t.y(), t.z(), 0.0, -t.x(), -t.y(), t.x(), 0.0;
  return m;
}

Eigen::Matrix3d EssentialFromPose(const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
  return CrossProductMatrix(t) * R;
}

void DecomposeEssential(const Eigen::Matrix3d& E, Eigen::Matrix3d* R1, Eigen::Matrix3d* R2, Eigen::Vector3d* t) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(E, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU();
  Eigen::Matrix3d V = svd.matrixV();
  // E is defined up to sign, so U and V may be flipped independently to make them rotations.
  if (U.determinant() < 0.0) U = -U;
  if (V.determinant() < 0.0) V = -V;
  Eigen::Matrix3d W;
  W << 0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0;
  *R1 = U * W * V.transpose();
  *R2 = U * W.transpose() * V.transpose();
  *t = U.col(2);
}

bool PoseFromEssential(const Eigen::Matrix3d& E, const std::vector<Eigen::Vector2d>& x0,
                       const std::vector<Eigen::Vector2d>& x1, Eigen::Matrix3d* R, Eigen::Vector3d* t) {
  if (!E.allFinite()) return false;
  Eigen::Matrix3d R1, R2;
  Eigen::Vector3d tu;
  DecomposeEssential(E, &R1, &R2, &tu);
  if (!R1.allFinite() || !R2.allFinite() || !tu.allFinite()) return false;
  const Eigen::Matrix3d* rotations[4] = {&R1, &R1, &R2, &R2};
  const double signs[4] = {1.0, -1.0, 1.0, -1.0};
  const size_t n = std::min(x0.size(), x1.size());
  int best = -1, best_count = 0;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d tk = signs[k] * tu;
    int count = 0;
    for (size_t i = 0; i < n; ++i) {
      double z0, z1;
      if (TriangulateDepths(*rotations[k], tk, x0[i], x1[i], &z0, &z1) && z0 > 0.0 && z1 > 0.0) ++count;
    }
    if (count > best_count) {
      best_count = count;
      best = k;
    }
  }
  if (best < 0) return false;
  *R = *rotations[best];
  *t = signs[best] * tu;
  return true;
}

Eigen::Matrix3d FundamentalFromEssential(const Eigen::Matrix3d& E, const Eigen::Matrix3d& K0,
                                         const Eigen::Matrix3d& K1) {
  return K1.inverse().transpose() * E * K0.inverse();
}

bool BougnouxFocals(const Eigen::Matrix3d& F, double* f0, double* f1) {
  if (!F.allFinite()) return false;
  // View 0's focal uses F (maps view-0 points to view-1 lines), view 1's uses F^T.
  const double f0_sq = BougnouxSquaredFocal(F);
  const double f1_sq = BougnouxSquaredFocal(F.transpose());
  if (!(f0_sq > 0.0) || !(f1_sq > 0.0) || !std::isfinite(f0_sq) || !std::isfinite(f1_sq)) return false;
  *f0 = std::sqrt(f0_sq);
  *f1 = std::sqrt(f1_sq);
  return true;
}

}  // namespace madsfm
