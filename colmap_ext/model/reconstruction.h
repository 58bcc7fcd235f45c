// COLMAP sparse models: cameras / images / points3D in the binary (.bin) and text (.txt) formats of COLMAP 3.8
// (read by 4.x as well). Used to write madsfm's two-view seed model and to read COLMAP's output for evaluation.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "colmap_ext/camera/camera_models.h"

namespace madsfm::colmap {

inline constexpr uint64_t kInvalidPoint3DId = UINT64_MAX;

struct ModelCamera {
  uint32_t camera_id = 0;
  CameraIntrinsics intrinsics;
};

struct ModelImage {
  uint32_t image_id = 0;
  Eigen::Vector4d qvec = Eigen::Vector4d(1, 0, 0, 0);  // world -> camera rotation (w, x, y, z)
  Eigen::Vector3d tvec = Eigen::Vector3d::Zero();      // world -> camera translation
  uint32_t camera_id = 0;
  std::string name;
  std::vector<Eigen::Vector2d> points2D;               // ALL keypoints of the image (COLMAP convention)
  std::vector<uint64_t> point3D_ids;                   // same size; kInvalidPoint3DId where untriangulated
};

struct ModelPoint3D {
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();
  std::array<uint8_t, 3> rgb{{128, 128, 128}};
  double error = 0.0;
  std::vector<std::pair<uint32_t, uint32_t>> track;    // (image_id, point2D_idx)
};

struct Reconstruction {
  std::map<uint32_t, ModelCamera> cameras;
  std::map<uint32_t, ModelImage> images;
  std::map<uint64_t, ModelPoint3D> points3D;
};

// Reads a model directory: the .bin files if present, else the .txt files. Throws naming the file on error.
Reconstruction ReadReconstruction(const std::string& dir);
void WriteReconstructionBinary(const Reconstruction& model, const std::string& dir);  // creates dir
void WriteReconstructionText(const Reconstruction& model, const std::string& dir);

// Rotation matrix <-> COLMAP quaternion (w, x, y, z).
Eigen::Matrix3d QuaternionToRotation(const Eigen::Vector4d& qvec);
Eigen::Vector4d RotationToQuaternion(const Eigen::Matrix3d& R);

}  // namespace madsfm::colmap
