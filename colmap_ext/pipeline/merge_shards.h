// The merge_shards step (`madsfm merge_shards`, colmap_ext/exe/merge_shards_command.h): writes the results of
// `two_view_estimator --shard_path` runs into the database (issue 7, docs/cluster.md).
#pragma once

#include <string>
#include <vector>

#include "colmap_ext/database/database.h"

namespace madsfm {

struct MergeShardsOptions {
  std::string database_path;
  std::vector<std::string> shard_paths;
  std::string uncovered_path;  // optional: write the uncovered pairs as a --pair_list file ("name1 name2" lines)
  bool progress = true;
};

struct MergeShardsSummary {
  int num_shard_files = 0, num_shards = 0;     // files given; shards of the split
  std::vector<int> missing_shard_indices;      // indices of the split no file was given for
  long long num_results = 0;                   // pair results merged (written to the database)
  long long num_geometries = 0;                // of which replaced COLMAP's two_view_geometries row
  long long num_already_done = 0;              // pairs the database already held with the same options
  std::vector<colmap::pair_t> uncovered;       // pairs to estimate that no shard (nor the database) holds
  bool coverage_from_database = true;          // false: the split could not be recomputed (pair list gone/changed)
  double seconds = 0;
};

// Checks every shard file against the database and the others, then merges all results in one transaction; the
// database then holds exactly what a single-process two_view_estimator run with the same options writes. Merging
// again changes nothing. Throws std::runtime_error naming the file on: a file that is not a shard, a shard of
// another database (fingerprint), other options or another split than the first file, a shard index given twice.
MergeShardsSummary MergeShards(const MergeShardsOptions& options);

}  // namespace madsfm
