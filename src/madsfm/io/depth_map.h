// Depth maps: storage, reading from sidecar files and sampling at keypoints (design.md section 5).
#pragma once

#include <cmath>
#include <string>
#include <vector>

namespace madsfm {

// A single-channel depth (or disparity) map, row-major: value(x, y) = data[y * width + x].
struct DepthMap {
  int width = 0;
  int height = 0;
  std::vector<float> data;

  float At(int x, int y) const { return data[static_cast<size_t>(y) * width + x]; }
  bool Empty() const { return width <= 0 || height <= 0; }
};

}  // namespace madsfm
