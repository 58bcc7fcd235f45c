#include "madsfm/geometry/homography.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>

namespace madsfm {

bool FitHomographyLinear(const std::vector<Eigen::Vector2d>& x0, const std::vector<Eigen::Vector2d>& x1,
                         const std::vector<int>& indices, Eigen::Matrix3d* H) {
  if (indices.size() < 4) return false;
  // Normal equations of the two DLT rows per correspondence, h = H row-major.
  Eigen::Matrix<double, 9, 9> M = Eigen::Matrix<double, 9, 9>::Zero();
  Eigen::Matrix<double, 9, 1> r0, r1;
  for (int i : indices) {
    const double a = x0[i].x(), b = x0[i].y(), u = x1[i].x(), v = x1[i].y();
    r0 << 0.0, 0.0, 0.0, -a, -b, -1.0, v * a, v * b, v;
    r1 << a, b, 1.0, 0.0, 0.0, 0.0, -u * a, -u * b, -u;
    M.selfadjointView<Eigen::Lower>().rankUpdate(r0);
    M.selfadjointView<Eigen::Lower>().rankUpdate(r1);
  }
  if (!M.allFinite()) return false;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> eig(M.selfadjointView<Eigen::Lower>());
  if (eig.info() != Eigen::Success) return false;
  const Eigen::Matrix<double, 9, 1> h = eig.eigenvectors().col(0);  // eigenvalues ascending
  *H << h(0), h(1), h(2), h(3), h(4), h(5), h(6), h(7), h(8);
  return H->allFinite();
}

double HomographyTransferError(const Eigen::Matrix3d& H, const Eigen::Vector2d& x0, const Eigen::Vector2d& x1) {
  const Eigen::Vector3d y = H * x0.homogeneous();
  if (!(std::abs(y.z()) > 0.0)) return std::numeric_limits<double>::infinity();
  return (y.hnormalized() - x1).norm();
}

std::vector<PlanarPose> DecomposeHomography(const Eigen::Matrix3d& H_in, const std::vector<Eigen::Vector2d>& x0,
                                            const std::vector<Eigen::Vector2d>& x1, const std::vector<int>& indices) {
  std::vector<PlanarPose> out;
  if (!H_in.allFinite() || indices.empty()) return out;
  // Scale: the middle singular value of R + t n^T is 1. Sign: x1^T H x0 > 0 (both depths positive).
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd_h(H_in);
  const double s2 = svd_h.singularValues()(1);
  if (!(s2 > 0.0)) return out;
  Eigen::Matrix3d H = H_in / s2;
  int positive = 0;
  for (int i : indices) positive += x1[i].homogeneous().dot(H * x0[i].homogeneous()) > 0.0 ? 1 : -1;
  if (positive < 0) H = -H;

  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(H.transpose() * H);
  if (eig.info() != Eigen::Success) return out;
  // Ascending eigenvalues: sigma3^2 <= 1 <= sigma1^2.
  const double l3 = eig.eigenvalues()(0), l1 = eig.eigenvalues()(2);
  const Eigen::Vector3d v3 = eig.eigenvectors().col(0), v2 = eig.eigenvectors().col(1), v1 = eig.eigenvectors().col(2);
  auto in_front = [&](const PlanarPose& p) {
    int votes = 0;
    for (int i : indices) votes += p.n.dot(x0[i].homogeneous()) > 0.0 ? 1 : -1;
    return votes > 0;
  };
  if (!(l1 - l3 > 1e-12)) {  // H is a rotation: no translation, no plane
    PlanarPose p;
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
    p.R = svd.matrixU() * svd.matrixV().transpose();
    if (p.R.determinant() < 0.0) return out;
    out.push_back(p);
    return out;
  }
  const double a = std::sqrt(std::max(0.0, 1.0 - l3)), b = std::sqrt(std::max(0.0, l1 - 1.0));
  const double c = std::sqrt(l1 - l3);
  for (const double sign : {1.0, -1.0}) {
    const Eigen::Vector3d u = (a * v1 + sign * b * v3) / c;
    Eigen::Matrix3d U, W;
    U << v2, u, v2.cross(u);
    const Eigen::Vector3d Hv2 = H * v2, Hu = H * u;
    W << Hv2, Hu, Hv2.cross(Hu);
    PlanarPose p;
    p.R = W * U.transpose();
    p.n = v2.cross(u);
    p.t = (H - p.R) * p.n;
    if (!in_front(p)) {
      p.n = -p.n;
      p.t = -p.t;
    }
    if (in_front(p) && p.R.allFinite() && p.t.allFinite()) out.push_back(p);
  }
  return out;
}

}  // namespace madsfm
