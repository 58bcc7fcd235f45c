// madsfm_shard_bench: what sharding gives on one machine (issue 7, docs/benchmarks.md section "Sharding").
//  * BM_ShardedRun/N: N `madsfm two_view_estimator --num_shards N --shard_index k --num_threads 1` processes at once
//    (as N Slurm array tasks on one node) on a synthetic project of 400 pairs (100-500 matches); pairs/s of the
//    whole split, wall time.
//  * BM_SingleProcess/T: the unsharded run with T threads on the same project, for the ratio.
//  * BM_MergeShards: merge_shards of 4 shard files holding 10,000 pair results (150 inlier matches each) into a
//    database of 10,000 pairs (a fresh copy per iteration, not timed).
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <thread>

#include "colmap_ext/database/database.h"
#include "colmap_ext/database/database_builder.h"
#include "colmap_ext/pipeline/merge_shards.h"
#include "colmap_ext/pipeline/two_view_estimator.h"
#include "colmap_ext/shard/fingerprint.h"
#include "colmap_ext/shard/shard_file.h"
#include "colmap_ext/shard/shard_plan.h"
#include "colmap_ext/synthetic/synthetic_project.h"

namespace madsfm {
namespace {

namespace fs = std::filesystem;
constexpr int kNumPairs = 400;
constexpr int kMergePairs = 10000;

const std::string& Dir() {
  static const std::string dir = (fs::temp_directory_path() / "madsfm_shard_bench").string();
  return dir;
}

const colmap::SyntheticProject& Project() {
  static const colmap::SyntheticProject project = [] {
    fs::remove_all(Dir() + "/project");
    colmap::SyntheticProjectOptions o;
    o.output_path = Dir() + "/project";
    o.num_pairs = kNumPairs;
    o.min_num_matches = 100;
    o.max_num_matches = 500;
    o.seed = 1;
    return colmap::WriteSyntheticProject(o);
  }();
  return project;
}

void Run(const std::string& command) {
  if (std::system((command + " > /dev/null").c_str()) != 0) throw std::runtime_error("failed: " + command);
}

std::string EstimatorCommand(const std::string& db) {
  return std::string(MADSFM_CLI_PATH) + " two_view_estimator --database_path " + db + " --depth_path " +
         Project().depth_path + " --progress 0";
}

void BM_ShardedRun(benchmark::State& state) {
  const int num_shards = static_cast<int>(state.range(0));
  const std::string db = Project().database_path;
  for (auto _ : state) {
    state.PauseTiming();
    std::vector<std::string> commands;
    for (int k = 0; k < num_shards; ++k) {
      const std::string shard = Dir() + "/shard_" + std::to_string(k) + ".sqlite";
      fs::remove(shard);
      commands.push_back(EstimatorCommand(db) + " --num_threads 1 --num_shards " + std::to_string(num_shards) +
                         " --shard_index " + std::to_string(k) + " --shard_path " + shard);
    }
    state.ResumeTiming();
    std::vector<std::thread> tasks;
    for (const std::string& c : commands) tasks.emplace_back([c] { Run(c); });
    for (auto& t : tasks) t.join();
  }
  state.counters["pairs_per_s"] =
      benchmark::Counter(static_cast<double>(kNumPairs) * state.iterations(), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ShardedRun)->Arg(1)->Arg(2)->Arg(4)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

void BM_SingleProcess(benchmark::State& state) {
  const std::string db = Dir() + "/single.db";
  fs::copy_file(Project().database_path, db, fs::copy_options::overwrite_existing);
  for (auto _ : state) {
    Run(EstimatorCommand(db) + " --overwrite 1 --num_threads " + std::to_string(state.range(0)));
  }
  state.counters["pairs_per_s"] =
      benchmark::Counter(static_cast<double>(kNumPairs) * state.iterations(), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_SingleProcess)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

// A database of kMergePairs pairs (random keypoints and 200 matches each) and 4 shard files with results for all.
struct MergeSetup {
  std::string db;
  std::vector<std::string> shards;
};

const MergeSetup& Merge10k() {
  static const MergeSetup setup = [] {
    MergeSetup s;
    const std::string dir = Dir() + "/merge";
    fs::remove_all(dir);
    fs::create_directories(dir);
    s.db = dir + "/database.db";
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> pix(0, 640);
    colmap::PairCounts pairs;
    {
      colmap::DatabaseBuilder b(s.db);
      b.Exec("BEGIN");
      const uint32_t cam = b.AddCamera(0, 640, 480, {500, 320, 240}, false);
      std::vector<Eigen::Vector2d> kp(400);
      std::vector<std::array<uint32_t, 2>> m(200);
      for (int i = 0; i < 2 * kMergePairs; ++i) {
        const uint32_t id = b.AddImage("im" + std::to_string(i) + ".png", cam);
        for (auto& k : kp) k = Eigen::Vector2d(pix(rng), pix(rng));
        b.AddKeypoints(id, kp);
        if (id % 2 == 0) {
          for (uint32_t j = 0; j < m.size(); ++j) m[j] = {j, j + 100};
          b.AddMatches(id - 1, id, m);
          pairs.push_back({colmap::ImagePairToPairId(id - 1, id), 200});
        }
      }
      b.Exec("COMMIT");
    }
    TwoViewEstimatorOptions options;  // the default options, as the fingerprint
    colmap::ShardInfo info;
    info.database_path = s.db;
    info.database_fingerprint = colmap::DatabaseFingerprint(*colmap::Database::Open(s.db, true));
    info.options_fingerprint = OptionsFingerprint(options);
    info.num_shards = 4;
    info.split_fingerprint = colmap::SplitFingerprint(pairs, 4);
    info.num_split_pairs = kMergePairs;
    info.min_num_matches = options.min_num_matches;
    const auto split = colmap::SplitPairsIntoShards(pairs, 4);
    for (int k = 0; k < 4; ++k) {
      info.shard_index = k;
      s.shards.push_back(dir + "/shard_" + std::to_string(k) + ".sqlite");
      auto shard = colmap::ShardFile::Create(s.shards.back(), info, split[k]);
      shard->Begin();
      for (colmap::pair_t p : split[k]) {
        colmap::ShardResult r;
        colmap::TwoViewGeometryRow g;
        g.pair_id = p;
        for (uint32_t j = 0; j < 150; ++j) g.inlier_matches.push_back({j, j + 100});
        g.config = colmap::kUncalibrated;
        g.F = Eigen::Matrix3d::Random();
        g.qvec = Eigen::Vector4d(1, 0, 0, 0);
        g.tvec = Eigen::Vector3d(1, 0, 0);
        r.geometry = g;
        r.madsfm.pair_id = p;
        r.madsfm.options_fingerprint = info.options_fingerprint;
        r.madsfm.num_inliers = 150;
        shard->WriteResult(r);
      }
      shard->Commit();
    }
    return s;
  }();
  return setup;
}

void BM_MergeShards(benchmark::State& state) {
  const MergeSetup& setup = Merge10k();
  MergeShardsOptions o;
  o.database_path = Dir() + "/merge/target.db";
  o.shard_paths = setup.shards;
  o.progress = false;
  for (auto _ : state) {
    state.PauseTiming();
    fs::copy_file(setup.db, o.database_path, fs::copy_options::overwrite_existing);
    state.ResumeTiming();
    const MergeShardsSummary s = MergeShards(o);
    if (s.num_results != kMergePairs || !s.uncovered.empty()) state.SkipWithError("merge did not cover all pairs");
  }
  state.counters["pairs"] = kMergePairs;
}
BENCHMARK(BM_MergeShards)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(5);

}  // namespace
}  // namespace madsfm
