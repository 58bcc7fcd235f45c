#include "madsfm/solvers/essential_5pt.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "testing/solver_instances.h"
#include "testing/median.h"

namespace madsfm {
namespace {

using testing::CameraSetup;
using testing::MakeSolverInstance;
using testing::SolverInstance;
using testing::SolverInstanceOptions;

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d s;
  s << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return s;
}

// Ground-truth essential matrix [t]_x R with unit Frobenius norm.
Eigen::Matrix3d TrueEssential(const SolverInstance& inst) {
  return (Skew(inst.gt.t) * inst.gt.R).normalized();
}

// ||E - E_gt|| / ||E_gt|| with the sign of E chosen to match E_gt (both unit norm).
double EssentialError(const Eigen::Matrix3d& e, const Eigen::Matrix3d& e_gt) {
  return std::min((e - e_gt).norm(), (e + e_gt).norm());
}

// max_i |[x1;1]^T E [x0;1]| / (|[x1;1]| |[x0;1]|) over the first 5 correspondences (unit-norm E).
double MaxEpipolarResidual(const Eigen::Matrix3d& e, const std::vector<Eigen::Vector2d>& x0,
                           const std::vector<Eigen::Vector2d>& x1) {
  double worst = 0.0;
  for (int i = 0; i < 5; ++i) {
    const Eigen::Vector3d a = x0[i].homogeneous(), b = x1[i].homogeneous();
    worst = std::max(worst, std::abs(b.dot(e * a)) / (a.norm() * b.norm()));
  }
  return worst;
}

// Number of pairs of solutions that coincide (up to sign).
int CountDuplicates(const std::vector<Eigen::Matrix3d>& essentials) {
  int count = 0;
  for (size_t i = 0; i < essentials.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      count += std::min((essentials[i] - essentials[j]).norm(), (essentials[i] + essentials[j]).norm()) < 1e-12;
  return count;
}

// Singular values of a unit-norm essential matrix are (s, s, 0) with s = 1/sqrt(2); returns the worst deviation.
double EssentialDefect(const Eigen::Matrix3d& e) {
  const Eigen::Vector3d s = Eigen::JacobiSVD<Eigen::Matrix3d>(e).singularValues();
  return std::max(std::abs(s(0) - s(1)), std::abs(s(2)));
}

// Smallest angle (radians) between two rotations.
double RotationAngle(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  const double c = std::clamp(0.5 * ((a.transpose() * b).trace() - 1.0), -1.0, 1.0);
  return std::acos(c);
}

// Decomposes E into the rotation of the (R, t) pair (out of four) that puts the most of the correspondences in
// front of both cameras (midpoint triangulation).
Eigen::Matrix3d RotationFromEssential(const Eigen::Matrix3d& e, const std::vector<Eigen::Vector2d>& x0,
                                      const std::vector<Eigen::Vector2d>& x1) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(e, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU(), v = svd.matrixV();
  if (u.determinant() < 0) u = -u;
  if (v.determinant() < 0) v = -v;
  Eigen::Matrix3d w;
  w << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  const Eigen::Matrix3d rotations[2] = {u * w * v.transpose(), u * w.transpose() * v.transpose()};
  const Eigen::Vector3d translations[2] = {u.col(2), -u.col(2)};
  int best_count = -1;
  Eigen::Matrix3d best = rotations[0];
  for (const Eigen::Matrix3d& r : rotations) {
    for (const Eigen::Vector3d& t : translations) {
      int count = 0;
      for (size_t i = 0; i < x0.size(); ++i) {
        // Depths (l0, l1) minimising |l1 b - (l0 R a + t)|.
        const Eigen::Vector3d a = r * x0[i].homogeneous(), b = x1[i].homogeneous();
        Eigen::Matrix<double, 3, 2> m;
        m << a, -b;
        const Eigen::Vector2d l = m.colPivHouseholderQr().solve(-t);
        count += l(0) > 0 && l(1) > 0;
      }
      if (count > best_count) {
        best_count = count;
        best = r;
      }
    }
  }
  return best;
}

using testing::Median;

TEST(Essential5pt, RecoversGroundTruthOnNoiseFreeInstances) {
  std::mt19937 rng(20240501);
  SolverInstanceOptions options;
  options.setup = CameraSetup::kCalibrated;
  options.num_points = 5;
  const int kTrials = 1000;
  int found = 0, max_count = 0, total_solutions = 0, bad_epipolar = 0, bad_essential = 0, duplicates = 0;
  double worst_epipolar = 0.0, worst_defect = 0.0;
  std::vector<Eigen::Matrix3d> essentials;
  for (int trial = 0; trial < kTrials; ++trial) {
    const SolverInstance inst = MakeSolverInstance(rng, options);
    const int n = SolveEssential5pt(inst.x0, inst.x1, &essentials);
    ASSERT_EQ(n, static_cast<int>(essentials.size()));
    ASSERT_LE(n, 10);
    max_count = std::max(max_count, n);
    total_solutions += n;
    duplicates += CountDuplicates(essentials);
    const Eigen::Matrix3d e_gt = TrueEssential(inst);
    double best = std::numeric_limits<double>::infinity();
    for (const Eigen::Matrix3d& e : essentials) {
      ASSERT_TRUE(e.allFinite());
      EXPECT_NEAR(e.norm(), 1.0, 1e-12);
      best = std::min(best, EssentialError(e, e_gt));
      const double epipolar = MaxEpipolarResidual(e, inst.x0, inst.x1);
      const double defect = EssentialDefect(e);
      worst_epipolar = std::max(worst_epipolar, epipolar);
      worst_defect = std::max(worst_defect, defect);
      bad_epipolar += !(epipolar < 1e-9);
      bad_essential += !(defect < 1e-8);
    }
    found += best < 1e-6;
  }
  const double rate = static_cast<double>(found) / kTrials;
  std::printf("essential_5pt: ground truth among the solutions (rel. error < 1e-6) in %.1f%% of %d instances\n",
              100 * rate, kTrials);
  std::printf("essential_5pt: %.2f solutions on average, at most %d; worst epipolar residual %.2e, worst "
              "essential defect %.2e\n",
              static_cast<double>(total_solutions) / kTrials, max_count, worst_epipolar, worst_defect);
  EXPECT_GE(rate, 0.99);
  EXPECT_EQ(bad_epipolar, 0);
  EXPECT_EQ(bad_essential, 0);
  EXPECT_EQ(duplicates, 0);
}

TEST(Essential5pt, UsesOnlyTheFirstFiveCorrespondences) {
  std::mt19937 rng(11);
  SolverInstanceOptions options;
  options.num_points = 5;
  const SolverInstance inst = MakeSolverInstance(rng, options);
  std::vector<Eigen::Matrix3d> a, b;
  SolveEssential5pt(inst.x0, inst.x1, &a);
  ASSERT_FALSE(a.empty());
  std::vector<Eigen::Vector2d> x0 = inst.x0, x1 = inst.x1;
  x0.push_back(Eigen::Vector2d(0.3, -0.2));
  x1.push_back(Eigen::Vector2d(-0.1, 0.4));
  b.push_back(Eigen::Matrix3d::Identity());  // the output is cleared first
  SolveEssential5pt(x0, x1, &b);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_LT((a[i] - b[i]).norm(), 1e-12);
}

// Every returned E must be finite, satisfy the 5 epipolar constraints and be an essential matrix.
void ExpectValidOrEmpty(const std::vector<Eigen::Vector2d>& x0, const std::vector<Eigen::Vector2d>& x1,
                        const char* what) {
  std::vector<Eigen::Matrix3d> essentials(3, Eigen::Matrix3d::Identity());
  const int n = SolveEssential5pt(x0, x1, &essentials);
  ASSERT_GE(n, 0) << what;
  ASSERT_LE(n, 10) << what;
  ASSERT_EQ(n, static_cast<int>(essentials.size())) << what;
  for (const Eigen::Matrix3d& e : essentials) {
    ASSERT_TRUE(e.allFinite()) << what;
    EXPECT_NEAR(e.norm(), 1.0, 1e-12) << what;
    EXPECT_LT(MaxEpipolarResidual(e, x0, x1), 1e-9) << what;
    EXPECT_LT(EssentialDefect(e), 1e-8) << what;
  }
  std::printf("essential_5pt: %s -> %d solutions\n", what, n);
}

TEST(Essential5pt, HandlesDegenerateInput) {
  std::mt19937 rng(5);
  SolverInstanceOptions options;
  options.num_points = 5;
  const SolverInstance inst = MakeSolverInstance(rng, options);

  ExpectValidOrEmpty({}, {}, "no points");
  {
    std::vector<Eigen::Vector2d> x0(inst.x0.begin(), inst.x0.begin() + 4), x1(inst.x1.begin(), inst.x1.begin() + 4);
    ExpectValidOrEmpty(x0, x1, "4 points");
    ExpectValidOrEmpty(inst.x0, x1, "5 and 4 points");
  }
  {
    std::vector<Eigen::Vector2d> x0(5, inst.x0[0]), x1(5, inst.x1[0]);
    ExpectValidOrEmpty(x0, x1, "coincident points");
  }
  {
    std::vector<Eigen::Vector2d> x0(5, Eigen::Vector2d::Zero()), x1(5, Eigen::Vector2d::Zero());
    ExpectValidOrEmpty(x0, x1, "all points at the origin");
  }
  {
    std::vector<Eigen::Vector2d> x0, x1;
    for (int i = 0; i < 5; ++i) {
      x0.push_back(Eigen::Vector2d(-0.2, 0.1) + 0.1 * i * Eigen::Vector2d(1.0, 0.5));
      x1.push_back(Eigen::Vector2d(0.15, -0.1) + (0.07 * i + 0.01 * i * i) * Eigen::Vector2d(0.3, 1.0));
    }
    ExpectValidOrEmpty(x0, x1, "collinear points");
  }
  {
    // A planar scene seen under a pure rotation: all epipolar geometries with the right rotation fit.
    std::vector<Eigen::Vector2d> x1 = inst.x0;
    ExpectValidOrEmpty(inst.x0, x1, "identical images");
  }
  {
    std::vector<Eigen::Vector2d> x0 = inst.x0;
    x0[2].x() = std::numeric_limits<double>::quiet_NaN();
    ExpectValidOrEmpty(x0, inst.x1, "NaN coordinate");
    x0[2].x() = std::numeric_limits<double>::infinity();
    ExpectValidOrEmpty(x0, inst.x1, "infinite coordinate");
  }
  {
    std::vector<Eigen::Vector2d> x0 = inst.x0, x1 = inst.x1;
    for (auto& p : x0) p *= 1e12;
    ExpectValidOrEmpty(x0, x1, "huge coordinates");
    for (auto& p : x0) p *= 1e-24;
    ExpectValidOrEmpty(x0, x1, "tiny coordinates");
  }
}

TEST(Essential5pt, RandomCorrespondencesGiveValidSolutions) {
  // Any 5 correspondences have essential matrices through them (not necessarily real ones).
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int kTrials = 1000;
  int bad = 0, total = 0;
  std::vector<Eigen::Matrix3d> essentials;
  for (int trial = 0; trial < kTrials; ++trial) {
    std::vector<Eigen::Vector2d> x0, x1;
    for (int i = 0; i < 5; ++i) {
      x0.push_back(Eigen::Vector2d(u(rng), u(rng)));
      x1.push_back(Eigen::Vector2d(u(rng), u(rng)));
    }
    const int n = SolveEssential5pt(x0, x1, &essentials);
    ASSERT_LE(n, 10);
    total += n;
    for (const Eigen::Matrix3d& e : essentials) {
      ASSERT_TRUE(e.allFinite());
      bad += !(MaxEpipolarResidual(e, x0, x1) < 1e-9 && EssentialDefect(e) < 1e-8);
    }
  }
  std::printf("essential_5pt: random correspondences: %.2f solutions on average, %d invalid\n",
              static_cast<double>(total) / kTrials, bad);
  EXPECT_EQ(bad, 0);
  EXPECT_GT(total, kTrials);
}

TEST(Essential5pt, RotationAccuracyUnderPixelNoise) {
  std::mt19937 rng(777);
  SolverInstanceOptions options;
  options.num_points = 5;
  options.pixel_noise = 0.5;
  const int kTrials = 1000;
  std::vector<double> errors_deg;
  int with_solution = 0;
  std::vector<Eigen::Matrix3d> essentials;
  for (int trial = 0; trial < kTrials; ++trial) {
    const SolverInstance inst = MakeSolverInstance(rng, options);
    SolveEssential5pt(inst.x0, inst.x1, &essentials);
    double best = M_PI;
    for (const Eigen::Matrix3d& e : essentials) {
      ASSERT_TRUE(e.allFinite());
      best = std::min(best, RotationAngle(RotationFromEssential(e, inst.x0, inst.x1), inst.gt.R));
    }
    with_solution += !essentials.empty();
    errors_deg.push_back(best * 180.0 / M_PI);
  }
  const double median = Median(errors_deg);
  std::printf("essential_5pt: 0.5 px noise: median rotation error of the best solution %.3f deg over %d "
              "instances (%.1f%% with a solution)\n",
              median, kTrials, 100.0 * with_solution / kTrials);
  // The error grows linearly with the noise (about 0.12 deg at 0.05 px on these instances): it is the sensitivity
  // of the minimal problem (5 points, small baselines), not of the solver. A broken solver gives tens of degrees.
  EXPECT_GE(with_solution, 0.99 * kTrials);
  EXPECT_LT(median, 2.0);
}

}  // namespace
}  // namespace madsfm
