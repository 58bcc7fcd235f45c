#include "colmap_ext/camera/camera_models.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace madsfm::colmap {
namespace {

struct ModelInfo {
  int id;
  const char* name;
  int num_params;
  int num_focal;  // 1: f, cx, cy, ...; 2: fx, fy, cx, cy, ...; 0: no focal length (spherical)
};

// Ids, names and parameter counts as in COLMAP (0-10 in 3.8 and 4.x; 11-17 added in 4.x, read from the
// current source; 17 EQUIRECTANGULAR is the newest and may be absent from a given 4.x release).
constexpr ModelInfo kModels[] = {
    {0, "SIMPLE_PINHOLE", 3, 1},
    {1, "PINHOLE", 4, 2},
    {2, "SIMPLE_RADIAL", 4, 1},
    {3, "RADIAL", 5, 1},
    {4, "OPENCV", 8, 2},
    {5, "OPENCV_FISHEYE", 8, 2},
    {6, "FULL_OPENCV", 12, 2},
    {7, "FOV", 5, 2},
    {8, "SIMPLE_RADIAL_FISHEYE", 4, 1},
    {9, "RADIAL_FISHEYE", 5, 1},
    {10, "THIN_PRISM_FISHEYE", 12, 2},
    {11, "RAD_TAN_THIN_PRISM_FISHEYE", 16, 2},
    {12, "SIMPLE_DIVISION", 4, 1},
    {13, "DIVISION", 5, 2},
    {14, "SIMPLE_FISHEYE", 3, 1},
    {15, "FISHEYE", 4, 2},
    {16, "EUCM", 6, 2},
    {17, "EQUIRECTANGULAR", 2, 0},
};
constexpr int kNumModels = static_cast<int>(sizeof(kModels) / sizeof(kModels[0]));

const ModelInfo* FindModel(int model_id) {
  if (model_id < 0 || model_id >= kNumModels) return nullptr;
  return &kModels[model_id];
}

// Validates model and parameter count for the accessors and the projection functions.
const ModelInfo& CheckedModel(const CameraIntrinsics& camera, const char* what) {
  const ModelInfo* info = FindModel(camera.model_id);
  if (info == nullptr) {
    throw std::invalid_argument(std::string(what) + ": unknown camera model " + CameraModelName(camera.model_id));
  }
  if (static_cast<int>(camera.params.size()) != info->num_params) {
    throw std::invalid_argument(std::string(what) + ": camera model " + info->name + " needs " +
                                std::to_string(info->num_params) + " parameters, got " +
                                std::to_string(camera.params.size()));
  }
  if (info->num_focal == 0) {
    throw std::invalid_argument(std::string(what) + ": camera model " + info->name + " has no focal length");
  }
  return *info;
}

// Minimal forward-mode dual number with two partial derivatives, for exact Jacobians of the distortion maps.
struct Dual {
  double a = 0;
  double d0 = 0, d1 = 0;
  Dual() = default;
  Dual(double value) : a(value) {}  // NOLINT: implicit from constants
  Dual(double value, double g0, double g1) : a(value), d0(g0), d1(g1) {}
};
inline Dual operator+(const Dual& x, const Dual& y) { return {x.a + y.a, x.d0 + y.d0, x.d1 + y.d1}; }
inline Dual operator*(const Dual& x, const Dual& y) {
  return {x.a * y.a, x.d0 * y.a + x.a * y.d0, x.d1 * y.a + x.a * y.d1};
}
inline Dual operator/(const Dual& x, const Dual& y) {
  const double inv = 1.0 / y.a;
  const double q = x.a * inv;
  return {q, (x.d0 - q * y.d0) * inv, (x.d1 - q * y.d1) * inv};
}
inline Dual sqrt(const Dual& x) {
  const double s = std::sqrt(x.a);
  const double g = 0.5 / s;
  return {s, x.d0 * g, x.d1 * g};
}
inline Dual atan(const Dual& x) {
  const double g = 1.0 / (1.0 + x.a * x.a);
  return {std::atan(x.a), x.d0 * g, x.d1 * g};
}
inline double Value(double x) { return x; }
inline double Value(const Dual& x) { return x.a; }

// Fisheye radial map: (u, v) -> (u, v) * theta_d / r with theta = atan(r), theta_d = theta * poly(theta^2), where
// poly(s) = 1 + k[0] s + k[1] s^2 + ... (num_k coefficients).
template <typename T>
void FisheyeDistort(const double* k, int num_k, const T& u, const T& v, T* ud, T* vd) {
  const T r2 = u * u + v * v;
  if (Value(r2) <= std::numeric_limits<double>::epsilon() * std::numeric_limits<double>::epsilon()) {
    // theta_d / r -> 1 as r -> 0 (the map is the identity to first order).
    *ud = u;
    *vd = v;
    return;
  }
  using std::atan;
  using std::sqrt;
  const T r = sqrt(r2);
  const T theta = atan(r);
  const T theta2 = theta * theta;
  T poly = T(1.0);
  T power = theta2;
  for (int i = 0; i < num_k; ++i) {
    poly = poly + k[i] * power;
    power = power * theta2;
  }
  const T scale = theta * poly / r;
  *ud = u * scale;
  *vd = v * scale;
}

// Distortion of normalised camera coordinates (u, v) -> distorted normalised coordinates (ud, vd), for the supported
// models; extra = the parameters after the focal length(s) and principal point. Same formulas as COLMAP's models.
template <typename T>
void Distort(int model_id, const double* extra, const T& u, const T& v, T* ud, T* vd) {
  switch (model_id) {
    case 0:  // SIMPLE_PINHOLE
    case 1:  // PINHOLE
      *ud = u;
      *vd = v;
      return;
    case 2: {  // SIMPLE_RADIAL: f, cx, cy, k
      const T r2 = u * u + v * v;
      const T s = T(1.0) + extra[0] * r2;
      *ud = u * s;
      *vd = v * s;
      return;
    }
    case 3: {  // RADIAL: f, cx, cy, k1, k2
      const T r2 = u * u + v * v;
      const T s = T(1.0) + extra[0] * r2 + extra[1] * r2 * r2;
      *ud = u * s;
      *vd = v * s;
      return;
    }
    case 4: {  // OPENCV: fx, fy, cx, cy, k1, k2, p1, p2
      const double k1 = extra[0], k2 = extra[1], p1 = extra[2], p2 = extra[3];
      const T uv = u * v;
      const T u2 = u * u;
      const T v2 = v * v;
      const T r2 = u2 + v2;
      const T s = T(1.0) + k1 * r2 + k2 * r2 * r2;
      *ud = u * s + 2.0 * p1 * uv + p2 * (r2 + 2.0 * u2);
      *vd = v * s + 2.0 * p2 * uv + p1 * (r2 + 2.0 * v2);
      return;
    }
    case 5:  // OPENCV_FISHEYE: fx, fy, cx, cy, k1, k2, k3, k4
      FisheyeDistort(extra, 4, u, v, ud, vd);
      return;
    case 6: {  // FULL_OPENCV: fx, fy, cx, cy, k1, k2, p1, p2, k3, k4, k5, k6
      const double k1 = extra[0], k2 = extra[1], p1 = extra[2], p2 = extra[3];
      const double k3 = extra[4], k4 = extra[5], k5 = extra[6], k6 = extra[7];
      const T uv = u * v;
      const T u2 = u * u;
      const T v2 = v * v;
      const T r2 = u2 + v2;
      const T r4 = r2 * r2;
      const T r6 = r4 * r2;
      const T s = (T(1.0) + k1 * r2 + k2 * r4 + k3 * r6) / (T(1.0) + k4 * r2 + k5 * r4 + k6 * r6);
      *ud = u * s + 2.0 * p1 * uv + p2 * (r2 + 2.0 * u2);
      *vd = v * s + 2.0 * p2 * uv + p1 * (r2 + 2.0 * v2);
      return;
    }
    case 8:  // SIMPLE_RADIAL_FISHEYE: f, cx, cy, k
      FisheyeDistort(extra, 1, u, v, ud, vd);
      return;
    case 9:  // RADIAL_FISHEYE: f, cx, cy, k1, k2
      FisheyeDistort(extra, 2, u, v, ud, vd);
      return;
    default:
      throw std::invalid_argument("camera model " + CameraModelName(model_id) + " is not supported");
  }
}

const char* CheckedSupportedModel(const CameraIntrinsics& camera, const char* what) {
  const ModelInfo& info = CheckedModel(camera, what);
  if (!IsSupportedCameraModel(camera.model_id)) {
    throw std::invalid_argument(std::string(what) + ": camera model " + info.name + " (id " +
                                std::to_string(info.id) + ") is not supported");
  }
  return info.name;
}

// Distortion parameters: those after the focal length(s) and the principal point (model already checked).
const double* ExtraParams(const CameraIntrinsics& camera) {
  return camera.params.data() + FindModel(camera.model_id)->num_focal + 2;
}

// Newton's method on d(x) = xd with exact Jacobians, damped by step halving whenever the residual does not decrease
// (keeps the iterate on the invertible branch of strongly distorting models). Stops at the floating-point floor:
// residual below 1e-15 relative, or a step below 1e-16 relative, or no decrease possible.
Eigen::Vector2d Undistort(int model_id, const double* extra, const Eigen::Vector2d& xd) {
  constexpr int kMaxIterations = 100;
  constexpr int kMaxHalvings = 40;
  const double scale = std::max(1.0, xd.norm());
  auto residual = [&](const Eigen::Vector2d& x) {
    double ud, vd;
    Distort<double>(model_id, extra, x.x(), x.y(), &ud, &vd);
    return Eigen::Vector2d(ud - xd.x(), vd - xd.y());
  };

  Eigen::Vector2d x = xd;
  for (int iter = 0; iter < kMaxIterations; ++iter) {
    Dual ud, vd;
    Distort<Dual>(model_id, extra, Dual(x.x(), 1, 0), Dual(x.y(), 0, 1), &ud, &vd);
    const Eigen::Vector2d res(ud.a - xd.x(), vd.a - xd.y());
    const double res_norm = res.norm();
    if (!(res_norm > 1e-15 * scale)) break;  // converged (or NaN input)
    Eigen::Matrix2d J;
    J << ud.d0, ud.d1, vd.d0, vd.d1;
    Eigen::Vector2d step = J.partialPivLu().solve(res);
    if (!step.allFinite()) break;
    bool improved = false;
    for (int h = 0; h < kMaxHalvings; ++h) {
      const Eigen::Vector2d candidate = x - step;
      if (residual(candidate).norm() < res_norm) {
        x = candidate;
        improved = true;
        break;
      }
      step *= 0.5;
    }
    if (!improved || step.norm() < 1e-16 * std::max(1.0, x.norm())) break;
  }
  return x;
}

}  // namespace

std::string CameraModelName(int model_id) {
  const ModelInfo* info = FindModel(model_id);
  if (info == nullptr) return "UNKNOWN(" + std::to_string(model_id) + ")";
  return info->name;
}

int CameraModelId(const std::string& name) {
  for (const ModelInfo& info : kModels) {
    if (name == info.name) return info.id;
  }
  return -1;
}

int CameraModelNumParams(int model_id) {
  const ModelInfo* info = FindModel(model_id);
  return info == nullptr ? -1 : info->num_params;
}

int CameraModelNumFocalParams(int model_id) {
  const ModelInfo* info = FindModel(model_id);
  return info == nullptr ? -1 : info->num_focal;
}

bool IsSupportedCameraModel(int model_id) {
  switch (model_id) {
    case 0: case 1: case 2: case 3: case 4: case 5: case 6: case 8: case 9:
      return true;
    default:
      return false;
  }
}

double CameraIntrinsics::FocalX() const {
  CheckedModel(*this, "FocalX");
  return params[0];
}

double CameraIntrinsics::FocalY() const {
  const ModelInfo& info = CheckedModel(*this, "FocalY");
  return info.num_focal == 1 ? params[0] : params[1];
}

double CameraIntrinsics::PrincipalX() const {
  const ModelInfo& info = CheckedModel(*this, "PrincipalX");
  return params[info.num_focal];
}

double CameraIntrinsics::PrincipalY() const {
  const ModelInfo& info = CheckedModel(*this, "PrincipalY");
  return params[info.num_focal + 1];
}

void CameraIntrinsics::SetFocal(double f) {
  const ModelInfo& info = CheckedModel(*this, "SetFocal");
  if (info.num_focal == 1) {
    params[0] = f;
    return;
  }
  const double aspect = (params[0] > 0 && std::isfinite(params[0]) && params[1] > 0 && std::isfinite(params[1]))
                            ? params[1] / params[0]
                            : 1.0;
  params[0] = f;
  params[1] = f * aspect;
}

Eigen::Vector2d ImageToCamera(const CameraIntrinsics& camera, const Eigen::Vector2d& image_point) {
  CheckedSupportedModel(camera, "ImageToCamera");
  const double fx = camera.FocalX(), fy = camera.FocalY();
  const double cx = camera.PrincipalX(), cy = camera.PrincipalY();
  const Eigen::Vector2d xd((image_point.x() - cx) / fx, (image_point.y() - cy) / fy);
  if (camera.model_id <= 1) return xd;  // pinhole models: no distortion
  return Undistort(camera.model_id, ExtraParams(camera), xd);
}

Eigen::Vector2d CameraToImage(const CameraIntrinsics& camera, const Eigen::Vector2d& camera_point) {
  CheckedSupportedModel(camera, "CameraToImage");
  const double fx = camera.FocalX(), fy = camera.FocalY();
  const double cx = camera.PrincipalX(), cy = camera.PrincipalY();
  double ud, vd;
  Distort<double>(camera.model_id, ExtraParams(camera), camera_point.x(), camera_point.y(), &ud, &vd);
  return Eigen::Vector2d(fx * ud + cx, fy * vd + cy);
}

}  // namespace madsfm::colmap
