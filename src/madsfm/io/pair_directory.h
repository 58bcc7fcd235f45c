// The pair-directory format of `madsfm pair` / `madsfm bench` (design.md section 5; the format of
// ../shared/data/example_pairs/*).
//
// A pair directory holds info.json with
//   "K0", "K1"                      3x3 intrinsics in pixels (required)
//   "T_0to1"                        4x4 (or 3x4) ground-truth pose, X1 = R X0 + t (optional)
//   "matches_0_file", "matches_1_file"  N x 2 .npy files of pixel coordinates, pixel centres at integers (required)
//   "depth_0_file", "depth_1_file"  depth maps (.npy / .pfm / COLMAP .bin) (optional)
//   "gt_depth_0_file", "gt_depth_1_file"  true metric z-depth maps (0 = no surface) at any resolution of the image's
//                                   aspect ratio (optional; `madsfm synth` writes them; bench measures the depth
//                                   corrections against them)
//   "image_size_0", "image_size_1"  [W, H] (optional; else the IHDR header of image0.png / image1.png, else the
//                                   depth map's size)
// File names are relative to the directory (absolute paths are kept). Every problem throws std::runtime_error
// naming the offending file.
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
  std::optional<DepthMap> gt_depth0, gt_depth1;  // true metric depth (gt_depth_*_file), for evaluation only
  int width0 = 0, height0 = 0, width1 = 0, height1 = 0;  // image sizes
  // Non-fatal problems found while reading (e.g. a depth file named in info.json that does not exist, read with
  // PairReadOptions::allow_missing_depth); empty for a clean read.
  std::vector<std::string> warnings;

  bool HasDepth() const { return depth0.has_value() && depth1.has_value(); }
};

struct PairReadOptions {
  // A depth file named in info.json but absent on disk is an error by default. When true it is skipped instead:
  // the depth stays empty and PairData::warnings says which file is missing.
  bool allow_missing_depth = false;
};

// Reads a pair directory. Checks: K0/K1 are 3x3, finite, with positive focal lengths and last row (0, 0, 1);
// T_0to1 is a rigid transform; both match files are N x 2 with the same N and finite values; depth maps are
// readable, non-empty, and have the image's aspect ratio (within 1%); the image sizes can be determined.
PairData ReadPairDirectory(const std::string& dir, const PairReadOptions& options = PairReadOptions());

// Expands PATH into pair directories: PATH itself if it holds info.json; else, for a directory, its
// subdirectories holding info.json (sorted by name; an error if there are none); else, for a text file, one
// directory per line relative to the file (blank lines and lines starting with '#' are skipped; every listed
// directory must hold info.json).
std::vector<std::string> ReadPairList(const std::string& path);

// File names written by WritePairDirectory (relative to the directory).
struct PairFileNames {
  std::string matches0 = "matches_0.npy";
  std::string matches1 = "matches_1.npy";
  std::string depth0 = "depth_0.npy";
  std::string depth1 = "depth_1.npy";
  std::string gt_depth0 = "gt_depth_0.npy";
  std::string gt_depth1 = "gt_depth_1.npy";
};

// Writes `pair` as a pair directory (created if needed): info.json with K0, K1, T_0to1 (if set), the file names,
// and image_size_0/1 (if positive); matches as float64 N x 2 .npy; depth maps and true depth maps (if set) as float32 .npy.
void WritePairDirectory(const PairData& pair, const std::string& dir, const PairFileNames& names = PairFileNames());

}  // namespace madsfm
