// madsfm_pipeline_bench: throughput of `two_view_estimator` on a COLMAP database of 1000 synthetic pairs
// (indoor_shared_focal preset, 300 matches, depth sidecars), with 1 and 2 threads. Counters: pairs/s and the
// share of the wall time spent reading (keypoints, depths, matches) and writing (transactions).
// Scaling efficiency = pairs/s(2 threads) / (2 x pairs/s(1 thread)), from the same run.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "colmap_ext/pipeline/two_view_estimator.h"
#include "colmap_ext/synthetic/synthetic_project.h"

namespace madsfm {
namespace {

namespace fs = std::filesystem;
constexpr int kNumPairs = 1000;

const std::string& ProjectDir() {
  static const std::string dir = [] {
    const std::string d = (fs::temp_directory_path() / "madsfm_pipeline_bench").string();
    fs::remove_all(d);
    colmap::SyntheticProjectOptions o;
    o.output_path = d;
    o.preset = "indoor_shared_focal";
    o.num_pairs = kNumPairs;
    o.min_num_matches = o.max_num_matches = 300;
    o.seed = 3;
    colmap::WriteSyntheticProject(o);
    return d;
  }();
  return dir;
}

void BM_TwoViewEstimator(benchmark::State& state) {
  TwoViewEstimatorOptions o;
  o.database_path = ProjectDir() + "/database.db";
  o.depth_path = ProjectDir() + "/depths";
  o.num_threads = static_cast<int>(state.range(0));
  o.overwrite = true;
  o.progress = false;
  double read = 0, write = 0, total = 0;
  int64_t pairs = 0;
  for (auto _ : state) {
    const TwoViewEstimatorSummary s = RunTwoViewEstimatorImpl(o);
    read += s.read_seconds;
    write += s.write_seconds;
    total += s.total_seconds;
    pairs += s.num_estimated + s.num_failed + s.num_not_verified;
  }
  state.counters["pairs_per_s"] = benchmark::Counter(static_cast<double>(pairs), benchmark::Counter::kIsRate);
  state.counters["read_share"] = read / total;
  state.counters["write_share"] = write / total;
}

BENCHMARK(BM_TwoViewEstimator)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

}  // namespace
}  // namespace madsfm
