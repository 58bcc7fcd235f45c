#include "colmap_ext/pipeline/merge_shards.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>

#include "colmap_ext/pipeline/two_view_estimator.h"
#include "colmap_ext/shard/fingerprint.h"
#include "colmap_ext/shard/shard_file.h"
#include "colmap_ext/shard/shard_plan.h"

namespace madsfm {
namespace {

using colmap::pair_t;
using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

// Refuses a shard that does not belong with the first one (or the database), naming both files.
void CheckCompatible(const colmap::ShardFile& shard, const colmap::ShardFile& first, const std::string& db_path,
                     const std::string& db_fingerprint) {
  const colmap::ShardInfo& s = shard.info();
  if (s.database_fingerprint != db_fingerprint) {
    throw std::runtime_error("shard file '" + shard.path() + "' was made from another database (it names '" +
                             s.database_path + "'), or '" + db_path +
                             "' changed since (cameras, images, keypoints or matches): fingerprint " +
                             s.database_fingerprint + " vs " + db_fingerprint);
  }
  if (&shard == &first) return;
  const colmap::ShardInfo& f = first.info();
  if (s.options_fingerprint != f.options_fingerprint) {
    throw std::runtime_error("shard file '" + shard.path() + "' was made with other options than '" + first.path() +
                             "':\n  " + s.options_fingerprint + "\n  " + f.options_fingerprint);
  }
  if (s.split_fingerprint != f.split_fingerprint || s.num_shards != f.num_shards) {
    throw std::runtime_error("shard file '" + shard.path() + "' (shard " + std::to_string(s.shard_index) + " of " +
                             std::to_string(s.num_shards) + ") belongs to another split than '" + first.path() +
                             "' (shard " + std::to_string(f.shard_index) + " of " + std::to_string(f.num_shards) +
                             ")");
  }
}

// The pairs the split was made of, recomputed from the database as two_view_estimator chose them; nullopt when that
// is impossible (the pair list file is gone or changed) or gives another split.
std::optional<colmap::PairCounts> RecomputeSplitPairs(const colmap::Database& db, const colmap::ShardInfo& info) {
  std::vector<std::pair<pair_t, int>> pairs = db.ReadMatchedPairs();
  if (!info.pair_list_path.empty()) {
    if (!std::filesystem::exists(info.pair_list_path) ||
        FileFingerprint(info.pair_list_path) != info.pair_list_fingerprint) {
      return std::nullopt;
    }
    const auto allowed = ReadImagePairList(info.pair_list_path);
    std::map<colmap::image_t, std::string> names;
    for (const auto& im : db.ReadImages()) names[im.image_id] = im.name;
    std::vector<std::pair<pair_t, int>> kept;
    for (const auto& pr : pairs) {
      colmap::image_t i1, i2;
      colmap::PairIdToImagePair(pr.first, &i1, &i2);
      if (names.count(i1) && names.count(i2) && allowed.count({names[i1], names[i2]})) kept.push_back(pr);
    }
    pairs = kept;
  }
  colmap::PairCounts candidates;
  for (const auto& pr : pairs) {
    if (pr.second >= info.min_num_matches) candidates.push_back(pr);
  }
  if (colmap::SplitFingerprint(candidates, info.num_shards) != info.split_fingerprint) return std::nullopt;
  return candidates;
}

}  // namespace

MergeShardsSummary MergeShards(const MergeShardsOptions& options) {
  const auto t_start = Clock::now();
  MergeShardsSummary summary;
  if (options.shard_paths.empty()) throw std::invalid_argument("no shard files given");
  auto db = colmap::Database::Open(options.database_path);
  const std::string db_fingerprint = colmap::DatabaseFingerprint(*db);

  // Open and check every file before the first write.
  std::vector<std::unique_ptr<colmap::ShardFile>> shards;
  std::map<int, std::string> path_of_index;
  for (const std::string& path : options.shard_paths) {
    shards.push_back(colmap::ShardFile::Open(path, /*read_only=*/true));
    CheckCompatible(*shards.back(), *shards.front(), options.database_path, db_fingerprint);
    const int k = shards.back()->info().shard_index;
    if (path_of_index.count(k)) {
      const int n = shards.back()->info().num_shards;
      throw std::runtime_error("shard " + std::to_string(k) + " of " + std::to_string(n) + " given twice: '" +
                               path_of_index[k] + "' and '" + path + "'");
    }
    path_of_index[k] = path;
  }
  const colmap::ShardInfo& info = shards.front()->info();
  summary.num_shard_files = static_cast<int>(shards.size());
  summary.num_shards = info.num_shards;
  for (int k = 0; k < info.num_shards; ++k) {
    if (!path_of_index.count(k)) summary.missing_shard_indices.push_back(k);
  }

  // Pairs the database already holds with these options (an earlier run or merge): they need no shard.
  std::set<pair_t> already_done;
  for (const auto& row : db->ReadMadsfmPairs()) {
    if (row.options_fingerprint == info.options_fingerprint) already_done.insert(row.pair_id);
  }

  // Merge in one transaction, as the single-process run writes: tables and backup first, then every result.
  std::set<pair_t> covered;
  long long total = 0;
  for (const auto& shard : shards) total += static_cast<long long>(shard->ResultPairs().size());
  const bool tty = options.progress && isatty(STDERR_FILENO);
  if (total > 0) {
    colmap::Database::Transaction txn(db.get());
    db->CreateMadsfmTables();
    db->BackupTwoViewGeometries();
    auto last_progress = Clock::now();
    for (const auto& shard : shards) {
      shard->ForEachResult([&](const colmap::ShardResult& r) {
        if (r.geometry) {
          db->WriteTwoViewGeometry(*r.geometry);
          ++summary.num_geometries;
        }
        db->WriteMadsfmPair(r.madsfm);
        covered.insert(r.madsfm.pair_id);
        ++summary.num_results;
        if (options.progress && Seconds(last_progress, Clock::now()) > 1.0) {
          std::fprintf(stderr, tty ? "\rmerge_shards: %lld/%lld results" : "merge_shards: %lld/%lld results\n",
                       summary.num_results, total);
          last_progress = Clock::now();
        }
      });
    }
    txn.Commit();
    if (tty && Seconds(t_start, Clock::now()) > 1.0) std::fprintf(stderr, "\n");
  }

  // Coverage: the split's pairs that neither a shard nor the database holds.
  std::optional<colmap::PairCounts> split_pairs = RecomputeSplitPairs(*db, info);
  summary.coverage_from_database = split_pairs.has_value();
  std::vector<pair_t> expected;
  if (split_pairs) {
    for (const auto& pr : *split_pairs) expected.push_back(pr.first);
  } else {
    for (const auto& shard : shards) {
      for (pair_t p : shard->AssignedPairs()) expected.push_back(p);
    }
  }
  for (pair_t p : expected) {
    if (already_done.count(p) && !covered.count(p)) ++summary.num_already_done;
    if (!covered.count(p) && !already_done.count(p)) summary.uncovered.push_back(p);
  }
  std::sort(summary.uncovered.begin(), summary.uncovered.end());

  if (!options.uncovered_path.empty()) {
    std::map<colmap::image_t, std::string> names;
    for (const auto& im : db->ReadImages()) names[im.image_id] = im.name;
    std::ofstream out(options.uncovered_path);
    if (!out) throw std::runtime_error("cannot write --uncovered_path '" + options.uncovered_path + "'");
    out << "# pairs no shard covered (" << summary.uncovered.size()
        << "); usable as two_view_estimator --pair_list\n";
    for (pair_t p : summary.uncovered) {
      colmap::image_t i1, i2;
      colmap::PairIdToImagePair(p, &i1, &i2);
      out << names[i1] << " " << names[i2] << "\n";
    }
    if (!out) throw std::runtime_error("cannot write --uncovered_path '" + options.uncovered_path + "'");
  }
  summary.seconds = Seconds(t_start, Clock::now());
  return summary;
}

}  // namespace madsfm
