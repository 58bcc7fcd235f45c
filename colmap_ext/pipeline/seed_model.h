// `madsfm seed_model`: picks the initial pair from the madsfm two-view results and writes a two-image sparse
// model that `colmap mapper --input_path` continues (../shared/docs/colmap.md, "what this means for madsfm").
#pragma once

#include <string>

#include "colmap_ext/database/database.h"

namespace madsfm {

struct SeedModelOptions {
  std::string database_path;
  std::string output_path;
  double min_tri_angle_deg = 4.0;  // median triangulation angle the initial pair needs from triangulation alone
  // Depth-backed seeds (low parallax): with depth_path set, a hybrid pair whose median triangulation angle is below
  // min_tri_angle_deg but at least min_depth_tri_angle_deg qualifies when most of its inliers agree with both
  // depth priors; its points are then placed by fusing the triangulated depth with the pair's affine-corrected
  // prior, weighted by their uncertainties (the prior's spread is measured on the pair itself).
  std::string depth_path;
  std::string depth_type = "depth";      // depth | disparity
  double min_depth_tri_angle_deg = 1.0;  // 0 or >= min_tri_angle_deg: no depth-backed seeds
  double min_depth_inlier_ratio = 0.5;   // depth inliers in each view / inliers
  double keypoint_sigma_px = 1.0;        // keypoint noise assumed for the triangulation's uncertainty
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
  bool depth_backed = false;     // the pair qualified through its depth priors (below min_tri_angle_deg)
  int num_fused_points = 0;      // points whose depth fuses triangulation and the corrected prior
  double prior_sigma = 0.0;      // relative spread of the corrected priors measured on the pair (depth-backed)
};

// Throws std::runtime_error when no pair qualifies (say why).
SeedModelSummary RunSeedModelImpl(const SeedModelOptions& options);

}  // namespace madsfm
