// Depth priors of a COLMAP image sampled at its keypoints (design.md section 2: each image's depth map is
// read once and sampled once at all of its keypoints).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace madsfm::colmap {

enum class DepthType { kDepth, kDisparity };
DepthType ParseDepthType(const std::string& name);  // "depth" | "disparity"; throws std::invalid_argument

struct KeypointDepths {
  std::string sidecar;        // the file used ("" when the image has none)
  std::vector<double> depth;  // one per keypoint, NaN where invalid or without a sidecar
  int num_valid = 0;
};

// Finds the sidecar of `image_name` under `depth_dir` (design.md lookup order), reads it (inverting disparity),
// checks its aspect ratio against the image (width x height) and samples it bilinearly at the keypoints given in
// COLMAP's convention (pixel centres at +0.5). An image without a sidecar gives all-NaN depths (the point-only
// fallback). A sidecar that exists but cannot be read, or has the wrong aspect ratio, throws
// std::runtime_error naming the file.
KeypointDepths LoadKeypointDepths(const std::string& depth_dir, const std::string& image_name, int width, int height,
                                  const std::vector<Eigen::Vector2d>& keypoints, DepthType type);

}  // namespace madsfm::colmap
