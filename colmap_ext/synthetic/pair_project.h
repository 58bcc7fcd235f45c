// A COLMAP project made of one pair directory (`madsfm import_pair`): database.db with one keypoint per match and the
// raw matches, images/, depths/<image>.npy, ground_truth.json (world = camera 0) and pairs.txt.
#pragma once

#include <string>

namespace madsfm::colmap {

struct PairProjectSummary {
  int num_matches = 0;
  std::string database_path;
};

// One SIMPLE_PINHOLE camera per image with the principal point of K and, unless known_focal, COLMAP's default focal
// guess 1.2 max(W, H) without a prior (known_focal: the true focal with prior_focal_length = 1). Throws
// std::runtime_error naming the file when the pair has no depth maps or images, or output_path/database.db exists.
PairProjectSummary WritePairProject(const std::string& pair_path, const std::string& output_path, bool known_focal);

}  // namespace madsfm::colmap
