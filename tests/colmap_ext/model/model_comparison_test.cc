// Tests of the model-vs-ground-truth comparison (colmap_ext/model/model_comparison.h) and of the
// `madsfm model_compare` command on synthetic models built from a known ground truth.
#include "colmap_ext/model/model_comparison.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "colmap_ext/exe/model_compare_command.h"
#include "testing/temp_dir.h"

namespace madsfm::colmap {
namespace {

namespace fs = std::filesystem;

// A scratch folder per test, removed afterwards.
class TempDir : public testing::TempDir {
 public:
  TempDir() : testing::TempDir("model_comparison_test") {}
};

void WriteText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::trunc);
  out << text;
}

Eigen::Matrix3d RandomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
  q.normalize();
  return q.toRotationMatrix();
}

// Cameras on a noisy ring around the origin, looking roughly at it, with focal lengths 700..1100 px.
GroundTruth MakeGroundTruth(int num_images, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  GroundTruth gt;
  for (int i = 0; i < num_images; ++i) {
    const double angle = 2.0 * M_PI * i / num_images;
    const Eigen::Vector3d c(5.0 * std::cos(angle) + 0.3 * uni(rng), 0.5 * uni(rng), 5.0 * std::sin(angle));
    const Eigen::Vector3d z = (-c).normalized();
    const Eigen::Vector3d x = Eigen::Vector3d::UnitY().cross(z).normalized();
    Eigen::Matrix3d R;
    R.row(0) = x.transpose();
    R.row(1) = z.cross(x).transpose();
    R.row(2) = z.transpose();
    R = Eigen::AngleAxisd(0.05 * uni(rng), Eigen::Vector3d(uni(rng), uni(rng), uni(rng)).normalized()) * R;
    GroundTruthImage image;
    char name[32];
    std::snprintf(name, sizeof(name), "img_%03d.png", i);
    image.name = name;
    image.R = R;
    image.t = -R * c;
    image.focal = 900.0 + 200.0 * uni(rng);
    gt.images.push_back(image);
  }
  return gt;
}

// A model holding the ground-truth images, moved by the similarity x' = s Q x + d (image ids 1.., one camera per
// image: SIMPLE_PINHOLE for even, PINHOLE with fx = fy for odd images) and `num_points` points with errors
// 0.1, 0.2, ...
Reconstruction ModelFromGroundTruth(const GroundTruth& gt, double s = 1.0,
                                    const Eigen::Matrix3d& Q = Eigen::Matrix3d::Identity(),
                                    const Eigen::Vector3d& d = Eigen::Vector3d::Zero(), int num_points = 4) {
  Reconstruction model;
  uint32_t id = 1;
  for (const GroundTruthImage& g : gt.images) {
    ModelCamera camera;
    camera.camera_id = id;
    camera.intrinsics.width = 1024;
    camera.intrinsics.height = 768;
    if (id % 2 == 0) {
      camera.intrinsics.model_id = CameraModelId("SIMPLE_PINHOLE");
      camera.intrinsics.params = {g.focal, 512, 384};
    } else {
      camera.intrinsics.model_id = CameraModelId("PINHOLE");
      camera.intrinsics.params = {g.focal, g.focal, 512, 384};
    }
    model.cameras[id] = camera;
    const Eigen::Vector3d c = -g.R.transpose() * g.t;
    const Eigen::Matrix3d R = g.R * Q.transpose();
    const Eigen::Vector3d c_new = s * Q * c + d;
    ModelImage image;
    image.image_id = id;
    image.camera_id = id;
    image.name = g.name;
    image.qvec = RotationToQuaternion(R);
    image.tvec = -R * c_new;
    model.images[id] = image;
    ++id;
  }
  for (int p = 0; p < num_points; ++p) {
    ModelPoint3D point;
    point.error = 0.1 * (p + 1);
    model.points3D[static_cast<uint64_t>(p + 1)] = point;
  }
  return model;
}

ModelImage& ImageNamed(Reconstruction& model, const std::string& name) {
  for (auto& [id, image] : model.images) {
    if (image.name == name) return image;
  }
  throw std::runtime_error("no image " + name);
}

// Rotates image `name` by `angle_deg` about `axis` (in its camera frame) keeping its camera centre.
void PerturbRotation(Reconstruction& model, const std::string& name, double angle_deg, const Eigen::Vector3d& axis) {
  ModelImage& image = ImageNamed(model, name);
  const Eigen::Matrix3d R = QuaternionToRotation(image.qvec);
  const Eigen::Vector3d c = -R.transpose() * image.tvec;
  const Eigen::Matrix3d R_new = Eigen::AngleAxisd(angle_deg * M_PI / 180.0, axis.normalized()).toRotationMatrix() * R;
  image.qvec = RotationToQuaternion(R_new);
  image.tvec = -R_new * c;
}

TEST(ModelComparisonTest, GroundTruthItselfGivesZeroErrors) {
  const GroundTruth gt = MakeGroundTruth(6, 1);
  const ModelComparison c = CompareToGroundTruth(ModelFromGroundTruth(gt), gt);
  std::printf("ground truth vs itself: max rot %.2e deg, max trans %.2e deg, max focal %.2e\n", c.max_rot_err_deg,
              c.max_trans_err_deg, c.max_focal_err);
  EXPECT_EQ(c.num_gt_images, 6);
  EXPECT_EQ(c.num_model_images, 6);
  EXPECT_EQ(c.num_registered, 6);
  EXPECT_EQ(c.num_model_images_not_in_gt, 0);
  EXPECT_TRUE(c.unregistered_names.empty());
  EXPECT_EQ(c.num_pairs, 15);
  EXPECT_EQ(c.num_trans_pairs, 15);
  EXPECT_EQ(c.pair_errors.size(), 15u);
  EXPECT_LT(c.max_rot_err_deg, 1e-9);
  EXPECT_LT(c.max_trans_err_deg, 1e-9);
  EXPECT_LT(c.median_rot_err_deg, 1e-9);
  EXPECT_LT(c.median_trans_err_deg, 1e-9);
  EXPECT_EQ(c.num_focal, 6);
  EXPECT_EQ(c.max_focal_err, 0.0);  // the model holds the very same focal doubles
  EXPECT_EQ(c.median_focal_err, 0.0);
  EXPECT_EQ(c.num_points3D, 4);
  EXPECT_NEAR(c.mean_reproj_error, 0.25, 1e-15);
}

TEST(ModelComparisonTest, SimilarityTransformedModelGivesZeroErrors) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  const GroundTruth gt = MakeGroundTruth(8, 2);
  double worst_rot = 0.0, worst_trans = 0.0;
  const int kTrials = 50;
  for (int trial = 0; trial < kTrials; ++trial) {
    const double s = std::pow(10.0, 2.0 * uni(rng));  // 0.01 .. 100
    const Eigen::Matrix3d Q = RandomRotation(rng);
    const Eigen::Vector3d d = 100.0 * Eigen::Vector3d(uni(rng), uni(rng), uni(rng));
    const ModelComparison c = CompareToGroundTruth(ModelFromGroundTruth(gt, s, Q, d), gt);
    ASSERT_EQ(c.num_registered, 8);
    ASSERT_EQ(c.num_pairs, 28);
    ASSERT_EQ(c.num_trans_pairs, 28);
    EXPECT_EQ(c.max_focal_err, 0.0);
    worst_rot = std::max(worst_rot, c.max_rot_err_deg);
    worst_trans = std::max(worst_trans, c.max_trans_err_deg);
  }
  std::printf("%d similarity-transformed models (scale 0.01..100): worst rot %.2e deg, worst trans %.2e deg\n",
              kTrials, worst_rot, worst_trans);
  EXPECT_LT(worst_rot, 1e-7);
  EXPECT_LT(worst_trans, 1e-7);
}

TEST(ModelComparisonTest, OnePerturbedRotationGivesTheExpectedErrors) {
  const GroundTruth gt = MakeGroundTruth(6, 3);
  Reconstruction model = ModelFromGroundTruth(gt, 2.0, Eigen::Matrix3d::Identity(), Eigen::Vector3d(1, 2, 3));
  const std::string perturbed = gt.images[2].name;
  PerturbRotation(model, perturbed, 5.0, Eigen::Vector3d(0.3, -1.0, 0.5));
  const ModelComparison c = CompareToGroundTruth(model, gt);
  // The relative rotation of every pair with the perturbed image is off by exactly 5 degrees, all others are exact.
  int with_error = 0;
  for (const PairError& e : c.pair_errors) {
    const bool involves = e.name_i == perturbed || e.name_j == perturbed;
    if (involves) {
      EXPECT_NEAR(e.rot_err_deg, 5.0, 1e-9) << e.name_i << " " << e.name_j;
      ++with_error;
    } else {
      EXPECT_LT(e.rot_err_deg, 1e-9) << e.name_i << " " << e.name_j;
      EXPECT_LT(e.trans_err_deg, 1e-9) << e.name_i << " " << e.name_j;
    }
  }
  EXPECT_EQ(with_error, 5);
  EXPECT_NEAR(c.max_rot_err_deg, 5.0, 1e-9);
  EXPECT_LT(c.median_rot_err_deg, 1e-9);  // 5 of 15 pairs
  // The baseline seen from the rotated camera turns by at most the rotation angle, in every pair with it.
  for (const PairError& e : c.pair_errors) {
    if (e.name_i == perturbed || e.name_j == perturbed) {
      EXPECT_LE(e.trans_err_deg, 5.0 + 1e-9) << e.name_i << " " << e.name_j;
      EXPECT_GT(e.trans_err_deg, 0.01) << e.name_i << " " << e.name_j;
    }
  }
  EXPECT_LT(c.median_trans_err_deg, 1e-9);
}

TEST(ModelComparisonTest, KnownTranslationDirectionError) {
  // Two cameras with identity rotation; the model's second centre is moved so the baseline turns 45 degrees.
  GroundTruth gt;
  gt.images.resize(2);
  gt.images[0].name = "a.png";
  gt.images[1].name = "b.png";
  gt.images[0].focal = gt.images[1].focal = 1000.0;
  gt.images[1].t = -Eigen::Vector3d(1, 0, 0);  // centres a (0, 0, 0), b (1, 0, 0): c_a - c_b = (-1, 0, 0)
  Reconstruction model = ModelFromGroundTruth(gt);
  ImageNamed(model, "a.png").tvec = -Eigen::Vector3d(1, 0, 0);  // centres a (1, 0, 0), b (3, 2, 0):
  ImageNamed(model, "b.png").tvec = -Eigen::Vector3d(3, 2, 0);  // c_a - c_b = (-2, -2, 0), 45 degrees off
  const ModelComparison c = CompareToGroundTruth(model, gt);
  ASSERT_EQ(c.num_pairs, 1);
  ASSERT_EQ(c.num_trans_pairs, 1);
  EXPECT_NEAR(c.median_trans_err_deg, 45.0, 1e-12);
  EXPECT_NEAR(c.max_trans_err_deg, 45.0, 1e-12);
  EXPECT_LT(c.max_rot_err_deg, 1e-12);
  // A reversed baseline is 180 degrees off (the sign is known in a reconstruction).
  ImageNamed(model, "a.png").tvec = -Eigen::Vector3d(5, 0, 0);
  ImageNamed(model, "b.png").tvec = -Eigen::Vector3d(2, 0, 0);
  EXPECT_NEAR(CompareToGroundTruth(model, gt).max_trans_err_deg, 180.0, 1e-12);
  // A zero ground-truth baseline is skipped.
  gt.images[1].t = gt.images[0].t;
  const ModelComparison z = CompareToGroundTruth(model, gt);
  EXPECT_EQ(z.num_pairs, 1);
  EXPECT_EQ(z.num_trans_pairs, 0);
  EXPECT_TRUE(std::isnan(z.median_trans_err_deg));
}

TEST(ModelComparisonTest, FocalErrorIsRelative) {
  const GroundTruth gt = MakeGroundTruth(5, 4);
  Reconstruction model = ModelFromGroundTruth(gt);
  // Image 2 (camera 2, SIMPLE_PINHOLE) 10% too long; image 3 (PINHOLE) fx 4% and fy 2% short: mean 3%.
  model.cameras.at(2).intrinsics.params[0] *= 1.1;
  model.cameras.at(3).intrinsics.params[0] *= 0.96;
  model.cameras.at(3).intrinsics.params[1] *= 0.98;
  const ModelComparison c = CompareToGroundTruth(model, gt);
  EXPECT_EQ(c.num_focal, 5);
  EXPECT_NEAR(c.max_focal_err, 0.1, 1e-12);
  EXPECT_EQ(c.median_focal_err, 0.0);  // 3 of 5 exact
  GroundTruth no_focal = gt;
  for (auto& image : no_focal.images) image.focal = std::nan("");
  no_focal.images[0].focal = gt.images[0].focal;
  const ModelComparison d = CompareToGroundTruth(model, no_focal);
  EXPECT_EQ(d.num_focal, 1);
  EXPECT_EQ(d.max_focal_err, 0.0);
}

TEST(ModelComparisonTest, UnregisteredAndExtraImagesAreCounted) {
  const GroundTruth gt = MakeGroundTruth(6, 5);
  Reconstruction model = ModelFromGroundTruth(gt);
  const std::string dropped = gt.images[4].name;
  model.images.erase(ImageNamed(model, dropped).image_id);
  ModelImage extra = model.images.begin()->second;
  extra.image_id = 100;
  extra.name = "not_in_gt.png";
  model.images[100] = extra;
  const ModelComparison c = CompareToGroundTruth(model, gt);
  EXPECT_EQ(c.num_gt_images, 6);
  EXPECT_EQ(c.num_model_images, 6);
  EXPECT_EQ(c.num_registered, 5);
  EXPECT_EQ(c.num_model_images_not_in_gt, 1);
  ASSERT_EQ(c.unregistered_names.size(), 1u);
  EXPECT_EQ(c.unregistered_names[0], dropped);
  EXPECT_EQ(c.num_pairs, 10);
  EXPECT_LT(c.max_rot_err_deg, 1e-9);
  EXPECT_LT(c.max_trans_err_deg, 1e-9);
  EXPECT_EQ(c.num_focal, 5);

  // Nothing registered: counts, and NaN (not 0) for the errors.
  const ModelComparison none = CompareToGroundTruth(Reconstruction(), gt);
  EXPECT_EQ(none.num_registered, 0);
  EXPECT_EQ(none.num_pairs, 0);
  EXPECT_EQ(none.unregistered_names.size(), 6u);
  EXPECT_TRUE(std::isnan(none.median_rot_err_deg) && std::isnan(none.max_rot_err_deg));
  EXPECT_TRUE(std::isnan(none.median_focal_err));
  EXPECT_TRUE(std::isnan(none.mean_reproj_error));
}

TEST(ModelComparisonTest, DuplicateModelNamesThrow) {
  const GroundTruth gt = MakeGroundTruth(3, 6);
  Reconstruction model = ModelFromGroundTruth(gt);
  model.images.at(2).name = model.images.at(1).name;
  EXPECT_THROW(CompareToGroundTruth(model, gt), std::runtime_error);
}

// ------------------------------------------------------------------------------------------------------------
// Ground-truth JSON.

TEST(GroundTruthJsonTest, RoundTripIsExact) {
  GroundTruth gt = MakeGroundTruth(5, 8);
  gt.images[3].focal = std::nan("");  // written without "f"
  TempDir tmp;
  WriteGroundTruthJson(gt, tmp.Sub("gt.json"));
  const GroundTruth back = ReadGroundTruthJson(tmp.Sub("gt.json"));
  ASSERT_EQ(back.images.size(), gt.images.size());
  for (size_t i = 0; i < gt.images.size(); ++i) {
    EXPECT_EQ(back.images[i].name, gt.images[i].name);
    EXPECT_EQ(back.images[i].R, gt.images[i].R);
    EXPECT_EQ(back.images[i].t, gt.images[i].t);
    if (i == 3) {
      EXPECT_TRUE(std::isnan(back.images[i].focal));
    } else {
      EXPECT_EQ(back.images[i].focal, gt.images[i].focal);
    }
  }
}

// Published ground truth prints rotations with about 6 significant digits (e.g. Strecha et al.'s .camera files):
// such a matrix is accepted and replaced by the nearest rotation.
TEST(GroundTruthJsonTest, RotationsPrintedWithSixDigitsAreAcceptedAndMadeOrthonormal) {
  const GroundTruth gt = MakeGroundTruth(4, 21);
  std::ostringstream text;
  text << std::setprecision(6) << "{\"images\": [";
  for (size_t i = 0; i < gt.images.size(); ++i) {
    text << (i ? ", " : "") << "{\"name\": \"" << gt.images[i].name << "\", \"R\": [";
    for (int k = 0; k < 9; ++k) text << (k ? ", " : "") << gt.images[i].R(k / 3, k % 3);
    text << "], \"t\": [" << gt.images[i].t(0) << ", " << gt.images[i].t(1) << ", " << gt.images[i].t(2) << "]}";
  }
  text << "]}";
  TempDir tmp;
  WriteText(tmp.Sub("gt.json"), text.str());
  const GroundTruth back = ReadGroundTruthJson(tmp.Sub("gt.json"));
  ASSERT_EQ(back.images.size(), gt.images.size());
  int rounded = 0;
  for (size_t i = 0; i < gt.images.size(); ++i) {
    const Eigen::Matrix3d& R = back.images[i].R;
    EXPECT_LT((R * R.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12) << i;
    EXPECT_NEAR(R.determinant(), 1.0, 1e-12) << i;
    EXPECT_LT((R - gt.images[i].R).norm(), 1e-5) << i;
    rounded += (R - gt.images[i].R).norm() > 1e-9;  // the printed digits did change the matrix
  }
  EXPECT_EQ(rounded, static_cast<int>(gt.images.size()));
}

TEST(GroundTruthJsonTest, MalformedFilesThrowNamingTheFile) {
  TempDir tmp;
  const std::string path = tmp.Sub("gt.json");
  auto expect_error = [&](const std::string& text, const std::string& needle) {
    WriteText(path, text);
    try {
      ReadGroundTruthJson(path);
      ADD_FAILURE() << "no error for: " << text;
    } catch (const std::runtime_error& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.rfind(path + ": ", 0), 0u) << msg;
      EXPECT_NE(msg.find(needle), std::string::npos) << msg;
    }
  };
  const std::string R = "[1,0,0,0,1,0,0,0,1]";
  expect_error("{\"images\": [", "invalid JSON");
  expect_error("[]", "expected an object with an \"images\" array");
  expect_error("{\"images\": [5]}", "images[0] must be an object");
  expect_error("{\"images\": [{\"R\": " + R + ", \"t\": [0,0,0]}]}", "missing or empty \"name\"");
  expect_error("{\"images\": [{\"name\": \"a\", \"t\": [0,0,0]}]}", "images[0] (a): missing \"R\"");
  expect_error("{\"images\": [{\"name\": \"a\", \"R\": [1,0,0], \"t\": [0,0,0]}]}", "\"R\" must be an array of 9");
  expect_error("{\"images\": [{\"name\": \"a\", \"R\": " + R + ", \"t\": [0,\"x\",0]}]}",
               "\"t\" must be an array of 3");
  expect_error("{\"images\": [{\"name\": \"a\", \"R\": [2,0,0,0,1,0,0,0,1], \"t\": [0,0,0]}]}", "not a rotation");
  expect_error("{\"images\": [{\"name\": \"a\", \"R\": [-1,0,0,0,1,0,0,0,1], \"t\": [0,0,0]}]}", "not a rotation");
  expect_error("{\"images\": [{\"name\": \"a\", \"R\": [1.001,0,0,0,1.001,0,0,0,1.001], \"t\": [0,0,0]}]}",
               "not a rotation");
  expect_error("{\"images\": [{\"name\": \"a\", \"R\": " + R + ", \"t\": [0,0,0], \"f\": -3}]}", "\"f\" must be");
  expect_error("{\"images\": [{\"name\": \"a\", \"R\": " + R + ", \"t\": [0,0,0], \"f\": \"9\"}]}", "\"f\" must be");
  expect_error("{\"images\": [{\"name\": \"a\", \"R\": " + R + ", \"t\": [0,0,0]}, {\"name\": \"a\", \"R\": " + R +
                   ", \"t\": [0,0,0]}]}",
               "images[1] (a): duplicate image name");
  try {
    ReadGroundTruthJson(tmp.Sub("missing.json"));
    ADD_FAILURE() << "no error for a missing file";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(tmp.Sub("missing.json")), std::string::npos) << e.what();
  }
}

// ------------------------------------------------------------------------------------------------------------
// The command.

struct CommandResult {
  int code = 0;
  std::string out, err;
};

CommandResult RunCommand(std::vector<std::string> args) {
  args.insert(args.begin(), {"madsfm", "model_compare"});
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  CommandResult r;
  r.code = RunModelCompare(static_cast<int>(argv.size()), argv.data());
  r.out = ::testing::internal::GetCapturedStdout();
  r.err = ::testing::internal::GetCapturedStderr();
  return r;
}

TEST(ModelCompareCommandTest, PrintsTextAndJson) {
  const GroundTruth gt = MakeGroundTruth(6, 9);
  Reconstruction model = ModelFromGroundTruth(gt, 3.0, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 1, 0), 10);
  model.images.erase(ImageNamed(model, gt.images[5].name).image_id);
  PerturbRotation(model, gt.images[0].name, 2.0, Eigen::Vector3d(1, 0, 0));
  TempDir tmp;
  WriteReconstructionBinary(model, tmp.Sub("model"));
  WriteGroundTruthJson(gt, tmp.Sub("gt.json"));

  const CommandResult text =
      RunCommand({"--input_path", tmp.Sub("model"), "--ground_truth_path", tmp.Sub("gt.json")});
  std::printf("%s", text.out.c_str());
  EXPECT_EQ(text.code, 0) << text.err;
  EXPECT_NE(text.out.find("Ground-truth images:          6\n"), std::string::npos);
  EXPECT_NE(text.out.find("Registered images:            5 (the model has 5 images, 0 not in the ground truth)"),
            std::string::npos);
  EXPECT_NE(text.out.find("Unregistered images:          img_005.png"), std::string::npos);
  EXPECT_NE(text.out.find("Image pairs:                  10\n"), std::string::npos);
  EXPECT_NE(text.out.find("Rotation error [deg]:         median 0.0000  max 2.0000"), std::string::npos);
  EXPECT_NE(text.out.find("3-D points:                   10\n"), std::string::npos);
  EXPECT_NE(text.out.find("Mean reprojection error [px]: 0.5500\n"), std::string::npos);

  const CommandResult json = RunCommand(
      {"--input_path", tmp.Sub("model"), "--ground_truth_path", tmp.Sub("gt.json"), "--output_format", "json"});
  EXPECT_EQ(json.code, 0) << json.err;
  const nlohmann::json j = nlohmann::json::parse(json.out);
  EXPECT_EQ(j.at("num_gt_images"), 6);
  EXPECT_EQ(j.at("num_registered"), 5);
  EXPECT_EQ(j.at("num_pairs"), 10);
  EXPECT_NEAR(j.at("max_rot_err_deg").get<double>(), 2.0, 1e-9);
  EXPECT_NEAR(j.at("median_rot_err_deg").get<double>(), 0.0, 1e-9);
  EXPECT_NEAR(j.at("median_trans_err_deg").get<double>(), 0.0, 1e-9);
  EXPECT_GT(j.at("max_trans_err_deg").get<double>(), 0.01);  // pairs with the rotated image
  EXPECT_LE(j.at("max_trans_err_deg").get<double>(), 2.0 + 1e-9);
  EXPECT_EQ(j.at("max_focal_err").get<double>(), 0.0);
  EXPECT_EQ(j.at("num_points3D"), 10);
  EXPECT_NEAR(j.at("mean_reproj_error").get<double>(), 0.55, 1e-12);
  EXPECT_EQ(j.at("unregistered_images"), nlohmann::json::array({"img_005.png"}));

  WriteReconstructionText(model, tmp.Sub("model_txt"));
  // A text model directory works too: the same numbers (parsed, compared as doubles).
  const CommandResult from_text = RunCommand({"--input_path", tmp.Sub("model_txt"), "--ground_truth_path",
                                              tmp.Sub("gt.json"), "--output_format", "json"});
  EXPECT_EQ(from_text.code, 0) << from_text.err;
  EXPECT_EQ(nlohmann::json::parse(from_text.out), j);
}

TEST(ModelCompareCommandTest, BadInputGivesExitCode1AndNamesTheFile) {
  const GroundTruth gt = MakeGroundTruth(3, 10);
  TempDir tmp;
  WriteReconstructionBinary(ModelFromGroundTruth(gt), tmp.Sub("model"));
  WriteGroundTruthJson(gt, tmp.Sub("gt.json"));
  WriteText(tmp.Sub("bad.json"), "{\"images\": 3}");

  CommandResult r = RunCommand({"--input_path", tmp.Sub("nope"), "--ground_truth_path", tmp.Sub("gt.json")});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find(tmp.Sub("nope")), std::string::npos) << r.err;
  r = RunCommand({"--input_path", tmp.Sub("model"), "--ground_truth_path", tmp.Sub("missing.json")});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find(tmp.Sub("missing.json")), std::string::npos) << r.err;
  r = RunCommand({"--input_path", tmp.Sub("model"), "--ground_truth_path", tmp.Sub("bad.json")});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find(tmp.Sub("bad.json")), std::string::npos) << r.err;
  // A corrupt model file.
  WriteText(tmp.Sub("model/images.bin"), "garbage");
  r = RunCommand({"--input_path", tmp.Sub("model"), "--ground_truth_path", tmp.Sub("gt.json")});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find(tmp.Sub("model/images.bin")), std::string::npos) << r.err;
  // Options.
  r = RunCommand({"--input_path", tmp.Sub("model")});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("--ground_truth_path"), std::string::npos) << r.err;
  r = RunCommand({"--input_path", tmp.Sub("model"), "--ground_truth_path", tmp.Sub("gt.json"), "--output_format",
                  "xml"});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("--output_format"), std::string::npos) << r.err;
  r = RunCommand({"--help"});
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("--ground_truth_path"), std::string::npos);
}

}  // namespace
}  // namespace madsfm::colmap
