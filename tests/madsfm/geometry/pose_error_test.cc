#include "madsfm/geometry/pose_error.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace madsfm {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

Eigen::Matrix3d Rot(double deg, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(deg * M_PI / 180.0, axis.normalized()).toRotationMatrix();
}

TEST(PoseError, RotationErrorIsTheRelativeAngle) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Matrix3d R_gt = Rot(180.0 * u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng)));
    const double angle = 90.0 + 90.0 * u(rng);  // [0, 180]
    const Eigen::Matrix3d R_est = Rot(angle, Eigen::Vector3d(u(rng), u(rng), u(rng))) * R_gt;
    EXPECT_NEAR(RotationErrorDeg(R_est, R_gt), angle, 1e-9);
    EXPECT_NEAR(RotationErrorDeg(R_gt, R_est), angle, 1e-9);
  }
  const Eigen::Matrix3d R = Rot(37.0, Eigen::Vector3d(1, 2, 3));
  EXPECT_NEAR(RotationErrorDeg(R, R), 0.0, 1e-12);
  // Small angles stay accurate (no acos precision loss near 0) and 180 deg is reached.
  EXPECT_NEAR(RotationErrorDeg(Rot(1e-6, Eigen::Vector3d(0, 0, 1)) * R, R), 1e-6, 1e-12);
  EXPECT_NEAR(RotationErrorDeg(Rot(180.0, Eigen::Vector3d(1, -1, 0)) * R, R), 180.0, 1e-9);
  EXPECT_NEAR(RotationErrorDeg(Rot(30.0, Eigen::Vector3d(0, 1, 0)), Eigen::Matrix3d::Identity()), 30.0, 1e-12);
  EXPECT_EQ(RotationErrorDeg(Eigen::Matrix3d::Constant(kNaN), R), 180.0);
}

TEST(PoseError, TranslationErrorIgnoresSignAndScale) {
  const Eigen::Vector3d t(1.0, 0.0, 0.0);
  EXPECT_NEAR(TranslationErrorDeg(t, t), 0.0, 1e-12);
  EXPECT_NEAR(TranslationErrorDeg(3.0 * t, t), 0.0, 1e-12);
  EXPECT_NEAR(TranslationErrorDeg(-t, t), 0.0, 1e-12);  // min(180, 0)
  EXPECT_NEAR(TranslationErrorDeg(Eigen::Vector3d(0.0, 2.0, 0.0), t), 90.0, 1e-12);
  const Eigen::Vector3d t30(std::cos(M_PI / 6), std::sin(M_PI / 6), 0.0);
  EXPECT_NEAR(TranslationErrorDeg(t30, t), 30.0, 1e-12);
  EXPECT_NEAR(TranslationErrorDeg(-t30, t), 30.0, 1e-12);  // 150 -> 30
  EXPECT_NEAR(TranslationErrorDeg(Eigen::Vector3d(1.0, 1e-8, 0.0), t), 1e-8 * 180.0 / M_PI, 1e-15);
  EXPECT_EQ(TranslationErrorDeg(Eigen::Vector3d::Zero(), t), 180.0);
  EXPECT_EQ(TranslationErrorDeg(t, Eigen::Vector3d::Zero()), 180.0);
  EXPECT_EQ(TranslationErrorDeg(Eigen::Vector3d(kNaN, 0.0, 0.0), t), 180.0);
  EXPECT_EQ(TranslationErrorDeg(t, Eigen::Vector3d(0.0, kInf, 0.0)), 180.0);
}

TEST(PoseError, AucMatchesHandComputedValues) {
  // errors {7, 1, 3}: the recall curve through (0, 0), (1, 1/3), (3, 2/3), (7, 1), flat afterwards.
  //  t = 2:  [1/6 + 1 * 1/3] / 2                                   = 0.25
  //  t = 5:  [1/6 + 2 * (1/3 + 2/3) / 2 + 2 * 2/3] / 5 = 2.5 / 5     = 0.5
  //  t = 10: [1/6 + 1 + 4 * (2/3 + 1) / 2 + 3 * 1] / 10 = 7.5 / 10   = 0.75
  const std::vector<double> auc = PoseAuc({7.0, 1.0, 3.0}, {2.0, 5.0, 10.0});
  ASSERT_EQ(auc.size(), 3u);
  EXPECT_NEAR(auc[0], 0.25, 1e-15);
  EXPECT_NEAR(auc[1], 0.5, 1e-15);
  EXPECT_NEAR(auc[2], 0.75, 1e-15);

  // All perfect: 1; all failed: 0.
  EXPECT_NEAR(PoseAuc({0.0, 0.0}, {5.0})[0], 1.0, 1e-15);
  EXPECT_EQ(PoseAuc({180.0, 90.0}, {5.0, 10.0, 20.0}), std::vector<double>({0.0, 0.0, 0.0}));
  // One error at 2 of two samples, threshold 4: [2 * 0.5 / 2 + 2 * 0.5] / 4 = 0.375.
  EXPECT_NEAR(PoseAuc({2.0, 180.0}, {4.0})[0], 0.375, 1e-15);
  // An error equal to the threshold does not count (SuperGlue's searchsorted, left side).
  EXPECT_EQ(PoseAuc({5.0}, {5.0})[0], 0.0);
  // Non-finite errors count as failures: {2, NaN, inf} at 4 -> [2 * (1/3) / 2 + 2 * 1/3] / 4 = 0.25.
  EXPECT_NEAR(PoseAuc({2.0, kNaN, kInf}, {4.0})[0], 0.25, 1e-15);
  // Empty input and a non-positive threshold give 0.
  EXPECT_EQ(PoseAuc({}, {5.0, 10.0}), std::vector<double>({0.0, 0.0}));
  EXPECT_EQ(PoseAuc({1.0}, {0.0})[0], 0.0);
  EXPECT_TRUE(PoseAuc({1.0}, {}).empty());
}

}  // namespace
}  // namespace madsfm
