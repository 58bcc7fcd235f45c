// Sampling a depth map at image keypoints (design.md section 5).
//
// In: a depth map of W' x H' pixels that covers an image of W x H pixels (same aspect ratio, any resolution), and
// keypoint coordinates in image pixels with pixel centres at integer coordinates (the upper-left pixel's centre is
// (0, 0); subtract 0.5 from COLMAP keypoints, whose upper-left centre is (0.5, 0.5)).
// Out: the bilinearly interpolated depth, or NaN when the keypoint has no valid depth.
//
// Image pixel (x, y) maps to ((x + 0.5) * W' / W - 0.5, (y + 0.5) * H' / H - 0.5) in the map. Map coordinates are
// clamped to [0, W' - 1] x [0, H' - 1], so points within half a map pixel of the border take the edge value. The
// sample is NaN when the keypoint lies outside the image ([-0.5, W - 0.5] x [-0.5, H - 0.5]) or is non-finite, or
// when any of the (up to four) map pixels with non-zero bilinear weight is invalid (non-finite or <= 0), or when
// the map or the image size is empty.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "madsfm/io/depth_map.h"

namespace madsfm {

double SampleDepth(const DepthMap& map, double x, double y, int image_width, int image_height);

// Samples at many keypoints at once; returns one value per point (NaN where invalid).
std::vector<double> SampleDepths(const DepthMap& map, const std::vector<Eigen::Vector2d>& points, int image_width,
                                 int image_height);

// Throws std::runtime_error ("depth file '<name>': ...") when the map is empty, the image size is not positive, or
// the aspect ratios W'/H' and W/H differ by more than 1% (relative).
void CheckAspectRatio(const DepthMap& map, int image_width, int image_height, const std::string& name);

}  // namespace madsfm
