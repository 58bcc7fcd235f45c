#include "colmap_ext/exe/seed_model_command.h"

#include <cstdio>
#include <cstdlib>
#include <exception>

#include "colmap_ext/exe/option_parser.h"
#include "colmap_ext/pipeline/seed_model.h"

namespace madsfm {

int RunSeedModel(int argc, char** argv) {
  SeedModelOptions o;
  OptionParser parser("seed_model",
                      "Picks the initial pair (many hybrid inliers, good triangulation angle, depth-consistent scale)\n"
                      "and writes a two-image sparse model (binary; all keypoints as points2D, triangulated inliers as\n"
                      "points3D) that `colmap mapper --input_path` continues.");
  parser.AddRequired("database_path", &o.database_path, "COLMAP database processed by two_view_estimator.");
  parser.AddRequired("output_path", &o.output_path, "Folder for cameras.bin, images.bin, points3D.bin (created).");
  parser.AddDefault("min_tri_angle", &o.min_tri_angle_deg, "Minimum median triangulation angle of the pair, deg.");
  parser.AddDefault("min_num_inliers", &o.min_num_inliers, "Minimum inliers of the initial pair.");
  parser.AddDefault("depth_path", &o.depth_path,
                    "Folder of depth sidecars (as given to two_view_estimator); enables depth-backed seeds.");
  parser.AddDefault("depth_type", &o.depth_type, "depth | disparity.");
  parser.AddDefault("min_depth_tri_angle", &o.min_depth_tri_angle_deg,
                    "With depth_path: a pair down to this median triangulation angle, deg, qualifies when its depth\n"
                    "priors agree with the pose; its points fuse triangulation and corrected priors (0: off).");
  if (!parser.Parse(argc, argv, 2)) return EXIT_FAILURE;
  if (parser.help_requested()) return EXIT_SUCCESS;
  try {
    const SeedModelSummary s = RunSeedModelImpl(o);
    std::printf("seed_model: initial pair %u '%s' - %u '%s': %d inliers, median triangulation angle %.1f deg, %d "
                "points -> %s\n",
                s.image_id1, s.name1.c_str(), s.image_id2, s.name2.c_str(), s.num_inliers, s.median_tri_angle_deg,
                s.num_points3D, o.output_path.c_str());
    if (s.depth_backed) {
      std::printf("seed_model: low parallax: %d points placed with the corrected depth priors (prior spread %.1f%%)\n",
                  s.num_fused_points, 100 * s.prior_sigma);
    }
    return EXIT_SUCCESS;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "madsfm seed_model: error: %s\n", e.what());
    return EXIT_FAILURE;
  }
}

}  // namespace madsfm
