// BundleFocalUncertainty: the focal length's standard deviation in bundle adjustment, checked against a brute-force
// covariance with an explicit gauge, and its behaviour: forward motion leaves the focal length far less determined
// than an orbit, and the deviation follows the reprojection noise.
#include "colmap_ext/model/focal_uncertainty.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

namespace madsfm::colmap {
namespace {

constexpr uint32_t kCamera = 1;

Eigen::Matrix3d LookAt(const Eigen::Vector3d& center, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - center).normalized();
  const Eigen::Vector3d x = Eigen::Vector3d::UnitY().cross(z).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R;  // world -> camera
  R.row(0) = x;
  R.row(1) = y;
  R.row(2) = z;
  return R;
}

// num_images cameras looking at a box of points around the origin: on an arc of +-20 deg at distance 5 (orbit), or
// on a straight walk towards it (forward, 0.25 per image, aim jittered by 0.5 deg). SIMPLE_RADIAL 500 px, k 0.02.
Reconstruction MakeScene(bool forward, double noise_px, uint32_t seed, int num_images = 6, int num_points = 150) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> box(-1.5, 1.5), jitter(-0.5, 0.5);
  std::normal_distribution<double> noise(0.0, noise_px);
  Reconstruction model;
  ModelCamera cam;
  cam.camera_id = kCamera;
  cam.intrinsics.model_id = CameraModelId("SIMPLE_RADIAL");
  cam.intrinsics.width = 640;
  cam.intrinsics.height = 480;
  cam.intrinsics.params = {500.0, 320.0, 240.0, 0.02};
  model.cameras[kCamera] = cam;
  for (int i = 0; i < num_images; ++i) {
    Eigen::Vector3d c;
    Eigen::Matrix3d R;
    if (forward) {
      c = Eigen::Vector3d(0.0, 0.0, -6.0 + 0.25 * i);
      const double deg = M_PI / 180.0;
      R = (Eigen::AngleAxisd(jitter(rng) * deg, Eigen::Vector3d::UnitX()) *
           Eigen::AngleAxisd(jitter(rng) * deg, Eigen::Vector3d::UnitY()))
              .toRotationMatrix() *
          LookAt(c, c + Eigen::Vector3d::UnitZ());
    } else {
      const double a = (-20.0 + 40.0 * i / (num_images - 1)) * M_PI / 180.0;
      c = 5.0 * Eigen::Vector3d(std::sin(a), 0.3, -std::cos(a));
      R = LookAt(c, Eigen::Vector3d::Zero());
    }
    ModelImage image;
    image.image_id = static_cast<uint32_t>(i + 1);
    image.camera_id = kCamera;
    image.name = "img" + std::to_string(i);
    image.qvec = RotationToQuaternion(R);
    image.tvec = -R * c;
    model.images[image.image_id] = image;
  }
  for (int j = 0; j < num_points; ++j) {
    ModelPoint3D point;
    point.xyz = Eigen::Vector3d(box(rng), box(rng), box(rng));
    for (auto& [id, image] : model.images) {
      const Eigen::Vector3d Xc = QuaternionToRotation(image.qvec) * point.xyz + image.tvec;
      if (Xc.z() <= 0.1) continue;
      const Eigen::Vector2d p = CameraToImage(cam.intrinsics, Xc.head<2>() / Xc.z());
      if (p.x() < 0 || p.y() < 0 || p.x() > 640 || p.y() > 480) continue;
      point.track.emplace_back(id, static_cast<uint32_t>(image.points2D.size()));
      image.points2D.push_back(p + Eigen::Vector2d(noise(rng), noise(rng)));
      image.point3D_ids.push_back(static_cast<uint64_t>(j + 1));
    }
    if (point.track.size() >= 2) model.points3D[static_cast<uint64_t>(j + 1)] = point;
  }
  return model;
}

// Residuals of every observation of points seen at least twice, for parameters
// [points (3 each) | per image: rotation increment (3), translation (3) | f, k].
Eigen::VectorXd Residuals(const Reconstruction& model, const Eigen::VectorXd& delta) {
  std::vector<double> r;
  int pi = 0;
  const int num_points = static_cast<int>(model.points3D.size());
  CameraIntrinsics k = model.cameras.at(kCamera).intrinsics;
  const int cam = 3 * num_points + 6 * static_cast<int>(model.images.size());
  k.params[0] += delta(cam);
  k.params[3] += delta(cam + 1);
  for (const auto& [pid, point] : model.points3D) {
    const Eigen::Vector3d X = point.xyz + delta.segment<3>(3 * pi);
    for (const auto& [image_id, idx] : point.track) {
      const ModelImage& image = model.images.at(image_id);
      const int ii = static_cast<int>(std::distance(model.images.begin(), model.images.find(image_id)));
      const Eigen::Vector3d w = delta.segment<3>(3 * num_points + 6 * ii);
      const Eigen::Matrix3d dR =
          w.norm() > 0 ? Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() : Eigen::Matrix3d::Identity();
      const Eigen::Vector3d Xc = dR * QuaternionToRotation(image.qvec) * X + image.tvec +
                                 delta.segment<3>(3 * num_points + 6 * ii + 3);
      const Eigen::Vector2d e = CameraToImage(k, Xc.head<2>() / Xc.z()) - image.points2D[idx];
      r.push_back(e.x());
      r.push_back(e.y());
    }
    ++pi;
  }
  return Eigen::Map<Eigen::VectorXd>(r.data(), static_cast<int>(r.size()));
}

// The focal length's standard deviation from the full Jacobian (central differences) with the gauge fixed
// explicitly: the first image's pose and the x translation of the last image held.
double BruteForceSigma(const Reconstruction& model) {
  const int num_points = static_cast<int>(model.points3D.size());
  const int num_images = static_cast<int>(model.images.size());
  const int n = 3 * num_points + 6 * num_images + 2;
  const Eigen::VectorXd r0 = Residuals(model, Eigen::VectorXd::Zero(n));
  Eigen::MatrixXd J(r0.size(), n);
  for (int j = 0; j < n; ++j) {
    Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
    const double h = j == n - 2 ? 1e-4 : 1e-7;
    d(j) = h;
    const Eigen::VectorXd a = Residuals(model, d);
    d(j) = -h;
    J.col(j) = (a - Residuals(model, d)) / (2 * h);
  }
  std::vector<int> keep;
  for (int j = 0; j < n; ++j) {
    const bool first_pose = j >= 3 * num_points && j < 3 * num_points + 6;
    const bool last_tx = j == 3 * num_points + 6 * (num_images - 1) + 3;
    if (!first_pose && !last_tx) keep.push_back(j);
  }
  Eigen::MatrixXd Jg(J.rows(), static_cast<int>(keep.size()));
  for (size_t c = 0; c < keep.size(); ++c) Jg.col(static_cast<int>(c)) = J.col(keep[c]);
  const Eigen::MatrixXd C = (Jg.transpose() * Jg).ldlt().solve(Eigen::MatrixXd::Identity(Jg.cols(), Jg.cols()));
  const double var = r0.squaredNorm() / (r0.size() - Jg.cols());
  return std::sqrt(var * C(Jg.cols() - 2, Jg.cols() - 2));
}

TEST(BundleFocalUncertainty, MatchesTheBruteForceCovariance) {
  for (bool forward : {false, true}) {
    const Reconstruction model = MakeScene(forward, 0.5, 3, 4, 40);
    const auto u = BundleFocalUncertainty(model, kCamera);
    ASSERT_TRUE(u.has_value());
    const double brute = BruteForceSigma(model);
    EXPECT_NEAR(u->sigma, brute, 1e-3 * brute) << (forward ? "forward" : "orbit");
    EXPECT_DOUBLE_EQ(u->focal, 500.0);
  }
}

TEST(BundleFocalUncertainty, ForwardMotionLeavesTheFocalLengthOpen) {
  const auto orbit = BundleFocalUncertainty(MakeScene(false, 0.5, 7), kCamera);
  const auto forward = BundleFocalUncertainty(MakeScene(true, 0.5, 7), kCamera);
  ASSERT_TRUE(orbit && forward);
  std::printf("focal sigma: orbit %.3f%%, forward %.3f%%\n", 100 * orbit->Relative(), 100 * forward->Relative());
  EXPECT_GT(forward->Relative(), 5.0 * orbit->Relative());
}

TEST(BundleFocalUncertainty, FollowsTheReprojectionNoise) {
  const auto low = BundleFocalUncertainty(MakeScene(false, 0.25, 11), kCamera);
  const auto high = BundleFocalUncertainty(MakeScene(false, 1.0, 11), kCamera);
  ASSERT_TRUE(low && high);
  EXPECT_NEAR(low->residual_sigma, 0.25, 0.05);
  EXPECT_NEAR(high->residual_sigma, 1.0, 0.2);
  EXPECT_NEAR(high->sigma / low->sigma, 4.0, 1.0);
}

TEST(BundleFocalUncertainty, NothingToSayWithoutTwoImagesOrTheCamera) {
  Reconstruction model = MakeScene(false, 0.5, 1);
  EXPECT_FALSE(BundleFocalUncertainty(model, 99).has_value());
  EXPECT_FALSE(BundleFocalUncertainty(model, kCamera, 3).has_value());  // more images than max_images
  while (model.images.size() > 1) model.images.erase(std::prev(model.images.end()));
  EXPECT_FALSE(BundleFocalUncertainty(model, kCamera).has_value());
}

}  // namespace
}  // namespace madsfm::colmap
