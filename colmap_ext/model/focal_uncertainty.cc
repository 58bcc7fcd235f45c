#include "colmap_ext/model/focal_uncertainty.h"

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

namespace madsfm::colmap {
namespace {

// A camera's free parameters in the reduced system: the focal length(s) and the extra (distortion) parameters.
struct CameraBlock {
  int offset = 0;
  std::vector<int> free;  // indices into CameraIntrinsics::params
};

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

// Image point of normalised camera coordinates n and its derivatives: d/dn (central differences) and d/d(free
// camera parameters) (central differences, steps relative to each parameter).
void ProjectWithJacobians(const CameraIntrinsics& camera, const std::vector<int>& free, const Eigen::Vector2d& n,
                          Eigen::Vector2d* p, Eigen::Matrix2d* dp_dn, Eigen::Matrix<double, 2, Eigen::Dynamic>* dp_dc) {
  *p = CameraToImage(camera, n);
  constexpr double kStep = 1e-7;
  for (int j = 0; j < 2; ++j) {
    Eigen::Vector2d a = n, b = n;
    a[j] += kStep;
    b[j] -= kStep;
    dp_dn->col(j) = (CameraToImage(camera, a) - CameraToImage(camera, b)) / (2.0 * kStep);
  }
  dp_dc->resize(2, static_cast<int>(free.size()));
  CameraIntrinsics c = camera;
  for (size_t k = 0; k < free.size(); ++k) {
    const int i = free[k];
    const double v = camera.params[i];
    const double h = 1e-6 * std::max(1.0, std::abs(v));
    c.params[i] = v + h;
    const Eigen::Vector2d a = CameraToImage(c, n);
    c.params[i] = v - h;
    const Eigen::Vector2d b = CameraToImage(c, n);
    c.params[i] = v;
    dp_dc->col(static_cast<int>(k)) = (a - b) / (2.0 * h);
  }
}

}  // namespace

std::optional<FocalUncertainty> BundleFocalUncertainty(const Reconstruction& model, uint32_t camera_id,
                                                       int max_images) {
  if (model.cameras.count(camera_id) == 0) return std::nullopt;
  // Reduced system layout: 6 pose parameters per image (rotation increment, translation), then each camera's block.
  std::map<uint32_t, int> image_offset;
  std::map<uint32_t, CameraBlock> cameras;
  int size = 0;
  for (const auto& [id, image] : model.images) {
    const auto cam = model.cameras.find(image.camera_id);
    if (cam == model.cameras.end()) return std::nullopt;
    image_offset[id] = size;
    size += 6;
  }
  if (image_offset.size() < 2 || static_cast<int>(image_offset.size()) > max_images) return std::nullopt;
  for (const auto& [id, image] : model.images) {
    if (cameras.count(image.camera_id)) continue;
    const CameraIntrinsics& k = model.cameras.at(image.camera_id).intrinsics;
    const int num_focal = CameraModelNumFocalParams(k.model_id);
    if (!IsSupportedCameraModel(k.model_id) || num_focal < 1 ||
        static_cast<int>(k.params.size()) != CameraModelNumParams(k.model_id)) {
      return std::nullopt;
    }
    CameraBlock block;
    block.offset = size;
    for (int i = 0; i < num_focal; ++i) block.free.push_back(i);
    for (int i = num_focal + 2; i < static_cast<int>(k.params.size()); ++i) block.free.push_back(i);
    size += static_cast<int>(block.free.size());
    cameras[image.camera_id] = block;
  }
  if (cameras.count(camera_id) == 0) return std::nullopt;

  struct Observation {
    Eigen::Matrix<double, 2, 3> d_point;
    Eigen::Matrix<double, 2, Eigen::Dynamic> d_camera;  // pose (6) then the camera block
    std::vector<int> index;                             // their columns in the reduced system
  };
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(size, size);
  double sum_sq = 0.0;
  int num_obs = 0, num_points = 0;
  std::vector<Observation> obs;
  std::vector<int> cols;
  for (const auto& [point_id, point] : model.points3D) {
    obs.clear();
    double point_sq = 0.0;
    for (const auto& [image_id, idx] : point.track) {
      const auto im = model.images.find(image_id);
      if (im == model.images.end() || idx >= im->second.points2D.size()) continue;
      const ModelImage& image = im->second;
      const Eigen::Matrix3d R = QuaternionToRotation(image.qvec);
      const Eigen::Vector3d RX = R * point.xyz;
      const Eigen::Vector3d Xc = RX + image.tvec;
      if (!(Xc.z() > 0.0)) continue;
      const CameraIntrinsics& k = model.cameras.at(image.camera_id).intrinsics;
      const CameraBlock& block = cameras.at(image.camera_id);
      const Eigen::Vector2d n = Xc.head<2>() / Xc.z();
      Eigen::Vector2d p;
      Eigen::Matrix2d dp_dn;
      Eigen::Matrix<double, 2, Eigen::Dynamic> dp_dc;
      ProjectWithJacobians(k, block.free, n, &p, &dp_dn, &dp_dc);
      Eigen::Matrix<double, 2, 3> dn_dXc;
      dn_dXc << 1.0 / Xc.z(), 0.0, -Xc.x() / (Xc.z() * Xc.z()), 0.0, 1.0 / Xc.z(), -Xc.y() / (Xc.z() * Xc.z());
      const Eigen::Matrix<double, 2, 3> dp_dXc = dp_dn * dn_dXc;
      Observation o;
      o.d_point = dp_dXc * R;
      const int nc = static_cast<int>(block.free.size());
      o.d_camera.resize(2, 6 + nc);
      o.d_camera.leftCols<3>() = -dp_dXc * Skew(RX);  // R <- exp([w]x) R
      o.d_camera.middleCols<3>(3) = dp_dXc;            // t <- t + dt
      o.d_camera.rightCols(nc) = dp_dc;
      const int off = image_offset.at(image_id);
      for (int j = 0; j < 6; ++j) o.index.push_back(off + j);
      for (int j = 0; j < nc; ++j) o.index.push_back(block.offset + j);
      if (!o.d_point.allFinite() || !o.d_camera.allFinite() || !p.allFinite()) continue;
      point_sq += (p - image.points2D[idx]).squaredNorm();
      obs.push_back(std::move(o));
    }
    if (obs.size() < 2) continue;
    // The point's own block and its coupling with the poses and cameras that see it (compact columns).
    Eigen::Matrix3d Hpp = Eigen::Matrix3d::Zero();
    cols.clear();
    for (const Observation& o : obs) {
      Hpp += o.d_point.transpose() * o.d_point;
      for (int c : o.index) {
        if (std::find(cols.begin(), cols.end(), c) == cols.end()) cols.push_back(c);
      }
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(Hpp);
    if (eig.info() != Eigen::Success || !(eig.eigenvalues()(0) > 1e-12 * eig.eigenvalues()(2))) continue;
    Eigen::MatrixXd B = Eigen::MatrixXd::Zero(3, static_cast<int>(cols.size()));
    for (const Observation& o : obs) {
      const Eigen::MatrixXd JtJ = o.d_camera.transpose() * o.d_camera;
      const Eigen::MatrixXd Jpc = o.d_point.transpose() * o.d_camera;
      for (size_t a = 0; a < o.index.size(); ++a) {
        for (size_t b = 0; b < o.index.size(); ++b) S(o.index[a], o.index[b]) += JtJ(a, b);
        const int pos = static_cast<int>(std::find(cols.begin(), cols.end(), o.index[a]) - cols.begin());
        B.col(pos) += Jpc.col(static_cast<int>(a));
      }
    }
    const Eigen::Matrix3d Hpp_inv =
        eig.eigenvectors() * eig.eigenvalues().cwiseInverse().asDiagonal() * eig.eigenvectors().transpose();
    const Eigen::MatrixXd reduce = B.transpose() * Hpp_inv * B;
    for (size_t a = 0; a < cols.size(); ++a)
      for (size_t b = 0; b < cols.size(); ++b) S(cols[a], cols[b]) -= reduce(a, b);
    sum_sq += point_sq;
    num_obs += static_cast<int>(obs.size());
    ++num_points;
  }
  const int dof = 2 * num_obs - 3 * num_points - (size - 7);
  if (dof < 1) return std::nullopt;
  double max_diag = 0.0;
  for (int i = 0; i < size; ++i) max_diag = std::max(max_diag, S(i, i));
  if (!(max_diag > 0.0)) return std::nullopt;
  for (int i = 0; i < size; ++i) S(i, i) += 1e-10 * std::max(S(i, i), 1e-6 * max_diag);
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(S);
  if (ldlt.info() != Eigen::Success) return std::nullopt;

  const CameraIntrinsics& k = model.cameras.at(camera_id).intrinsics;
  const CameraBlock& block = cameras.at(camera_id);
  const int num_focal = CameraModelNumFocalParams(k.model_id);
  Eigen::MatrixXd E = Eigen::MatrixXd::Zero(size, num_focal);
  for (int j = 0; j < num_focal; ++j) E(block.offset + j, j) = 1.0;
  const Eigen::MatrixXd X = ldlt.solve(E);
  const double residual_var = sum_sq / dof;
  double var = 0.0;  // of the mean focal length
  for (int a = 0; a < num_focal; ++a)
    for (int b = 0; b < num_focal; ++b) var += X(block.offset + a, b);
  var *= residual_var / (num_focal * num_focal);
  if (!(var >= 0.0) || !std::isfinite(var)) return std::nullopt;
  FocalUncertainty u;
  u.focal = num_focal == 1 ? k.params[0] : 0.5 * (k.params[0] + k.params[1]);
  u.sigma = std::sqrt(var);
  u.residual_sigma = std::sqrt(residual_var);
  u.num_observations = num_obs;
  return u;
}

}  // namespace madsfm::colmap
