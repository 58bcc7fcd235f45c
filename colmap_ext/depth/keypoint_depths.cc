#include "colmap_ext/depth/keypoint_depths.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "madsfm/io/depth_map_io.h"
#include "madsfm/io/depth_sampling.h"

namespace madsfm::colmap {

DepthType ParseDepthType(const std::string& name) {
  if (name == "depth") return DepthType::kDepth;
  if (name == "disparity") return DepthType::kDisparity;
  throw std::invalid_argument("unknown depth type '" + name + "' (expected depth or disparity)");
}

KeypointDepths LoadKeypointDepths(const std::string& depth_dir, const std::string& image_name, int width, int height,
                                  const std::vector<Eigen::Vector2d>& keypoints, DepthType type) {
  KeypointDepths out;
  out.depth.assign(keypoints.size(), std::numeric_limits<double>::quiet_NaN());
  const auto sidecar = FindDepthSidecar(depth_dir, image_name);
  if (!sidecar) return out;
  out.sidecar = *sidecar;
  DepthMap map = ReadDepthMap(*sidecar);
  if (type == DepthType::kDisparity) map = DisparityToDepth(map);
  CheckAspectRatio(map, width, height, *sidecar);
  for (size_t i = 0; i < keypoints.size(); ++i) {
    // COLMAP keypoints put the centre of the upper-left pixel at (0.5, 0.5); the sampler uses integers.
    const double d = SampleDepth(map, keypoints[i].x() - 0.5, keypoints[i].y() - 0.5, width, height);
    if (d > 0.0) {
      out.depth[i] = d;
      ++out.num_valid;
    }
  }
  return out;
}

}  // namespace madsfm::colmap
