#include "madsfm/geometry/rigid_alignment.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>
#include <vector>

namespace madsfm {
namespace {

TEST(RigidAlignment, RecoversRandomSimilarities) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Matrix3d R = Eigen::AngleAxisd(3 * u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized())
                                  .toRotationMatrix();
    const Eigen::Vector3d t(u(rng), u(rng), u(rng));
    const double s = std::exp(2 * u(rng));
    const int n = 3 + trial % 5;
    std::vector<Eigen::Vector3d> p, q;
    for (int i = 0; i < n; ++i) {
      p.emplace_back(u(rng), u(rng), 2 + u(rng));
      q.push_back(s * R * p.back() + t);
    }
    Eigen::Matrix3d Re;
    Eigen::Vector3d te;
    double se;
    ASSERT_TRUE(AlignSimilarity(p.data(), q.data(), n, &se, &Re, &te));
    EXPECT_LT((Re - R).norm(), 1e-9);
    EXPECT_LT((te - t).norm(), 1e-9);
    EXPECT_NEAR(se, s, 1e-9 * s);
    for (auto& qi : q) qi = R * (qi - t) / s + t;  // now q = R p + t
    for (int i = 0; i < n; ++i) q[i] = R * p[i] + t;
    ASSERT_TRUE(AlignRigid(p.data(), q.data(), n, &Re, &te));
    EXPECT_LT((Re - R).norm(), 1e-9);
    EXPECT_LT((te - t).norm(), 1e-9);
  }
}

TEST(RigidAlignment, RejectsDegenerateInput) {
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  const std::vector<Eigen::Vector3d> collinear = {{0, 0, 1}, {0, 0, 2}, {0, 0, 3}};
  EXPECT_FALSE(AlignRigid(collinear.data(), collinear.data(), 3, &R, &t));
  const std::vector<Eigen::Vector3d> same = {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}};
  EXPECT_FALSE(AlignRigid(same.data(), same.data(), 3, &R, &t));
  std::vector<Eigen::Vector3d> nan = {{0, 0, 1}, {1, 0, 2}, {0, NAN, 3}};
  EXPECT_FALSE(AlignRigid(nan.data(), nan.data(), 3, &R, &t));
  EXPECT_FALSE(AlignRigid(nan.data(), nan.data(), 2, &R, &t));
}

}  // namespace
}  // namespace madsfm
