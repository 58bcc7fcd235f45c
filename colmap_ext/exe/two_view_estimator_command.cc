#include "colmap_ext/exe/two_view_estimator_command.h"

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "colmap_ext/database/database.h"
#include "colmap_ext/exe/option_parser.h"
#include "colmap_ext/pipeline/two_view_estimator.h"

namespace madsfm {

int RunTwoViewEstimator(int argc, char** argv) {
  TwoViewEstimatorOptions o;
  OptionParser parser(
      "two_view_estimator",
      "Estimates every matched image pair of a COLMAP database with the hybrid affine-depth estimator and writes\n"
      "two-view geometries (inlier matches, E or F, relative pose) back, plus madsfm's own table. COLMAP's\n"
      "original rows are backed up first (madsfm restore puts them back). Resumable: pairs done with the same\n"
      "options are skipped. Images without a depth sidecar fall back to the point-only method.");
  parser.AddRequired("database_path", &o.database_path, "COLMAP database (3.8 ... 4.x).");
  parser.AddDefault("depth_path", &o.depth_path,
                    "Folder of depth sidecars: <image name>.npy / .pfm / .geometric.bin ... (docs/formats.md).");
  parser.AddDefault("camera_mode", &o.camera_mode,
                    "auto | calibrated | shared_focal | two_focal. auto: calibrated if both cameras have a focal\n"
                    "prior, shared_focal if both images use one camera, else two_focal.");
  parser.AddDefault("depth_type", &o.depth_type, "depth | disparity (disparity maps are inverted first).");
  parser.AddDefault("estimate_shift", &o.estimator.estimate_shift,
                    "1: the depth maps are affine-invariant (relative depth models): one scale and two shifts per pair\n"
                    "(the paper's model). 0: they are metric up to one scale per image (sensor depth, metric depth\n"
                    "models): scale only, which keeps small baselines from trading shifts against focal lengths.");
  parser.AddDefault("pair_list", &o.pair_list, "Optional file of 'name1 name2' lines: only these pairs.");
  parser.AddDefault("num_threads", &o.num_threads, "Threads (-1: all cores).");
  parser.AddDefault("overwrite", &o.overwrite, "Re-estimate pairs already done with the same options.");
  parser.AddDefault("min_num_matches", &o.min_num_matches, "Pairs with fewer raw matches are skipped.");
  parser.AddDefault("min_num_inliers", &o.min_num_inliers, "Fewer inliers: the pair keeps COLMAP's row.");
  parser.AddDefault("batch_size", &o.batch_size, "Pairs per write transaction (a kill loses at most one batch).");
  parser.AddDefault("num_shards", &o.num_shards,
                    "Split the pairs into this many shards, balanced by match count (docs/cluster.md).");
  parser.AddDefault("shard_index", &o.shard_index, "Which shard this run estimates, 0 ... num_shards - 1.");
  parser.AddDefault("shard_path", &o.shard_path,
                    "Shard file (SQLite) to write instead of the database, which is then only read; a rerun\n"
                    "resumes it. Merge the shards with `madsfm merge_shards`.");
  parser.AddDefault("progress", &o.progress, "Print progress to stderr.");
  parser.AddDefault("reproj_threshold", &o.estimator.reproj_threshold,
                    "Reprojection inlier threshold, px (paper: 8 indoor ~640 px images, 16 outdoor/large).");
  parser.AddDefault("epipolar_threshold", &o.estimator.epipolar_threshold, "Sampson inlier threshold, px.");
  parser.AddDefault("min_iterations", &o.estimator.min_iterations, "Minimum RANSAC iterations.");
  parser.AddDefault("min_iterations_two_focal_points", &o.estimator.min_iterations_two_focal_points,
                    "One camera per image and no depth on a pair (7-point samples only): at least this many.");
  parser.AddDefault("min_iterations_shared_focal_points", &o.estimator.min_iterations_shared_focal_points,
                    "Shared focal length and no depth on a pair (6-point samples only): at least this many.");
  parser.AddDefault("max_iterations", &o.estimator.max_iterations, "Maximum RANSAC iterations.");
  parser.AddDefault("guided_sampling_fraction", &o.estimator.guided_sampling_fraction,
                    "Share of the minimal samples drawn from the matches COLMAP's geometric verification kept (the\n"
                    "rest from all raw matches; all are scored). 0: uniform sampling only.");
  int seed = 0;
  parser.AddDefault("seed", &seed, "Random seed (results do not depend on the thread count).");
  if (!parser.Parse(argc, argv, 2)) return EXIT_FAILURE;
  if (parser.help_requested()) return EXIT_SUCCESS;
  o.estimator.seed = static_cast<uint64_t>(seed);
  try {
    const TwoViewEstimatorSummary s = RunTwoViewEstimatorImpl(o);
    if (!o.shard_path.empty()) {
      std::printf("two_view_estimator: shard %d of %d: %d of the %d pairs to estimate -> %s\n", o.shard_index,
                  o.num_shards, s.num_shard_pairs, s.num_pairs - s.num_skipped_few_matches, o.shard_path.c_str());
    }
    std::printf("two_view_estimator: %d matched pairs: %d estimated (%d point-only for lack of depth), %d failed "
                "(COLMAP's rows kept), %d point-only not estimated (COLMAP's verification found < %d inliers; rows "
                "kept), %d already done, %d with < %d matches\n",
                s.num_pairs, s.num_estimated, s.num_point_fallback, s.num_failed, s.num_not_verified,
                o.min_num_inliers, s.num_skipped_done, s.num_skipped_few_matches, o.min_num_matches);
    std::printf("two_view_estimator: %d images, %d with depth; time %.2f s (read %.2f s, estimate %.2f s, write %.2f s)\n",
                s.num_images, s.num_images_with_depth, s.total_seconds, s.read_seconds, s.estimate_seconds,
                s.write_seconds);
    return EXIT_SUCCESS;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "madsfm two_view_estimator: error: %s\n", e.what());
    return EXIT_FAILURE;
  }
}

int RunRestore(int argc, char** argv) {
  std::string database_path;
  OptionParser parser("restore",
                      "Puts back COLMAP's original two-view geometries and cameras that madsfm replaced, and drops\n"
                      "madsfm's tables.");
  parser.AddRequired("database_path", &database_path, "COLMAP database.");
  if (!parser.Parse(argc, argv, 2)) return EXIT_FAILURE;
  if (parser.help_requested()) return EXIT_SUCCESS;
  try {
    auto db = colmap::Database::Open(database_path);
    const int n = db->RestoreTwoViewGeometries();
    std::printf("restore: %d two-view geometries restored in '%s'\n", n, database_path.c_str());
    return EXIT_SUCCESS;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "madsfm restore: error: %s\n", e.what());
    return EXIT_FAILURE;
  }
}

}  // namespace madsfm
