// madsfm_solver_bench: every minimal solver on a pre-generated pool of random realistic instances
// (tests/testing/solver_instances.h), solved round-robin. Compare times as ratios to
// BM_Essential5pt of the same run (docs/benchmarks.md).
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "madsfm/solvers/essential_5pt.h"
#include "madsfm/solvers/fundamental_7pt.h"
#include "madsfm/solvers/relpose_affine_depth_3pt.h"
#include "madsfm/solvers/relpose_affine_depth_shared_focal_4pt.h"
#include "madsfm/solvers/relpose_affine_depth_two_focal_4pt.h"
#include "madsfm/solvers/relpose_scale_depth_3pt.h"
#include "madsfm/solvers/shared_focal_6pt.h"
#include "testing/solver_instances.h"

namespace madsfm {
namespace {

using testing::CameraSetup;

const std::vector<testing::SolverInstance>& Pool(CameraSetup setup, int num_points) {
  static std::vector<testing::SolverInstance> pools[3][8];
  auto& pool = pools[static_cast<int>(setup)][num_points];
  if (pool.empty()) {
    std::mt19937 rng(1234 + 10 * num_points + static_cast<int>(setup));
    testing::SolverInstanceOptions opt;
    opt.setup = setup;
    opt.num_points = num_points;
    for (int i = 0; i < 1000; ++i) pool.push_back(testing::MakeSolverInstance(rng, opt));
  }
  return pool;
}

template <typename Output, typename Solve>
void RunPool(benchmark::State& state, CameraSetup setup, int num_points, Solve solve) {
  const auto& pool = Pool(setup, num_points);
  std::vector<Output> out;
  out.reserve(32);
  size_t i = 0;
  int64_t solutions = 0;
  for (auto _ : state) {
    const auto& inst = pool[i];
    solutions += solve(inst, &out);
    benchmark::DoNotOptimize(out.data());
    i = (i + 1) % pool.size();
  }
  state.counters["solutions"] = benchmark::Counter(static_cast<double>(solutions), benchmark::Counter::kAvgIterations);
}

void BM_AffineDepthCalibrated3pt(benchmark::State& state) {
  RunPool<AffineDepthPose>(state, CameraSetup::kCalibrated, 3, [](const auto& s, auto* out) {
    return SolveRelposeAffineDepth3pt(s.x0, s.x1, s.d0, s.d1, out);
  });
}
void BM_AffineDepthSharedFocal4pt(benchmark::State& state) {
  RunPool<AffineDepthPose>(state, CameraSetup::kSharedFocal, 4, [](const auto& s, auto* out) {
    return SolveRelposeAffineDepthSharedFocal4pt(s.x0, s.x1, s.d0, s.d1, out);
  });
}
void BM_AffineDepthTwoFocal4pt(benchmark::State& state) {
  RunPool<AffineDepthPose>(state, CameraSetup::kTwoFocal, 4, [](const auto& s, auto* out) {
    return SolveRelposeAffineDepthTwoFocal4pt(s.x0, s.x1, s.d0, s.d1, out);
  });
}
void BM_ScaleDepthCalibrated3pt(benchmark::State& state) {
  RunPool<AffineDepthPose>(state, CameraSetup::kCalibrated, 3, [](const auto& s, auto* out) {
    return SolveRelposeScaleDepth3pt(s.x0, s.x1, s.d0, s.d1, out);
  });
}
void BM_Essential5pt(benchmark::State& state) {
  RunPool<Eigen::Matrix3d>(state, CameraSetup::kCalibrated, 5,
                           [](const auto& s, auto* out) { return SolveEssential5pt(s.x0, s.x1, out); });
}
void BM_SharedFocal6pt(benchmark::State& state) {
  RunPool<FocalFundamental>(state, CameraSetup::kSharedFocal, 6,
                            [](const auto& s, auto* out) { return SolveSharedFocal6pt(s.x0, s.x1, out); });
}
void BM_Fundamental7pt(benchmark::State& state) {
  RunPool<Eigen::Matrix3d>(state, CameraSetup::kTwoFocal, 7,
                           [](const auto& s, auto* out) { return SolveFundamental7pt(s.x0, s.x1, out); });
}

BENCHMARK(BM_AffineDepthCalibrated3pt);
BENCHMARK(BM_AffineDepthSharedFocal4pt);
BENCHMARK(BM_AffineDepthTwoFocal4pt);
BENCHMARK(BM_ScaleDepthCalibrated3pt);
BENCHMARK(BM_Essential5pt);
BENCHMARK(BM_SharedFocal6pt);
BENCHMARK(BM_Fundamental7pt);

}  // namespace
}  // namespace madsfm
