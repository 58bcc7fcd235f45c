#include "colmap_ext/exe/merge_shards_command.h"

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "colmap_ext/exe/option_parser.h"
#include "colmap_ext/pipeline/merge_shards.h"

namespace madsfm {

int RunMergeShards(int argc, char** argv) {
  MergeShardsOptions o;
  OptionParser parser(
      "merge_shards",
      "Merges the shard files of `two_view_estimator --num_shards N --shard_index K --shard_path FILE` runs into the\n"
      "database, in one transaction. Refuses (naming the file) shards of another database, made with other options or\n"
      "from another split; merging twice changes nothing. Reports the pairs no shard covered (a missing or killed\n"
      "task: rerun it, it resumes its shard file, and merge again). The result equals a single-process run.");
  parser.AddRequired("database_path", &o.database_path, "COLMAP database the shards were made from.");
  parser.AddPositional("SHARD", &o.shard_paths, true, "Shard files (e.g. shards/shard_*_of_8.sqlite).");
  parser.AddDefault("uncovered_path", &o.uncovered_path,
                    "Write the uncovered pairs here as 'name1 name2' lines (a --pair_list for a rerun).");
  parser.AddDefault("progress", &o.progress, "Print progress to stderr.");
  if (!parser.Parse(argc, argv, 2)) return EXIT_FAILURE;
  if (parser.help_requested()) return EXIT_SUCCESS;
  try {
    const MergeShardsSummary s = MergeShards(o);
    std::printf("merge_shards: %d shard files of %d: %lld pair results merged (%lld two-view geometries) into %s "
                "in %.2f s\n",
                s.num_shard_files, s.num_shards, s.num_results, s.num_geometries, o.database_path.c_str(), s.seconds);
    if (!s.missing_shard_indices.empty()) {
      std::string list;
      for (int k : s.missing_shard_indices) list += (list.empty() ? "" : ", ") + std::to_string(k);
      std::printf("merge_shards: warning: no file for shard(s) %s of %d\n", list.c_str(), s.num_shards);
    }
    if (s.num_already_done > 0) {
      std::printf("merge_shards: %lld pairs were already in the database with the same options\n", s.num_already_done);
    }
    if (!s.coverage_from_database) {
      std::printf("merge_shards: note: the pair list of the split is gone or changed; coverage counts only the pairs "
                  "of the shards given\n");
    }
    if (s.uncovered.empty()) {
      std::printf("merge_shards: every pair is covered\n");
    } else {
      std::printf("merge_shards: warning: %zu pairs not covered by any shard (first: pair_id %llu)%s\n",
                  s.uncovered.size(), static_cast<unsigned long long>(s.uncovered.front()),
                  o.uncovered_path.empty() ? "; list them with --uncovered_path"
                                           : ("; listed in " + o.uncovered_path).c_str());
    }
    return EXIT_SUCCESS;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "madsfm merge_shards: error: %s\n", e.what());
    return EXIT_FAILURE;
  }
}

}  // namespace madsfm
