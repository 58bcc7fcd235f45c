// The pair-directory format of `madsfm pair` / `madsfm bench` (design.md section 5; the format of
// ../shared/data/example_pairs/*).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "madsfm/io/depth_map.h"

namespace madsfm {

struct PairData {
  std::string path;                      // the directory
  Eigen::Matrix3d K0, K1;                // intrinsics (pixels)
  std::optional<Eigen::Matrix4d> T_0to1; // ground truth, X1 = R X0 + t
  std::vector<Eigen::Vector2d> p0, p1;   // matched pixel coordinates
  std::optional<DepthMap> depth0, depth1;  // absent when info.json names no depth file
  int width0 = 0, height0 = 0, width1 = 0, height1 = 0;  // image sizes
};

}  // namespace madsfm
