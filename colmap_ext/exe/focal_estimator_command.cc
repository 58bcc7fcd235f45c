#include "colmap_ext/exe/focal_estimator_command.h"

#include <cstdio>
#include <cstdlib>
#include <exception>

#include "colmap_ext/exe/option_parser.h"
#include "colmap_ext/pipeline/focal_estimator.h"

namespace madsfm {

int RunFocalEstimator(int argc, char** argv) {
  FocalEstimatorOptions o;
  OptionParser parser("focal_estimator",
                      "Aggregates the pairwise focal estimates of two_view_estimator into one focal length per camera\n"
                      "(weighted by inliers, outlier-rejecting) and writes it into the cameras table with\n"
                      "prior_focal_length = 1, for cameras without a prior (all with --overwrite 1).");
  parser.AddRequired("database_path", &o.database_path, "COLMAP database processed by two_view_estimator.");
  parser.AddDefault("overwrite", &o.overwrite, "Also replace focal lengths that came with a prior.");
  parser.AddDefault("min_num_pairs", &o.min_num_pairs, "Cameras with fewer usable pair estimates are left as they are.");
  if (!parser.Parse(argc, argv, 2)) return EXIT_FAILURE;
  if (parser.help_requested()) return EXIT_SUCCESS;
  try {
    const auto changes = RunFocalEstimatorImpl(o);
    std::printf("| camera | old f | new f | pairs used | spread | updated |\n|---|---|---|---|---|---|\n");
    for (const FocalChange& c : changes) {
      std::printf("| %u | %.2f | %.2f | %d | %.2f%% | %s |\n", c.camera_id, c.old_focal, c.new_focal, c.num_pairs,
                  100.0 * c.spread, c.updated ? "yes" : (c.had_prior && !o.overwrite ? "no (has prior)" : "no"));
    }
    return EXIT_SUCCESS;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "madsfm focal_estimator: error: %s\n", e.what());
    return EXIT_FAILURE;
  }
}

}  // namespace madsfm
