#include "madsfm/geometry/essential_matrix.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "testing/solver_instances.h"

namespace madsfm {
namespace {

using testing::CameraSetup;
using testing::MakeSolverInstance;
using testing::SolverInstance;
using testing::SolverInstanceOptions;

Eigen::Matrix3d RandomRotation(std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  return Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
}

Eigen::Matrix3d FocalMatrix(double f) { return Eigen::Vector3d(f, f, 1.0).asDiagonal(); }

TEST(EssentialMatrix, CrossProductMatrixActsAsCrossProduct) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng));
    const Eigen::Matrix3d A = CrossProductMatrix(a);
    EXPECT_LT((A * b - a.cross(b)).norm(), 1e-12);
    EXPECT_LT((A + A.transpose()).norm(), 1e-15);
  }
}

TEST(EssentialMatrix, EssentialFromPoseSatisfiesEpipolarConstraint) {
  std::mt19937 rng(2);
  SolverInstanceOptions opt;
  opt.num_points = 20;
  for (int trial = 0; trial < 100; ++trial) {
    const SolverInstance inst = MakeSolverInstance(rng, opt);
    const Eigen::Matrix3d E = EssentialFromPose(inst.gt.R, inst.gt.t);
    const Eigen::Matrix3d En = E / E.norm();
    for (int i = 0; i < opt.num_points; ++i) {
      EXPECT_NEAR(inst.x1[i].homogeneous().dot(En * inst.x0[i].homogeneous()), 0.0, 1e-12);
    }
    // Essential: two equal singular values, one zero.
    const Eigen::Vector3d sv = Eigen::JacobiSVD<Eigen::Matrix3d>(En).singularValues();
    EXPECT_NEAR(sv(0), sv(1), 1e-12);
    EXPECT_NEAR(sv(2), 0.0, 1e-12);
  }
}

TEST(EssentialMatrix, DecomposeEssentialContainsThePose) {
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int trial = 0; trial < 1000; ++trial) {
    const Eigen::Matrix3d R = RandomRotation(rng);
    const Eigen::Vector3d t(g(rng), g(rng), g(rng));
    // Any scale and sign of E.
    const double s = (trial % 2 ? -1.0 : 1.0) * std::exp(g(rng));
    Eigen::Matrix3d R1, R2;
    Eigen::Vector3d tu;
    DecomposeEssential(s * EssentialFromPose(R, t), &R1, &R2, &tu);
    EXPECT_NEAR(R1.determinant(), 1.0, 1e-12);
    EXPECT_NEAR(R2.determinant(), 1.0, 1e-12);
    EXPECT_LT((R1 * R1.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    EXPECT_LT((R2 * R2.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    EXPECT_NEAR(tu.norm(), 1.0, 1e-12);
    EXPECT_LT(std::min((R1 - R).norm(), (R2 - R).norm()), 1e-10);
    const Eigen::Vector3d t_unit = t.normalized();
    EXPECT_LT(std::min((tu - t_unit).norm(), (tu + t_unit).norm()), 1e-10);
  }
}

TEST(EssentialMatrix, PoseFromEssentialResolvesCheirality) {
  std::mt19937 rng(4);
  SolverInstanceOptions opt;
  for (int trial = 0; trial < 1000; ++trial) {
    opt.num_points = 1 + trial % 10;
    const SolverInstance inst = MakeSolverInstance(rng, opt);
    // Scale and sign of E do not matter.
    const Eigen::Matrix3d E = (trial % 2 ? -3.0 : 0.5) * EssentialFromPose(inst.gt.R, inst.gt.t);
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    ASSERT_TRUE(PoseFromEssential(E, inst.x0, inst.x1, &R, &t));
    EXPECT_LT((R - inst.gt.R).norm(), 1e-9) << "trial " << trial;
    EXPECT_LT((t - inst.gt.t.normalized()).norm(), 1e-9) << "trial " << trial;
  }
}

TEST(EssentialMatrix, PoseFromEssentialFailsWithoutUsablePoints) {
  const Eigen::Matrix3d E = EssentialFromPose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(1.0, 0.0, 0.0));
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  EXPECT_FALSE(PoseFromEssential(E, {}, {}, &R, &t));
  const std::vector<Eigen::Vector2d> nan = {Eigen::Vector2d(std::numeric_limits<double>::quiet_NaN(), 0.0)};
  EXPECT_FALSE(PoseFromEssential(E, nan, nan, &R, &t));
  EXPECT_FALSE(PoseFromEssential(Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN()),
                                 {Eigen::Vector2d(0.1, 0.2)}, {Eigen::Vector2d(0.3, 0.2)}, &R, &t));
}

TEST(EssentialMatrix, FundamentalFromEssentialMapsPixels) {
  std::mt19937 rng(5);
  SolverInstanceOptions opt;
  opt.setup = CameraSetup::kTwoFocal;
  opt.num_points = 10;
  for (int trial = 0; trial < 100; ++trial) {
    SolverInstance inst = MakeSolverInstance(rng, opt);
    // General intrinsics: principal points away from the origin.
    Eigen::Matrix3d K0 = FocalMatrix(inst.gt.f0), K1 = FocalMatrix(inst.gt.f1);
    K0.block<2, 1>(0, 2) = Eigen::Vector2d(320.0, 240.0);
    K1.block<2, 1>(0, 2) = Eigen::Vector2d(-100.0, 700.0);
    const Eigen::Matrix3d F = FundamentalFromEssential(EssentialFromPose(inst.gt.R, inst.gt.t), K0, K1);
    const Eigen::Matrix3d Fn = F / F.norm();
    for (int i = 0; i < opt.num_points; ++i) {
      const Eigen::Vector2d p0 = inst.x0[i] + K0.block<2, 1>(0, 2), p1 = inst.x1[i] + K1.block<2, 1>(0, 2);
      EXPECT_LT(std::sqrt(SampsonErrorSquared(Fn, p0, p1)), 1e-8);
    }
    EXPECT_LT((K1.transpose() * F * K0 - EssentialFromPose(inst.gt.R, inst.gt.t)).norm(),
              1e-9 * EssentialFromPose(inst.gt.R, inst.gt.t).norm());
  }
}

// c(p0, p1) = [p1;1]^T F [p0;1]; the Sampson error is c^2 / |grad c|^2 (gradient over the four
// image coordinates), the squared length of the first-order correction onto c = 0.
double EpipolarResidual(const Eigen::Matrix3d& F, const Eigen::Vector4d& p) {
  return Eigen::Vector3d(p(2), p(3), 1.0).dot(F * Eigen::Vector3d(p(0), p(1), 1.0));
}

TEST(EssentialMatrix, SampsonErrorMatchesFirstOrderGeometricError) {
  std::mt19937 rng(6);
  std::normal_distribution<double> g(0.0, 1.0);
  SolverInstanceOptions opt;
  opt.setup = CameraSetup::kTwoFocal;
  opt.num_points = 10;
  double worst_exact = 0.0, worst_formula = 0.0, worst_linearised = 0.0;
  for (int trial = 0; trial < 100; ++trial) {
    const SolverInstance inst = MakeSolverInstance(rng, opt);
    const double fscale = (trial % 2 ? 1.0 : -1e-3) * std::exp(g(rng));  // scale-invariant
    const Eigen::Matrix3d F = fscale * FundamentalFromEssential(EssentialFromPose(inst.gt.R, inst.gt.t),
                                                                FocalMatrix(inst.gt.f0), FocalMatrix(inst.gt.f1));
    for (int i = 0; i < opt.num_points; ++i) {
      // Exact correspondences: zero error (relative to the pixel scale).
      worst_exact = std::max(worst_exact, std::sqrt(SampsonErrorSquared(F, inst.x0[i], inst.x1[i])));
      // Perturbed by ~1 px: compare with the direct first-order evaluation (central differences).
      Eigen::Vector4d p(inst.x0[i].x(), inst.x0[i].y(), inst.x1[i].x(), inst.x1[i].y());
      p += Eigen::Vector4d(g(rng), g(rng), g(rng), g(rng));
      const double c = EpipolarResidual(F, p);
      Eigen::Vector4d grad;
      for (int k = 0; k < 4; ++k) {
        Eigen::Vector4d h = Eigen::Vector4d::Zero();
        h(k) = 1e-3;
        grad(k) = (EpipolarResidual(F, p + h) - EpipolarResidual(F, p - h)) / 2e-3;  // exact: c is bilinear
      }
      const double direct = c * c / grad.squaredNorm();
      const double sampson = SampsonErrorSquared(F, p.head<2>(), p.tail<2>());
      worst_formula = std::max(worst_formula, std::abs(sampson - direct) / direct);
      // The first-order correction delta = -c grad / |grad|^2 has |delta|^2 = Sampson error and
      // satisfies the constraint up to second order.
      const Eigen::Vector4d delta = -c * grad / grad.squaredNorm();
      EXPECT_NEAR(delta.squaredNorm(), sampson, 1e-9 * sampson);
      worst_linearised = std::max(worst_linearised, std::abs(EpipolarResidual(F, p + delta)) / std::abs(c));
    }
  }
  std::printf("[Sampson] worst error on exact data %.2e px; worst rel. difference to the direct evaluation %.2e; "
              "worst |c(p + delta)| / |c(p)| %.2e\n",
              worst_exact, worst_formula, worst_linearised);
  EXPECT_LT(worst_exact, 1e-8);
  EXPECT_LT(worst_formula, 1e-6);
  EXPECT_LT(worst_linearised, 1e-2);
}

TEST(EssentialMatrix, BougnouxRecoversTwoFocals) {
  std::mt19937 rng(7);
  SolverInstanceOptions opt;
  opt.setup = CameraSetup::kTwoFocal;
  opt.num_points = 1;
  const int kTrials = 1000;
  int exact = 0, failed = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    const SolverInstance inst = MakeSolverInstance(rng, opt);
    ASSERT_NE(inst.gt.f0, inst.gt.f1);
    const double s = trial % 2 ? -1.0 : 1e-3;  // F's scale and sign are irrelevant
    const Eigen::Matrix3d F = s * FundamentalFromEssential(EssentialFromPose(inst.gt.R, inst.gt.t),
                                                           FocalMatrix(inst.gt.f0), FocalMatrix(inst.gt.f1));
    double f0 = 0.0, f1 = 0.0;
    if (!BougnouxFocals(F, &f0, &f1)) {
      ++failed;
      continue;
    }
    EXPECT_TRUE(std::isfinite(f0) && std::isfinite(f1) && f0 > 0.0 && f1 > 0.0);
    if (std::abs(f0 / inst.gt.f0 - 1.0) < 1e-6 && std::abs(f1 / inst.gt.f1 - 1.0) < 1e-6) ++exact;
  }
  std::printf("[Bougnoux] both focals to 1e-6 (relative) in %d / %d random poses (%.1f%%), %d rejected\n", exact,
              kTrials, 100.0 * exact / kTrials, failed);
  EXPECT_GE(exact, 990);
}

TEST(EssentialMatrix, BougnouxRecoversTwoFocalsForArbitraryPoses) {
  // Fully random rotations and translation directions (not only realistic viewing geometry).
  std::mt19937 rng(8);
  std::normal_distribution<double> g(0.0, 1.0);
  const int kTrials = 1000;
  int exact = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    const double gt_f0 = 200.0 * std::exp(2.7 * std::abs(g(rng)) / 2.0), gt_f1 = 200.0 + 2800.0 * std::abs(g(rng)) / 3;
    const Eigen::Matrix3d F = FundamentalFromEssential(
        EssentialFromPose(RandomRotation(rng), Eigen::Vector3d(g(rng), g(rng), g(rng))), FocalMatrix(gt_f0),
        FocalMatrix(gt_f1));
    double f0, f1;
    if (BougnouxFocals(F, &f0, &f1) && std::abs(f0 / gt_f0 - 1.0) < 1e-6 && std::abs(f1 / gt_f1 - 1.0) < 1e-6) ++exact;
  }
  std::printf("[Bougnoux] arbitrary poses: both focals to 1e-6 (relative) in %d / %d (%.1f%%)\n", exact, kTrials,
              100.0 * exact / kTrials);
  EXPECT_GE(exact, 990);
}

TEST(EssentialMatrix, BougnouxRejectsDegenerateInput) {
  double f0 = -1.0, f1 = -1.0;
  // Pure sideways translation with parallel optical axes: the axes are coplanar, 0 / 0.
  const Eigen::Matrix3d F = FundamentalFromEssential(
      EssentialFromPose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(1.0, 0.0, 0.0)), FocalMatrix(500.0),
      FocalMatrix(800.0));
  EXPECT_FALSE(BougnouxFocals(F, &f0, &f1));
  EXPECT_FALSE(BougnouxFocals(Eigen::Matrix3d::Zero(), &f0, &f1));
  EXPECT_FALSE(BougnouxFocals(Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN()), &f0, &f1));
  EXPECT_EQ(f0, -1.0);  // untouched on failure
  EXPECT_EQ(f1, -1.0);
}

}  // namespace
}  // namespace madsfm
