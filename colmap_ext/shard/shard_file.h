// Shard files of `two_view_estimator --num_shards N --shard_index K --shard_path FILE` (issue 7): one SQLite file per
// shard holding what the single-process run would write for the shard's pairs, plus the fingerprints that decide
// whether `merge_shards` may merge it (docs/cluster.md, docs/formats.md).
//
// Tables: madsfm_shard_info(key, value) (the ShardInfo fields), madsfm_shard_pairs(pair_id) (the pairs the split
// gave this shard) and madsfm_shard_results(pair_id, geometry, madsfm) with the two database rows of a pair as
// little-endian blobs (geometry NULL when the pair keeps COLMAP's row). Results are written in transactions, so a
// killed task leaves whole batches and a rerun resumes.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "colmap_ext/database/database.h"

struct sqlite3;

namespace madsfm::colmap {

struct ShardInfo {
  std::string database_path;         // for messages only: the path the task was given
  std::string database_fingerprint;  // DatabaseFingerprint
  std::string options_fingerprint;   // two_view_estimator's OptionsFingerprint
  std::string split_fingerprint;     // SplitFingerprint of all shards' pairs
  int num_shards = 1, shard_index = 0;
  long long num_split_pairs = 0;     // pairs of all shards together
  int min_num_matches = 0;           // how the split's pairs were chosen (merge recomputes them)
  std::string pair_list_path, pair_list_fingerprint;  // empty without --pair_list
  std::string madsfm_version;
};

// One pair's result: the two_view_geometries row (absent: COLMAP's row stays) and madsfm's own row.
struct ShardResult {
  std::optional<TwoViewGeometryRow> geometry;
  MadsfmPairRow madsfm;  // options_fingerprint is the shard's
};

class ShardFile {
 public:
  // Writes a new shard file with its info and assigned pairs. The file appears complete or not at all (written
  // as FILE.tmp, then renamed). Throws naming the path when it exists or cannot be written.
  static std::unique_ptr<ShardFile> Create(const std::string& path, const ShardInfo& info,
                                           const std::vector<pair_t>& assigned_pairs);
  // Opens an existing shard file. Throws naming the file when it is missing, not SQLite, or not a madsfm shard.
  static std::unique_ptr<ShardFile> Open(const std::string& path, bool read_only);
  ~ShardFile();
  ShardFile(const ShardFile&) = delete;
  ShardFile& operator=(const ShardFile&) = delete;

  const std::string& path() const { return path_; }
  const ShardInfo& info() const { return info_; }
  std::vector<pair_t> AssignedPairs() const;  // sorted
  std::vector<pair_t> ResultPairs() const;    // sorted

  // Results are written between Begin() and Commit() (one transaction per batch); ~ShardFile rolls back an
  // uncommitted batch.
  void Begin();
  void WriteResult(const ShardResult& result);
  void Commit();

  // Every result in pair id order (streamed: memory does not grow with the shard). Throws naming the file and pair
  // when a blob is malformed.
  void ForEachResult(const std::function<void(const ShardResult&)>& visit) const;

 private:
  ShardFile() = default;
  std::string path_;
  sqlite3* db_ = nullptr;
  ShardInfo info_;
  bool in_transaction_ = false;
};

}  // namespace madsfm::colmap
