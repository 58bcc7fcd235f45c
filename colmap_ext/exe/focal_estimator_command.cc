#include "colmap_ext/exe/focal_estimator_command.h"

#include <cstdio>
#include <cstdlib>
#include <exception>

#include "colmap_ext/exe/option_parser.h"
#include "colmap_ext/pipeline/focal_estimator.h"

namespace madsfm {

int RunFocalEstimator(int argc, char** argv) {
  FocalEstimatorOptions o;
  OptionParser parser(
      "focal_estimator",
      "Aggregates the pairwise focal estimates of two_view_estimator into one focal length per camera (weighted by\n"
      "inliers, outlier-rejecting; only pairs estimated with depth priors count) and writes it into the cameras\n"
      "table, for cameras without a prior (all with --overwrite 1). Trusted estimates (>= min_prior_pairs pairs\n"
      "within prior_agreement of it and each with a relative sigma <= prior_max_pair_sigma, >= min_prior_fraction\n"
      "of the pairs) become priors (prior_focal_length = 1);\n"
      "others only initial values (prior_focal_length = 0) that COLMAP refines. Cameras without depth-backed\n"
      "pairs keep COLMAP's row.");
  parser.AddRequired("database_path", &o.database_path, "COLMAP database processed by two_view_estimator.");
  parser.AddDefault("overwrite", &o.overwrite, "Also replace focal lengths that came with a prior.");
  parser.AddDefault("min_num_pairs", &o.min_num_pairs, "Cameras with fewer usable pair estimates are left as they are.");
  parser.AddDefault("min_prior_pairs", &o.min_prior_pairs, "Trusted (a prior): at least this many pairs agree ...");
  parser.AddDefault("prior_agreement", &o.prior_agreement, "... within this relative difference of the estimate ...");
  parser.AddDefault("min_prior_fraction", &o.min_prior_fraction, "... and at least this fraction of the pairs.");
  parser.AddDefault("prior_max_pair_sigma", &o.prior_max_pair_sigma,
                    "An agreeing pair determines its focal to this relative standard deviation (pose, scale and\n"
                    "shifts free; pairs of an older madsfm, without it, do not count).");
  if (!parser.Parse(argc, argv, 2)) return EXIT_FAILURE;
  if (parser.help_requested()) return EXIT_SUCCESS;
  try {
    const auto changes = RunFocalEstimatorImpl(o);
    std::printf("| camera | old f | new f | pairs used | agreeing / depth pairs | spread | updated |\n"
                "|---|---|---|---|---|---|---|\n");
    for (const FocalChange& c : changes) {
      const char* what = c.updated ? (c.trusted ? "yes, prior" : "yes, initial value")
                         : c.had_prior && !o.overwrite ? "no (has prior)"
                         : c.num_samples == 0          ? "no (no depth-backed pairs)"
                                                       : "no";
      std::printf("| %u | %.2f | %.2f | %d | %d / %d | %.2f%% | %s |\n", c.camera_id, c.old_focal, c.new_focal,
                  c.num_pairs, c.num_agreeing, c.num_samples, 100.0 * c.spread, what);
    }
    return EXIT_SUCCESS;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "madsfm focal_estimator: error: %s\n", e.what());
    return EXIT_FAILURE;
  }
}

}  // namespace madsfm
