// Depth-map files (design.md section 5): reading .npy / .pfm / COLMAP .bin / 16-bit .png, finding an image's sidecar,
// writing.
//
// Every reader throws std::runtime_error whose message starts with "depth file '<path>': " and says what is
// wrong (missing file, unsupported extension, bad header, truncated data, wrong shape or dtype, empty map).
// Values are returned as stored: invalid pixels (non-finite or <= 0) are kept and handled by the sampler.
#pragma once

#include <optional>
#include <string>

#include "madsfm/io/depth_map.h"

namespace madsfm {

// Reads a depth map, dispatching on the (case-insensitive) extension:
//  .npy  2-D float16/float32/float64 array (H, W), C or Fortran order; a singleton channel axis, (1, H, W) or
//        (H, W, 1), is squeezed; other shapes and integer/complex/object dtypes are errors.
//  .pfm  grayscale "Pf" only (a 3-channel "PF" file is an error); a negative scale means little-endian; rows are
//        stored bottom-to-top and returned top-to-bottom.
//  .bin  COLMAP dense depth map: ASCII "W&H&C&" header, then little-endian float32; only C = 1 is accepted.
//  .png  16-bit grayscale (sensor depth, 16-bit exports of depth models): the stored integers in any unit, 0 = no
//        depth (invalid); colour, alpha, palette, fewer bits and non-linear colour-space chunks are errors.
DepthMap ReadDepthMap(const std::string& path);

// Looks up the depth sidecar of the image `image_name` (as stored in the COLMAP database, e.g. "a/b.jpg") under
// depth_dir, in this order: a/b.jpg.npy, a/b.npy, a/b.jpg.pfm, a/b.pfm, a/b.jpg.geometric.bin,
// a/b.jpg.photometric.bin, a/b.jpg.bin, a/b.jpg.png, a/b.png. Returns the path of the first regular file that
// exists, or nullopt.
std::optional<std::string> FindDepthSidecar(const std::string& depth_dir, const std::string& image_name);

// Writers (float32, little-endian); they throw std::runtime_error naming the file on failure or on an empty or
// inconsistent map (data.size() != width * height).
void WriteDepthMapNpy(const DepthMap& map, const std::string& path);
void WriteDepthMapPfm(const DepthMap& map, const std::string& path);
void WriteDepthMapColmapBin(const DepthMap& map, const std::string& path);

// Inverts a disparity map into a depth map: 1 / v for positive finite v, NaN otherwise.
DepthMap DisparityToDepth(const DepthMap& disparity);

}  // namespace madsfm
