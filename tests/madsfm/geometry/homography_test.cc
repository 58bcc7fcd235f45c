#include "madsfm/geometry/homography.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace madsfm {
namespace {

struct PlaneScene {
  Eigen::Matrix3d R;
  Eigen::Vector3d t, n;
  double d = 1.0;
  std::vector<Eigen::Vector2d> x0, x1;
  std::vector<int> all;
};

// Points on a random plane 2-8 units in front of camera 0, seen by a camera moved by up to 30 deg and 1-3 units.
PlaneScene MakePlaneScene(std::mt19937& rng, int num_points) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  PlaneScene s;
  s.R = Eigen::AngleAxisd(0.5 * u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized()).toRotationMatrix();
  const Eigen::Vector3d c1 = Eigen::Vector3d(u(rng), u(rng), 0.3 * u(rng)).normalized() * (2.0 + u(rng));
  s.t = -s.R * c1;
  s.n = Eigen::Vector3d(0.5 * u(rng), 0.5 * u(rng), 1.0).normalized();
  s.d = 5.0 + 3.0 * u(rng);
  for (int i = 0; s.x0.size() < static_cast<size_t>(num_points) && i < 100 * num_points; ++i) {
    const Eigen::Vector3d ray(0.6 * u(rng), 0.45 * u(rng), 1.0);
    const Eigen::Vector3d X = ray * (s.d / s.n.dot(ray));
    const Eigen::Vector3d X1 = s.R * X + s.t;
    if (X.z() <= 0.0 || X1.z() <= 0.0) continue;
    s.all.push_back(static_cast<int>(s.x0.size()));
    s.x0.push_back(X.hnormalized());
    s.x1.push_back(X1.hnormalized());
  }
  return s;
}

double AngleDeg(const Eigen::Matrix3d& A, const Eigen::Matrix3d& B) {
  return Eigen::AngleAxisd(A.transpose() * B).angle() * 180.0 / M_PI;
}

TEST(Homography, LinearFitIsExactOnNoiseFreePlanes) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 100; ++trial) {
    const PlaneScene s = MakePlaneScene(rng, 50);
    Eigen::Matrix3d H;
    ASSERT_TRUE(FitHomographyLinear(s.x0, s.x1, s.all, &H));
    double worst = 0.0;
    for (int i : s.all) worst = std::max(worst, HomographyTransferError(H, s.x0[i], s.x1[i]));
    EXPECT_LT(worst, 1e-9);
  }
  Eigen::Matrix3d H;
  const PlaneScene s = MakePlaneScene(rng, 3);
  EXPECT_FALSE(FitHomographyLinear(s.x0, s.x1, s.all, &H));  // fewer than 4
}

TEST(Homography, DecompositionRecoversThePoseAndItsTwin) {
  std::mt19937 rng(5);
  int twins = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const PlaneScene s = MakePlaneScene(rng, 30);
    const Eigen::Matrix3d H = s.R + (s.t / s.d) * s.n.transpose();
    // Any scale and sign of H.
    const std::vector<PlanarPose> poses = DecomposeHomography(-3.7 * H, s.x0, s.x1, s.all);
    ASSERT_FALSE(poses.empty());
    ASSERT_LE(poses.size(), 2u);
    int match = -1;
    for (size_t k = 0; k < poses.size(); ++k) {
      if (AngleDeg(poses[k].R, s.R) < 1e-6 && (poses[k].t - s.t / s.d).norm() < 1e-8 * (1.0 + s.t.norm() / s.d) &&
          (poses[k].n - s.n).norm() < 1e-8) {
        match = static_cast<int>(k);
      }
    }
    ASSERT_GE(match, 0) << "trial " << trial;
    if (poses.size() == 2) {
      // The twin reproduces the same homography (up to scale) and is another pose.
      const PlanarPose& w = poses[1 - match];
      const Eigen::Matrix3d Hw = w.R + w.t * w.n.transpose();
      EXPECT_LT((Hw / Hw.norm() - H / H.norm()).norm(), 1e-9);
      EXPECT_NEAR(w.R.determinant(), 1.0, 1e-9);
      EXPECT_GT(AngleDeg(w.R, s.R) + std::acos(std::clamp(w.t.normalized().dot(s.t.normalized()), -1.0, 1.0)), 1e-3);
      ++twins;
    }
  }
  EXPECT_GE(twins, 150);  // a plane in front of both cameras usually has a physical twin
}

TEST(Homography, PureRotationHasNoTranslation) {
  std::mt19937 rng(7);
  PlaneScene s = MakePlaneScene(rng, 20);
  for (size_t i = 0; i < s.x0.size(); ++i) s.x1[i] = (s.R * s.x0[i].homogeneous()).hnormalized();
  const std::vector<PlanarPose> poses = DecomposeHomography(2.0 * s.R, s.x0, s.x1, s.all);
  ASSERT_EQ(poses.size(), 1u);
  EXPECT_LT(AngleDeg(poses[0].R, s.R), 1e-6);
  EXPECT_EQ(poses[0].t.norm(), 0.0);
}

}  // namespace
}  // namespace madsfm
