// `madsfm seed_model`: picks the initial pair from the madsfm two-view results and writes a two-image sparse
// model that `colmap mapper --input_path` continues (../shared/docs/colmap.md, "what this means for madsfm").
#pragma once

#include <string>

#include "colmap_ext/database/database.h"

namespace madsfm {

struct SeedModelOptions {
  std::string database_path;
  std::string output_path;
  double min_tri_angle_deg = 4.0;  // median triangulation angle the initial pair needs
  int min_num_inliers = 30;
  int num_candidates = 30;         // best pairs (by inliers) whose geometry is examined
  double max_reproj_error = 4.0;   // px, for the triangulated seed points
};

struct SeedModelSummary {
  colmap::image_t image_id1 = 0, image_id2 = 0;
  std::string name1, name2;
  int num_inliers = 0;
  int num_points3D = 0;
  double median_tri_angle_deg = 0.0;
  double score = 0.0;
};

// Throws std::runtime_error when no pair qualifies (say why).
SeedModelSummary RunSeedModelImpl(const SeedModelOptions& options);

}  // namespace madsfm
