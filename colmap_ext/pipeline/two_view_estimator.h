// The two_view_estimator step: the hybrid affine-depth estimator on every matched pair of a COLMAP database,
// written back as two-view geometries (issue 5). Command line: colmap_ext/exe/two_view_estimator_command.h.
#pragma once

#include <cstdint>
#include <functional>
#include <set>
#include <string>
#include <utility>

#include "madsfm/estimators/hybrid_estimator_options.h"

namespace madsfm {

struct TwoViewEstimatorOptions {
  std::string database_path;
  std::string depth_path;            // folder of depth sidecars (design.md section 5); may be empty: points only
  std::string camera_mode = "auto";  // auto | calibrated | shared_focal | two_focal
  std::string depth_type = "depth";  // depth | disparity
  std::string pair_list;             // optional file of "name1 name2" lines restricting the pairs
  int num_threads = -1;              // -1: all cores
  bool overwrite = false;            // re-estimate pairs already done with the same options
  int min_num_matches = 15;          // pairs with fewer raw matches are skipped
  int min_num_inliers = 15;          // fewer inliers: the pair keeps COLMAP's own row
  int batch_size = 256;              // pairs per write transaction
  bool progress = true;
  // Called after every batch has been written (committed to the database or the shard file), with the pairs done so
  // far in this run and the pairs to do; for progress displays and the crash tests. Runs on the calling thread.
  std::function<void(int done, int total)> on_batch_written;
  // Sharding (docs/cluster.md): with shard_path set, the database is only read and the results of the pairs of
  // shard shard_index (of num_shards, split by SplitPairsIntoShards) go to the shard file; merge_shards writes them.
  int num_shards = 1;
  int shard_index = 0;
  std::string shard_path;
  HybridEstimatorOptions estimator;
};

struct TwoViewEstimatorSummary {
  int num_pairs = 0;           // matched pairs considered
  int num_estimated = 0;       // written with a madsfm model
  int num_point_fallback = 0;  // of which estimated with the point-only method (missing depth)
  int num_failed = 0;          // no model / too few inliers: COLMAP's row kept
  int num_not_verified = 0;    // point-only pairs COLMAP's verification gave < min_num_inliers: not estimated, row kept
  int num_skipped_done = 0;    // already done with the same options (resume)
  int num_skipped_few_matches = 0;
  int num_shard_pairs = 0;     // sharded runs: pairs of this shard (of num_pairs - num_skipped_few_matches)
  int num_images_with_depth = 0, num_images = 0;
  double read_seconds = 0, estimate_seconds = 0, write_seconds = 0, total_seconds = 0;
  double estimate_cpu_seconds = 0;  // summed per-pair estimator time
  int64_t num_iterations = 0;       // RANSAC iterations summed over the estimated pairs (all searches)
};

// Runs the estimator; throws std::runtime_error / std::invalid_argument with a clear message on bad input.
TwoViewEstimatorSummary RunTwoViewEstimatorImpl(const TwoViewEstimatorOptions& options);

// The string stored with every pair result; a rerun with a different one re-estimates.
std::string OptionsFingerprint(const TwoViewEstimatorOptions& options);

// A --pair_list file: "name1 name2" per line ('#' comments), returned in both orders. Throws naming the file and
// line when a line is malformed.
std::set<std::pair<std::string, std::string>> ReadImagePairList(const std::string& path);
// Fingerprint of a file's bytes (to tie shards to the pair list they were split from).
std::string FileFingerprint(const std::string& path);

}  // namespace madsfm
