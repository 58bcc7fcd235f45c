#include "madsfm/refinement/relpose_refiner.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numeric>
#include <random>

#include "testing/problem_from_instance.h"
#include "testing/solver_instances.h"

namespace madsfm {
namespace {

using testing::CameraSetup;

AffineDepthPose Perturb(const AffineDepthPose& m, int param, double h) {
  AffineDepthPose n = m;
  if (param < 3) {
    n.R = Eigen::AngleAxisd(h, Eigen::Vector3d::Unit(param)).toRotationMatrix() * m.R;
  } else if (param < 6) {
    n.t(param - 3) += h;
  } else if (param == 6) {
    n.shift0 += h;
  } else if (param == 7) {
    n.shift1 += h;
  } else if (param == 8) {
    n.scale += h;
  } else if (param == 9) {
    n.f0 += h;
  } else {
    n.f1 += h;
  }
  return n;
}

std::vector<int> Iota(int n) {
  std::vector<int> v(n);
  std::iota(v.begin(), v.end(), 0);
  return v;
}

class RefinerTest : public ::testing::TestWithParam<CameraSetup> {};

TEST_P(RefinerTest, AnalyticJacobianMatchesFiniteDifferences) {
  std::mt19937 rng(11);
  testing::SolverInstanceOptions opt;
  opt.setup = GetParam();
  opt.num_points = 15;
  opt.pixel_noise = 2.0;  // non-zero residuals
  int checked = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const auto inst = testing::MakeSolverInstance(rng, opt);
    const RelposeProblem p = testing::ProblemFromInstance(inst, opt.setup);
    const std::vector<int> all = Iota(p.size());
    AffineDepthPose m = inst.gt;
    m.f1 = m.f1 * 1.01;  // f0 != f1 so both focal columns are exercised
    std::vector<double> r;
    std::vector<std::vector<double>> J;
    EvaluateRelposeResiduals(p, all, all, all, 3.0, m, &r, &J);
    ASSERT_EQ(r.size(), 5u * p.size());
    for (int j = 0; j < kRelposeNumParams; ++j) {
      const double scale_j = j < 3 ? 1.0 : (j < 6 ? m.t.norm() : (j < 8 ? inst.median_depth : (j == 8 ? m.scale : m.f0)));
      const double h = 1e-6 * scale_j;
      std::vector<double> rp, rm;
      EvaluateRelposeResiduals(p, all, all, all, 3.0, Perturb(m, j, h), &rp);
      EvaluateRelposeResiduals(p, all, all, all, 3.0, Perturb(m, j, -h), &rm);
      ASSERT_EQ(rp.size(), r.size());
      for (size_t k = 0; k < r.size(); ++k) {
        const double fd = (rp[k] - rm[k]) / (2 * h);
        const double tol = 1e-5 * (std::abs(fd) + std::abs(J[k][j])) + 1e-6 * (1.0 + std::abs(r[k])) / scale_j;
        EXPECT_NEAR(J[k][j], fd, tol) << "param " << j << " residual " << k;
      }
    }
    ++checked;
  }
  EXPECT_EQ(checked, 20);
}

TEST_P(RefinerTest, ConvergesFromPerturbedGroundTruth) {
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  testing::SolverInstanceOptions opt;
  opt.setup = GetParam();
  opt.num_points = 40;
  int ok = 0;
  const int kTrials = 100;
  for (int trial = 0; trial < kTrials; ++trial) {
    const auto inst = testing::MakeSolverInstance(rng, opt);
    const RelposeProblem p = testing::ProblemFromInstance(inst, opt.setup);
    const std::vector<int> all = Iota(p.size());
    AffineDepthPose m = inst.gt;
    m.R = Eigen::AngleAxisd(0.03, Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized()).toRotationMatrix() * m.R;
    m.t += 0.05 * m.t.norm() * Eigen::Vector3d(g(rng), g(rng), g(rng));
    m.shift0 += 0.03 * inst.median_depth * g(rng);
    m.shift1 += 0.03 * inst.median_depth / m.scale * g(rng);
    m.scale *= 1.0 + 0.03 * g(rng);
    if (opt.setup != CameraSetup::kCalibrated) {
      m.f0 *= 1.05;
      m.f1 = opt.setup == CameraSetup::kSharedFocal ? m.f0 : m.f1 * 0.95;
    }
    RelposeRefinerOptions ro;
    ro.max_iterations = 100;
    ro.sampson_weight = 2.0;
    RelposeRefinerSummary summary;
    if (!RefineRelpose(p, all, all, all, ro, &m, &summary)) continue;
    ok += testing::ModelError(m, inst) < 1e-6;
  }
  const double rate = static_cast<double>(ok) / kTrials;
  std::printf("refiner (%d): converged to ground truth (1e-6) in %.1f%% of %d perturbed instances\n",
              static_cast<int>(GetParam()), 100 * rate, kTrials);
  EXPECT_GE(rate, 0.95);
}

TEST(Refiner, RejectsTooFewResiduals) {
  RelposeProblem p;
  p.mode = CameraMode::kCalibrated;
  p.x0 = {{0.1, 0.2}};
  p.x1 = {{0.1, 0.25}};
  p.d0 = {2.0};
  p.d1 = {2.0};
  p.IndexDepths();
  AffineDepthPose m;
  m.t = Eigen::Vector3d(0.1, 0, 0);
  const AffineDepthPose before = m;
  EXPECT_FALSE(RefineRelpose(p, {}, {}, {0}, RelposeRefinerOptions(), &m));
  EXPECT_EQ(m.t, before.t);
}

INSTANTIATE_TEST_SUITE_P(Modes, RefinerTest,
                         ::testing::Values(CameraSetup::kCalibrated, CameraSetup::kSharedFocal, CameraSetup::kTwoFocal));

}  // namespace
}  // namespace madsfm
