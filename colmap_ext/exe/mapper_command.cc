#include "colmap_ext/exe/mapper_command.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "colmap_ext/exe/option_parser.h"
#include "colmap_ext/pipeline/mapper.h"

namespace madsfm {

int RunMapper(int argc, char** argv) {
  MapperOptions o;
  TwoViewEstimatorOptions& tv = o.two_view;
  // Everything of the form --Mapper.xxx value (or --Mapper.xxx=value) is passed to colmap mapper unchanged.
  std::vector<char*> own_args = {argv[0], argv[1]};
  for (int i = 2; i < argc; ++i) {
    if (std::strncmp(argv[i], "--Mapper.", 9) == 0) {
      o.colmap_mapper_args.push_back(argv[i]);
      if (std::strchr(argv[i], '=') == nullptr && i + 1 < argc) o.colmap_mapper_args.push_back(argv[++i]);
    } else {
      own_args.push_back(argv[i]);
    }
  }
  OptionParser parser(
      "mapper",
      "The whole madsfm pipeline on a COLMAP project: two_view_estimator (hybrid affine-depth estimation of every\n"
      "matched pair), focal_estimator (per-camera focal lengths: priors when trusted, else initial values),\n"
      "seed_model (initial pair + two-view model), then `colmap mapper --input_path <output_path>/seed`. Never\n"
      "worse than plain COLMAP in registered images: without a seed, or when the seeded run registers fewer images\n"
      "than have verified pairs (or fails), colmap mapper runs without the seed (relaxed initial-pair constraints\n"
      "if it finds no initial pair), then on a copy of the database with COLMAP's own rows; the model with the\n"
      "most registered images goes to <output_path>/0 (docs/cli.md). Options --Mapper.* are passed to every\n"
      "colmap mapper run. Run COLMAP's feature_extractor and a matcher first.");
  parser.AddRequired("database_path", &tv.database_path, "COLMAP database with keypoints and matches.");
  parser.AddRequired("image_path", &o.image_path, "Image folder (for colmap mapper).");
  parser.AddRequired("output_path", &o.output_path,
                     "Output folder: 0/ (the kept model), seed/, one folder and colmap_mapper_<run>.log per run.");
  parser.AddDefault("depth_path", &tv.depth_path, "Folder of depth sidecars (docs/formats.md).");
  parser.AddDefault("depth_type", &tv.depth_type, "depth | disparity.");
  parser.AddDefault("estimate_shift", &tv.estimator.estimate_shift,
                    "1: the depth maps are affine-invariant (relative depth models): one scale and two shifts per pair\n"
                    "(the paper's model). 0: they are metric up to one scale per image (sensor depth, metric depth\n"
                    "models): scale only, which keeps small baselines from trading shifts against focal lengths.");
  parser.AddDefault("camera_mode", &tv.camera_mode, "auto | calibrated | shared_focal | two_focal.");
  parser.AddDefault("num_threads", &tv.num_threads, "Threads (-1: all cores).");
  parser.AddDefault("reproj_threshold", &tv.estimator.reproj_threshold, "Reprojection inlier threshold, px.");
  parser.AddDefault("epipolar_threshold", &tv.estimator.epipolar_threshold, "Sampson inlier threshold, px.");
  parser.AddDefault("guided_sampling_fraction", &tv.estimator.guided_sampling_fraction,
                    "Share of the minimal samples drawn from the matches COLMAP's geometric verification kept (the\n"
                    "rest from all raw matches; all are scored). 0: uniform sampling only.");
  parser.AddDefault("min_tri_angle", &o.seed.min_tri_angle_deg,
                    "Minimum median triangulation angle of the seed pair, deg (no pair: no seed).");
  parser.AddDefault("min_depth_tri_angle", &o.seed.min_depth_tri_angle_deg,
                    "Low parallax: a seed pair down to this angle, deg, when its depth priors agree with the pose\n"
                    "(their corrected depths place the seed points; 0: off).");
  parser.AddDefault("min_prior_pairs", &o.focal.min_prior_pairs,
                    "A focal estimate becomes a prior when at least this many depth-backed pairs agree ...");
  parser.AddDefault("prior_agreement", &o.focal.prior_agreement, "... within this relative difference ...");
  parser.AddDefault("min_prior_fraction", &o.focal.min_prior_fraction, "... and they are this fraction of the pairs.");
  parser.AddDefault("prior_max_pair_sigma", &o.focal.prior_max_pair_sigma,
                    "... each determining its focal to this relative standard deviation.");
  parser.AddDefault("relaxed_init_min_tri_angle", &o.relaxed_init_min_tri_angle,
                    "--Mapper.init_min_tri_angle of the relaxed unseeded run (COLMAP's default: 16).");
  parser.AddDefault("relaxed_init_min_num_inliers", &o.relaxed_init_min_num_inliers,
                    "--Mapper.init_min_num_inliers of the relaxed unseeded run (COLMAP's default: 100).");
  parser.AddDefault("fix_focal_low_parallax", &o.fix_focal_low_parallax,
                    "1: with a depth-backed (low-parallax) seed and one shared camera whose focal estimate is trusted,\n"
                    "a seeded run whose bundle adjustment moved that focal beyond the estimate's uncertainty (>= 1%) is\n"
                    "repeated with the focal fixed (--Mapper.ba_refine_focal_length 0); 0: never.");
  parser.AddDefault("fix_focal_ba_uncertain", &o.fix_focal_ba_uncertain,
                    "1: with any seed and one shared camera whose focal estimate is trusted, the seeded run is repeated\n"
                    "with the focal fixed when its bundle adjustment determines that focal less well than the pairs did\n"
                    "(standard deviations) and moved it by more than that (forward motion); 0: never.");
  parser.AddDefault("fallback", &o.fallback,
                    "0: only the seeded colmap mapper run (unseeded when there is no seed), no fallbacks.");
  parser.AddDefault("colmap_path", &o.colmap_path, "The colmap executable.");
  if (!parser.Parse(static_cast<int>(own_args.size()), own_args.data(), 2)) return EXIT_FAILURE;
  if (parser.help_requested()) return EXIT_SUCCESS;
  try {
    const MapperSummary s = RunMapperImpl(o, [](bool warning, const std::string& line) {
      std::fprintf(warning ? stderr : stdout, "%s\n", line.c_str());
      std::fflush(warning ? stderr : stdout);
    });
    std::printf("mapper: model in %s (total %.1f s)\n", s.final_path.c_str(), s.total_seconds);
    return EXIT_SUCCESS;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "madsfm mapper: error: %s\n", e.what());
    return EXIT_FAILURE;
  }
}

}  // namespace madsfm
