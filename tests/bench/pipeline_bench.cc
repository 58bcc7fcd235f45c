// madsfm_pipeline_bench: throughput of `two_view_estimator` on a COLMAP database of 1000 synthetic pairs
// (indoor_shared_focal preset, 300 matches, depth sidecars), with 1 and 2 threads. Counters: pairs/s and the
// share of the wall time spent reading (keypoints, depths, matches) and writing (transactions).
// Scaling efficiency = pairs/s(2 threads) / (2 x pairs/s(1 thread)), from the same run.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "colmap_ext/exe/two_view_estimator.h"
#include "madsfm/io/depth_map_io.h"
#include "madsfm/synthetic/two_view_scene.h"
#include "testing/colmap_database_builder.h"

namespace madsfm {
namespace {

namespace fs = std::filesystem;
constexpr int kNumPairs = 1000;

const std::string& ProjectDir() {
  static const std::string dir = [] {
    const std::string d = (fs::temp_directory_path() / "madsfm_pipeline_bench").string();
    fs::remove_all(d);
    fs::create_directories(d + "/depths");
    testing::ColmapDatabaseBuilder b(d + "/database.db");
    SyntheticPairOptions opt = *SyntheticPairPreset("indoor_shared_focal");
    opt.num_matches = 300;
    const auto pairs = GenerateTwoViewSet(opt, kNumPairs, 3);
    b.Exec("BEGIN");
    for (int k = 0; k < kNumPairs; ++k) {
      const PairData& p = pairs[k].pair;
      const uint32_t cam = b.AddCamera(0, p.width0, p.height0,
                                       {1.2 * std::max(p.width0, p.height0), p.K0(0, 2) + 0.5, p.K0(1, 2) + 0.5}, false);
      const std::string n1 = "p" + std::to_string(k) + "a.png", n2 = "p" + std::to_string(k) + "b.png";
      const uint32_t i1 = b.AddImage(n1, cam), i2 = b.AddImage(n2, cam);
      std::vector<Eigen::Vector2d> k1, k2;
      std::vector<std::array<uint32_t, 2>> m;
      for (size_t i = 0; i < p.p0.size(); ++i) {
        k1.push_back(p.p0[i] + Eigen::Vector2d(0.5, 0.5));
        k2.push_back(p.p1[i] + Eigen::Vector2d(0.5, 0.5));
        m.push_back({static_cast<uint32_t>(i), static_cast<uint32_t>(i)});
      }
      b.AddKeypoints(i1, k1);
      b.AddKeypoints(i2, k2);
      b.AddMatches(i1, i2, m);
      WriteDepthMapNpy(*p.depth0, d + "/depths/" + n1 + ".npy");
      WriteDepthMapNpy(*p.depth1, d + "/depths/" + n2 + ".npy");
    }
    b.Exec("COMMIT");
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
    pairs += s.num_estimated + s.num_failed;
  }
  state.counters["pairs_per_s"] = benchmark::Counter(static_cast<double>(pairs), benchmark::Counter::kIsRate);
  state.counters["read_share"] = read / total;
  state.counters["write_share"] = write / total;
}

BENCHMARK(BM_TwoViewEstimator)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

}  // namespace
}  // namespace madsfm
