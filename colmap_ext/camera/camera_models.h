// COLMAP camera models (ids and parameter order as in COLMAP 3.8 and 4.x) and keypoint undistortion.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace madsfm::colmap {

// COLMAP model ids: SIMPLE_PINHOLE 0, PINHOLE 1, SIMPLE_RADIAL 2, RADIAL 3, OPENCV 4, OPENCV_FISHEYE 5,
// FULL_OPENCV 6, FOV 7, SIMPLE_RADIAL_FISHEYE 8, RADIAL_FISHEYE 9, THIN_PRISM_FISHEYE 10; 4.x adds
// RAD_TAN_THIN_PRISM_FISHEYE 11, SIMPLE_DIVISION 12, DIVISION 13, SIMPLE_FISHEYE 14, FISHEYE 15, EUCM 16,
// EQUIRECTANGULAR 17 (newest; no focal length).
std::string CameraModelName(int model_id);                 // "UNKNOWN(<id>)" for others
int CameraModelId(const std::string& name);                // -1 if unknown
int CameraModelNumParams(int model_id);                    // -1 if unknown
int CameraModelNumFocalParams(int model_id);               // 1 (f), 2 (fx, fy), 0 (none); -1 if unknown
// Models ImageToCamera / CameraToImage handle: SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL, RADIAL, OPENCV, OPENCV_FISHEYE,
// FULL_OPENCV, SIMPLE_RADIAL_FISHEYE, RADIAL_FISHEYE.
bool IsSupportedCameraModel(int model_id);

struct CameraIntrinsics {
  int model_id = 0;
  int width = 0, height = 0;
  std::vector<double> params;

  // Accessors throw std::invalid_argument for unknown models, a wrong params count, or a model without focal length.
  double FocalX() const;  // f or fx
  double FocalY() const;  // f or fy
  double PrincipalX() const;
  double PrincipalY() const;
  // Writes a new (single) focal length into params: f, or fx = f and fy = f * (old fy / old fx) (aspect kept).
  void SetFocal(double f);
};

// Maps an image point (COLMAP convention: pixel centres at +0.5) to normalised camera coordinates (x/z, y/z),
// removing distortion (iteratively where the model has no closed-form inverse: damped Newton on COLMAP's distortion
// function with exact Jacobians, to the floating-point floor; round trips agree to ~1e-12 px). Throws
// std::invalid_argument for unsupported models (naming them) or a wrong number of params.
Eigen::Vector2d ImageToCamera(const CameraIntrinsics& camera, const Eigen::Vector2d& image_point);
// Inverse: normalised camera coordinates -> image point (with distortion).
Eigen::Vector2d CameraToImage(const CameraIntrinsics& camera, const Eigen::Vector2d& camera_point);

}  // namespace madsfm::colmap
