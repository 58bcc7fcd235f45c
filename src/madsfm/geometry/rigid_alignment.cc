#include "madsfm/geometry/rigid_alignment.h"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>

namespace madsfm {
namespace {

// Shared core: centroids, cross-covariance and its rotation. Returns false if degenerate.
bool AlignCore(const Eigen::Vector3d* p, const Eigen::Vector3d* q, int n, Eigen::Vector3d* mp, Eigen::Vector3d* mq,
               Eigen::Matrix3d* R, Eigen::Vector3d* sigma_signed, double* var_p) {
  if (n < 3) return false;
  mp->setZero();
  mq->setZero();
  for (int i = 0; i < n; ++i) {
    *mp += p[i];
    *mq += q[i];
  }
  *mp /= n;
  *mq /= n;
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  double vp = 0.0;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d a = p[i] - *mp;
    H += (q[i] - *mq) * a.transpose();
    vp += a.squaredNorm();
  }
  if (!H.allFinite() || !(vp > 0.0)) return false;
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d sv = svd.singularValues();
  // Rank < 2 (collinear or coincident points): the rotation is not determined.
  if (!(sv(1) > 1e-12 * sv(0)) || !(sv(0) > 0.0)) return false;
  Eigen::Matrix3d U = svd.matrixU();
  const Eigen::Matrix3d V = svd.matrixV();
  double d = (U * V.transpose()).determinant() > 0 ? 1.0 : -1.0;
  U.col(2) *= d;
  *R = U * V.transpose();
  *sigma_signed = Eigen::Vector3d(sv(0), sv(1), d * sv(2));
  *var_p = vp;
  return R->allFinite();
}

}  // namespace

bool AlignRigid(const Eigen::Vector3d* p, const Eigen::Vector3d* q, int n, Eigen::Matrix3d* R, Eigen::Vector3d* t) {
  Eigen::Vector3d mp, mq, sig;
  Eigen::Matrix3d Rl;
  double vp;
  if (!AlignCore(p, q, n, &mp, &mq, &Rl, &sig, &vp)) return false;
  *R = Rl;
  *t = mq - Rl * mp;
  return true;
}

bool AlignSimilarity(const Eigen::Vector3d* p, const Eigen::Vector3d* q, int n, double* s, Eigen::Matrix3d* R,
                     Eigen::Vector3d* t) {
  Eigen::Vector3d mp, mq, sig;
  Eigen::Matrix3d Rl;
  double vp;
  if (!AlignCore(p, q, n, &mp, &mq, &Rl, &sig, &vp)) return false;
  const double sl = sig.sum() / vp;
  if (!(sl > 0.0) || !std::isfinite(sl)) return false;
  *s = sl;
  *R = Rl;
  *t = mq - sl * Rl * mp;
  return true;
}

}  // namespace madsfm
