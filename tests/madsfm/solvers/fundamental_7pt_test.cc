#include "madsfm/solvers/fundamental_7pt.h"

#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "madsfm/geometry/essential_matrix.h"
#include "testing/solver_instances.h"

namespace madsfm {
namespace {

using testing::CameraSetup;
using testing::MakeSolverInstance;
using testing::SolverInstance;
using testing::SolverInstanceOptions;

Eigen::Matrix3d Intrinsics(double f, const Eigen::Vector2d& pp) {
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  K(0, 0) = K(1, 1) = f;
  K.block<2, 1>(0, 2) = pp;
  return K;
}

// Ground-truth F (unit norm) of an instance whose points are shifted by pp0 / pp1.
Eigen::Matrix3d TrueFundamental(const SolverInstance& inst, const Eigen::Vector2d& pp0, const Eigen::Vector2d& pp1) {
  const Eigen::Matrix3d F = FundamentalFromEssential(EssentialFromPose(inst.gt.R, inst.gt.t),
                                                     Intrinsics(inst.gt.f0, pp0), Intrinsics(inst.gt.f1, pp1));
  return F / F.norm();
}

// Distance of F to +-F_gt (both unit norm).
double SignFreeError(const Eigen::Matrix3d& F, const Eigen::Matrix3d& F_gt) {
  return std::min((F - F_gt).norm(), (F + F_gt).norm());
}

// sigma_3 / sigma_1.
double RankTwoResidual(const Eigen::Matrix3d& F) {
  const Eigen::Vector3d sv = Eigen::JacobiSVD<Eigen::Matrix3d>(F).singularValues();
  return sv(2) / sv(0);
}

// Largest Sampson error (pixels) of the first 7 correspondences.
double MaxSampson(const Eigen::Matrix3d& F, const std::vector<Eigen::Vector2d>& p0,
                  const std::vector<Eigen::Vector2d>& p1) {
  double worst = 0.0;
  for (int i = 0; i < 7; ++i) worst = std::max(worst, std::sqrt(SampsonErrorSquared(F, p0[i], p1[i])));
  return worst;
}

struct RateStats {
  int found = 0, total = 0, max_count = 0, total_solutions = 0;
  double worst_rank = 0.0, worst_sampson = 0.0;
  std::vector<double> best_errors;  // per instance, distance of the closest solution to F_gt
  bool all_finite = true;
};

RateStats RunRandomInstances(const Eigen::Vector2d& pp0, const Eigen::Vector2d& pp1, unsigned seed) {
  std::mt19937 rng(seed);
  SolverInstanceOptions opt;
  opt.setup = CameraSetup::kTwoFocal;
  opt.num_points = 7;
  RateStats stats;
  std::vector<Eigen::Matrix3d> Fs;
  for (int trial = 0; trial < 1000; ++trial) {
    SolverInstance inst = MakeSolverInstance(rng, opt);
    for (auto& p : inst.x0) p += pp0;
    for (auto& p : inst.x1) p += pp1;
    const Eigen::Matrix3d F_gt = TrueFundamental(inst, pp0, pp1);
    const int n = SolveFundamental7pt(inst.x0, inst.x1, &Fs);
    EXPECT_EQ(n, static_cast<int>(Fs.size()));
    stats.max_count = std::max(stats.max_count, n);
    stats.total_solutions += n;
    ++stats.total;
    double best = std::numeric_limits<double>::infinity();
    for (const auto& F : Fs) {
      if (!F.allFinite()) stats.all_finite = false;
      EXPECT_NEAR(F.norm(), 1.0, 1e-12);
      stats.worst_rank = std::max(stats.worst_rank, RankTwoResidual(F));
      stats.worst_sampson = std::max(stats.worst_sampson, MaxSampson(F, inst.x0, inst.x1));
      best = std::min(best, SignFreeError(F, F_gt));
    }
    if (best < 1e-6) ++stats.found;
    stats.best_errors.push_back(best);
  }
  std::sort(stats.best_errors.begin(), stats.best_errors.end());
  return stats;
}

TEST(Fundamental7pt, RecoversTrueFundamentalOnRandomInstances) {
  const RateStats s = RunRandomInstances(Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), 7);
  std::printf("[7pt centred] true F among the solutions (rel. err < 1e-6) in %d / %d instances (%.1f%%); "
              "mean #solutions %.2f, max %d; worst sigma3/sigma1 %.2e, worst Sampson error %.2e px\n",
              s.found, s.total, 100.0 * s.found / s.total, static_cast<double>(s.total_solutions) / s.total,
              s.max_count, s.worst_rank, s.worst_sampson);
  std::printf("[7pt centred] closest-solution error: median %.2e, 99th percentile %.2e, max %.2e\n",
              s.best_errors[500], s.best_errors[989], s.best_errors.back());
  EXPECT_TRUE(s.all_finite);
  EXPECT_GE(s.found, 990);
  EXPECT_LE(s.max_count, 3);
  EXPECT_LT(s.worst_rank, 1e-9);     // every solution has rank 2
  EXPECT_LT(s.worst_sampson, 1e-6);  // and satisfies the 7 epipolar constraints (pixels)
}

TEST(Fundamental7pt, RecoversTrueFundamentalWithOffCentrePixels) {
  // Pixel coordinates with the principal point far from the origin: the internal normalisation
  // must keep the conditioning.
  const RateStats s = RunRandomInstances(Eigen::Vector2d(960.0, 540.0), Eigen::Vector2d(2000.0, 1500.0), 11);
  std::printf("[7pt off-centre] true F among the solutions (rel. err < 1e-6) in %d / %d instances (%.1f%%); "
              "worst sigma3/sigma1 %.2e, worst Sampson error %.2e px\n",
              s.found, s.total, 100.0 * s.found / s.total, s.worst_rank, s.worst_sampson);
  EXPECT_TRUE(s.all_finite);
  EXPECT_GE(s.found, 990);
  EXPECT_LE(s.max_count, 3);
  EXPECT_LT(s.worst_rank, 1e-9);
  EXPECT_LT(s.worst_sampson, 1e-6);
}

TEST(Fundamental7pt, BougnouxOnSolverOutputGivesTrueFocals) {
  std::mt19937 rng(21);
  SolverInstanceOptions opt;
  opt.setup = CameraSetup::kTwoFocal;
  opt.num_points = 7;
  std::vector<Eigen::Matrix3d> Fs;
  int found = 0;
  const int kTrials = 1000;
  for (int trial = 0; trial < kTrials; ++trial) {
    const SolverInstance inst = MakeSolverInstance(rng, opt);
    SolveFundamental7pt(inst.x0, inst.x1, &Fs);
    double best = std::numeric_limits<double>::infinity();
    for (const auto& F : Fs) {
      double f0, f1;
      if (!BougnouxFocals(F, &f0, &f1)) continue;
      best = std::min(best, std::max(std::abs(f0 / inst.gt.f0 - 1.0), std::abs(f1 / inst.gt.f1 - 1.0)));
    }
    if (best < 1e-6) ++found;
  }
  std::printf("[7pt + Bougnoux] both focals within 1e-6 (relative) for some solution in %d / %d instances (%.1f%%)\n",
              found, kTrials, 100.0 * found / kTrials);
  // End to end: 7-point F, then Bougnoux (which amplifies F errors near its degeneracy).
  EXPECT_GE(found, 990);
}

void ExpectFiniteSolutions(const std::vector<Eigen::Vector2d>& p0, const std::vector<Eigen::Vector2d>& p1) {
  std::vector<Eigen::Matrix3d> Fs;
  const int n = SolveFundamental7pt(p0, p1, &Fs);
  EXPECT_GE(n, 0);
  EXPECT_LE(n, 3);
  EXPECT_EQ(n, static_cast<int>(Fs.size()));
  for (const auto& F : Fs) EXPECT_TRUE(F.allFinite());
}

TEST(Fundamental7pt, UsesOnlyTheFirstSevenCorrespondences) {
  std::mt19937 rng(17);
  SolverInstanceOptions opt;
  opt.setup = CameraSetup::kTwoFocal;
  opt.num_points = 7;
  const SolverInstance inst = MakeSolverInstance(rng, opt);
  std::vector<Eigen::Matrix3d> Fs, Fs_more;
  const int n = SolveFundamental7pt(inst.x0, inst.x1, &Fs);
  std::vector<Eigen::Vector2d> x0 = inst.x0, x1 = inst.x1;
  x0.emplace_back(123.0, -45.0);  // an outlier after the sample
  x1.emplace_back(-7.0, 300.0);
  ASSERT_EQ(SolveFundamental7pt(x0, x1, &Fs_more), n);
  for (int i = 0; i < n; ++i) EXPECT_EQ(Fs[i], Fs_more[i]);
}

TEST(Fundamental7pt, DegenerateInputGivesNoSolutionOrFiniteOnes) {
  std::vector<Eigen::Matrix3d> Fs;
  const std::vector<Eigen::Vector2d> same(7, Eigen::Vector2d(3.0, 4.0));
  EXPECT_EQ(SolveFundamental7pt(same, same, &Fs), 0);
  EXPECT_TRUE(Fs.empty());

  std::vector<Eigen::Vector2d> p0, p1;
  for (int i = 0; i < 6; ++i) {
    p0.emplace_back(i, 2 * i + 1);
    p1.emplace_back(i * i, i - 3);
  }
  EXPECT_EQ(SolveFundamental7pt(p0, p1, &Fs), 0);  // fewer than 7 points

  p0.emplace_back(0.5, -1.0);
  p1.emplace_back(2.0, 7.0);
  ExpectFiniteSolutions(p0, p1);  // 7 arbitrary points
  std::vector<Eigen::Vector2d> nan0 = p0;
  nan0[3].x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(SolveFundamental7pt(nan0, p1, &Fs), 0);
  nan0[3].x() = std::numeric_limits<double>::infinity();
  EXPECT_EQ(SolveFundamental7pt(p0, nan0, &Fs), 0);

  // Collinear points in both images.
  std::vector<Eigen::Vector2d> l0, l1;
  for (int i = 0; i < 7; ++i) {
    l0.emplace_back(10.0 * i, 5.0 * i - 3.0);
    l1.emplace_back(-4.0 * i + 1.0, 2.0 * i * i);
  }
  ExpectFiniteSolutions(l0, l1);
  ExpectFiniteSolutions(l0, l0);

  // Planar scene (all correspondences related by one homography): F is not determined.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-500.0, 500.0);
  Eigen::Matrix3d H;
  H << 1.1, 0.05, 20.0, -0.03, 0.95, -15.0, 1e-4, -2e-4, 1.0;
  std::vector<Eigen::Vector2d> h0, h1;
  for (int i = 0; i < 7; ++i) {
    h0.emplace_back(u(rng), u(rng));
    h1.push_back((H * h0.back().homogeneous()).hnormalized());
  }
  ExpectFiniteSolutions(h0, h1);
  // Pure identity motion (no parallax at all).
  ExpectFiniteSolutions(h0, h0);
}

}  // namespace
}  // namespace madsfm
