// madsfm_refiner_bench: the Levenberg-Marquardt refinement of the hybrid estimator's local optimisation (the hot
// path of `madsfm bench`, docs/benchmarks.md): RefineRelpose, plain least squares with at most 10 iterations, as
// every least-squares step of the LO runs it, on 300 correspondences with 1 px noise, 10% depth noise, every residual
// type (two reprojection residuals per view and the Sampson error per correspondence), from a perturbed ground
// truth. One pool of 100 instances per camera setup, refined round-robin.
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <numeric>
#include <random>
#include <vector>

#include "madsfm/refinement/relpose_refiner.h"
#include "testing/problem_from_instance.h"
#include "testing/solver_instances.h"

namespace madsfm {
namespace {

using testing::CameraSetup;

struct Instance {
  RelposeProblem problem;
  AffineDepthPose start;
};

const std::vector<Instance>& Pool(CameraSetup setup) {
  static std::vector<Instance> pools[3];
  auto& pool = pools[static_cast<int>(setup)];
  if (pool.empty()) {
    std::mt19937 rng(77 + static_cast<int>(setup));
    std::normal_distribution<double> g(0.0, 1.0);
    testing::SolverInstanceOptions opt;
    opt.setup = setup;
    opt.num_points = 300;
    opt.pixel_noise = 1.0;
    opt.depth_noise = 0.1;
    for (int i = 0; i < 100; ++i) {
      const testing::SolverInstance inst = testing::MakeSolverInstance(rng, opt);
      Instance in{testing::ProblemFromInstance(inst, setup), inst.gt};
      in.start.R = Eigen::AngleAxisd(0.01, Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized()).toRotationMatrix() *
                   in.start.R;
      in.start.t += 0.02 * in.start.t.norm() * Eigen::Vector3d(g(rng), g(rng), g(rng));
      in.start.scale *= 1.0 + 0.02 * g(rng);
      if (setup != CameraSetup::kCalibrated) {
        in.start.f0 *= 1.02;
        in.start.f1 = setup == CameraSetup::kSharedFocal ? in.start.f0 : in.start.f1 * 0.98;
      }
      pool.push_back(in);
    }
  }
  return pool;
}

void RunRefiner(benchmark::State& state, CameraSetup setup) {
  const auto& pool = Pool(setup);
  std::vector<int> all(pool[0].problem.size());
  std::iota(all.begin(), all.end(), 0);
  RelposeRefinerOptions ro;
  ro.max_iterations = 10;
  size_t i = 0;
  int64_t converged = 0;
  for (auto _ : state) {
    AffineDepthPose m = pool[i].start;
    converged += RefineRelpose(pool[i].problem, all, all, all, ro, &m);
    benchmark::DoNotOptimize(m.t.data());
    i = (i + 1) % pool.size();
  }
  state.counters["ok"] = benchmark::Counter(static_cast<double>(converged), benchmark::Counter::kAvgIterations);
}

void BM_RefineCalibrated(benchmark::State& state) { RunRefiner(state, CameraSetup::kCalibrated); }
void BM_RefineSharedFocal(benchmark::State& state) { RunRefiner(state, CameraSetup::kSharedFocal); }
void BM_RefineTwoFocal(benchmark::State& state) { RunRefiner(state, CameraSetup::kTwoFocal); }

BENCHMARK(BM_RefineCalibrated)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RefineSharedFocal)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RefineTwoFocal)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace madsfm
