#include "madsfm/geometry/triangulation.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "testing/solver_instances.h"

namespace madsfm {
namespace {

TEST(Triangulation, ExactDepthsOnNoiseFreeData) {
  std::mt19937 rng(1);
  testing::SolverInstanceOptions opt;
  opt.num_points = 10;
  opt.with_shift = false;
  for (int trial = 0; trial < 200; ++trial) {
    const testing::SolverInstance inst = testing::MakeSolverInstance(rng, opt);
    for (int i = 0; i < opt.num_points; ++i) {
      double z0, z1;
      ASSERT_TRUE(TriangulateDepths(inst.gt.R, inst.gt.t, inst.x0[i], inst.x1[i], &z0, &z1));
      const double true_z0 = inst.gt.Depth0(inst.d0[i]), true_z1 = inst.gt.Depth1(inst.d1[i]);
      EXPECT_NEAR(z0, true_z0, 1e-9 * true_z0);
      EXPECT_NEAR(z1, true_z1, 1e-9 * true_z1);
      // Depths scale with the translation.
      double w0, w1;
      ASSERT_TRUE(TriangulateDepths(inst.gt.R, 0.25 * inst.gt.t, inst.x0[i], inst.x1[i], &w0, &w1));
      EXPECT_NEAR(w0, 0.25 * true_z0, 1e-9 * true_z0);
      EXPECT_NEAR(w1, 0.25 * true_z1, 1e-9 * true_z1);
    }
  }
}

TEST(Triangulation, AccurateAtSmallParallax) {
  // Forward motion; points close to the epipole see the baseline under ~1e-4 rad. The depths must
  // keep close to full precision (no cancellation in the 2x2 normal equations).
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.2, Eigen::Vector3d(0.3, 1.0, 0.1).normalized()).toRotationMatrix();
  const Eigen::Vector3d c1(0.01, -0.02, 1.0);  // camera 1 centre in camera 0
  const Eigen::Vector3d t = -R * c1;
  double worst = 0.0, min_parallax = 1.0;
  for (int i = 1; i <= 100; ++i) {
    const Eigen::Vector3d X = c1 * (3.0 + 0.05 * i) + Eigen::Vector3d(1e-4 * i, -2e-4, 0.0);
    const Eigen::Vector3d X1 = R * X + t;
    min_parallax = std::min(min_parallax, X.normalized().cross((X - c1).normalized()).norm());
    double z0, z1;
    ASSERT_TRUE(TriangulateDepths(R, t, X.hnormalized(), X1.hnormalized(), &z0, &z1));
    worst = std::max({worst, std::abs(z0 / X.z() - 1.0), std::abs(z1 / X1.z() - 1.0)});
  }
  EXPECT_LT(min_parallax, 1e-4);
  EXPECT_LT(worst, 1e-9);
}

TEST(Triangulation, MidPointOfSkewRays) {
  // Camera 1's centre is at x = 1 in camera 0. The view-0 ray through (0, 0) is (0, 0, s); the
  // view-1 ray through (-1, 0.1) is u (-1, 0.1, 1) in camera 1, i.e. (1 - u, 0.1 u, u) in camera 0.
  // The rays are skew; minimising (1 - u)^2 + 0.01 u^2 + (s - u)^2 gives s = u = 1 / 1.01.
  const Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  const Eigen::Vector3d t(-1.0, 0.0, 0.0);
  double z0, z1;
  ASSERT_TRUE(TriangulateDepths(R, t, Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(-1.0, 0.1), &z0, &z1));
  EXPECT_NEAR(z0, 1.0 / 1.01, 1e-12);
  EXPECT_NEAR(z1, 1.0 / 1.01, 1e-12);
}

TEST(Triangulation, ReportsPointsBehindTheCameras) {
  const Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  const Eigen::Vector3d t(-1.0, 0.0, 0.0);
  const Eigen::Vector3d X(0.2, 0.1, -4.0);  // behind both cameras
  double z0, z1;
  ASSERT_TRUE(TriangulateDepths(R, t, X.hnormalized(), (R * X + t).hnormalized(), &z0, &z1));
  EXPECT_NEAR(z0, -4.0, 1e-12);
  EXPECT_NEAR(z1, -4.0, 1e-12);
}

TEST(Triangulation, RejectsParallelRaysAndNonFiniteInput) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.0, 1.0, 0.0)).toRotationMatrix();
  const Eigen::Vector3d t(0.5, 0.0, 0.1);
  const Eigen::Vector2d x0(0.1, -0.2);
  const Eigen::Vector2d x1_parallel = (R * x0.homogeneous()).hnormalized();  // point at infinity
  double z0 = 7.0, z1 = 7.0;
  EXPECT_FALSE(TriangulateDepths(R, t, x0, x1_parallel, &z0, &z1));
  EXPECT_FALSE(TriangulateDepths(R, t, x0, x1_parallel + Eigen::Vector2d(1e-10, 0.0), &z0, &z1));
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(TriangulateDepths(R, t, Eigen::Vector2d(nan, 0.0), x1_parallel, &z0, &z1));
  EXPECT_FALSE(TriangulateDepths(R, t, x0, Eigen::Vector2d(0.0, inf), &z0, &z1));
  EXPECT_FALSE(TriangulateDepths(R, Eigen::Vector3d(nan, 0.0, 0.0), x0, Eigen::Vector2d(0.3, 0.0), &z0, &z1));
  EXPECT_EQ(z0, 7.0);  // untouched
  EXPECT_EQ(z1, 7.0);
  // A clearly non-parallel pair still works.
  EXPECT_TRUE(TriangulateDepths(R, t, x0, x1_parallel + Eigen::Vector2d(1e-2, 0.0), &z0, &z1));
}

}  // namespace
}  // namespace madsfm
