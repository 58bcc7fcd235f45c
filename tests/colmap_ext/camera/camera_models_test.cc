// COLMAP camera models: ids/names/parameter counts, known projections, and the round trip
// CameraToImage(ImageToCamera(p)) == p over the whole image for every supported model.
#include "colmap_ext/camera/camera_models.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace madsfm::colmap {
namespace {

CameraIntrinsics MakeCamera(int model_id, int width, int height, std::vector<double> params) {
  CameraIntrinsics camera;
  camera.model_id = model_id;
  camera.width = width;
  camera.height = height;
  camera.params = std::move(params);
  return camera;
}

TEST(CameraModels, IdsNamesAndParamCounts) {
  const struct {
    int id;
    const char* name;
    int num_params;
  } kExpected[] = {{0, "SIMPLE_PINHOLE", 3},     {1, "PINHOLE", 4},        {2, "SIMPLE_RADIAL", 4},
                   {3, "RADIAL", 5},             {4, "OPENCV", 8},         {5, "OPENCV_FISHEYE", 8},
                   {6, "FULL_OPENCV", 12},       {7, "FOV", 5},            {8, "SIMPLE_RADIAL_FISHEYE", 4},
                   {9, "RADIAL_FISHEYE", 5},     {10, "THIN_PRISM_FISHEYE", 12}, {11, "RAD_TAN_THIN_PRISM_FISHEYE", 16},
                   {12, "SIMPLE_DIVISION", 4},   {13, "DIVISION", 5},      {14, "SIMPLE_FISHEYE", 3},
                   {15, "FISHEYE", 4},           {16, "EUCM", 6},          {17, "EQUIRECTANGULAR", 2}};
  for (const auto& e : kExpected) {
    EXPECT_EQ(CameraModelName(e.id), e.name);
    EXPECT_EQ(CameraModelId(e.name), e.id);
    EXPECT_EQ(CameraModelNumParams(e.id), e.num_params) << e.name;
  }
  EXPECT_EQ(CameraModelName(42), "UNKNOWN(42)");
  EXPECT_EQ(CameraModelName(-1), "UNKNOWN(-1)");
  EXPECT_EQ(CameraModelId("NOT_A_MODEL"), -1);
  EXPECT_EQ(CameraModelNumParams(42), -1);
  EXPECT_EQ(CameraModelNumParams(-1), -1);
  for (int id : {0, 1, 2, 3, 4, 5, 6}) EXPECT_TRUE(IsSupportedCameraModel(id)) << CameraModelName(id);
  for (int id : {7, 10, 11, 12, 17, 42, -1}) EXPECT_FALSE(IsSupportedCameraModel(id)) << CameraModelName(id);
}

TEST(CameraModels, AccessorsAndSetFocal) {
  CameraIntrinsics simple = MakeCamera(2, 640, 480, {600, 320, 240, 0.01});
  EXPECT_EQ(simple.FocalX(), 600);
  EXPECT_EQ(simple.FocalY(), 600);
  EXPECT_EQ(simple.PrincipalX(), 320);
  EXPECT_EQ(simple.PrincipalY(), 240);
  simple.SetFocal(700);
  EXPECT_EQ(simple.params, (std::vector<double>{700, 320, 240, 0.01}));

  CameraIntrinsics pinhole = MakeCamera(1, 1024, 768, {800, 880, 512, 384});
  EXPECT_EQ(pinhole.FocalX(), 800);
  EXPECT_EQ(pinhole.FocalY(), 880);
  EXPECT_EQ(pinhole.PrincipalX(), 512);
  EXPECT_EQ(pinhole.PrincipalY(), 384);
  pinhole.SetFocal(1000);  // aspect fy / fx = 1.1 kept
  EXPECT_DOUBLE_EQ(pinhole.params[0], 1000);
  EXPECT_DOUBLE_EQ(pinhole.params[1], 1100);
  EXPECT_EQ(pinhole.params[2], 512);

  CameraIntrinsics wrong_count = MakeCamera(1, 1024, 768, {800, 880, 512});
  EXPECT_THROW(wrong_count.FocalX(), std::invalid_argument);
  EXPECT_THROW(MakeCamera(42, 10, 10, {1, 2, 3}).FocalX(), std::invalid_argument);
}

TEST(CameraModels, KnownValuesPinholeModels) {
  // SIMPLE_PINHOLE f = 1000, principal point (320, 240).
  const CameraIntrinsics simple = MakeCamera(0, 640, 480, {1000, 320, 240});
  const Eigen::Vector2d n = ImageToCamera(simple, Eigen::Vector2d(820, 740));
  EXPECT_DOUBLE_EQ(n.x(), 0.5);
  EXPECT_DOUBLE_EQ(n.y(), 0.5);
  const Eigen::Vector2d p = CameraToImage(simple, Eigen::Vector2d(-0.25, 0.1));
  EXPECT_DOUBLE_EQ(p.x(), 70);
  EXPECT_DOUBLE_EQ(p.y(), 340);

  // PINHOLE fx = 800, fy = 600, principal point at the image centre (400, 300) of an 800 x 600 image: the centre of
  // the upper-left pixel is (0.5, 0.5) in COLMAP's convention, so x = (u - cx) / fx applies to it directly.
  const CameraIntrinsics pinhole = MakeCamera(1, 800, 600, {800, 600, 400, 300});
  const Eigen::Vector2d corner = ImageToCamera(pinhole, Eigen::Vector2d(0.5, 0.5));
  EXPECT_DOUBLE_EQ(corner.x(), (0.5 - 400) / 800);
  EXPECT_DOUBLE_EQ(corner.y(), (0.5 - 300) / 600);
  const Eigen::Vector2d centre = ImageToCamera(pinhole, Eigen::Vector2d(400, 300));
  EXPECT_EQ(centre, Eigen::Vector2d(0, 0));
  const Eigen::Vector2d q = CameraToImage(pinhole, Eigen::Vector2d(0.5, -0.5));
  EXPECT_DOUBLE_EQ(q.x(), 800);
  EXPECT_DOUBLE_EQ(q.y(), 0);
}

TEST(CameraModels, KnownValuesDistortedModels) {
  // SIMPLE_RADIAL f = 500, c = (250, 200), k = 0.1; (0.1, 0.2): r^2 = 0.05, factor 1.005.
  const CameraIntrinsics simple_radial = MakeCamera(2, 500, 400, {500, 250, 200, 0.1});
  Eigen::Vector2d p = CameraToImage(simple_radial, Eigen::Vector2d(0.1, 0.2));
  EXPECT_NEAR(p.x(), 300.25, 1e-12);
  EXPECT_NEAR(p.y(), 300.5, 1e-12);

  // OPENCV fx = fy = 100, c = 0, k1 = 0.1, k2 = 0.01, p1 = 0.001, p2 = 0.002; (0.3, 0.4), worked by hand:
  // r^2 = 0.25, radial 1.025625, x = 0.3076875 + 2 p1 x y + p2 (r^2 + 2 x^2) = 0.3087875,
  // y = 0.41025 + 2 p2 x y + p1 (r^2 + 2 y^2) = 0.4113.
  const CameraIntrinsics opencv = MakeCamera(4, 100, 100, {100, 100, 0, 0, 0.1, 0.01, 0.001, 0.002});
  p = CameraToImage(opencv, Eigen::Vector2d(0.3, 0.4));
  EXPECT_NEAR(p.x(), 30.87875, 1e-11);
  EXPECT_NEAR(p.y(), 41.13, 1e-11);

  // OPENCV_FISHEYE without distortion is equidistant: (1, 0) is 45 degrees off-axis -> radius f * pi / 4.
  const CameraIntrinsics fisheye = MakeCamera(5, 1000, 1000, {400, 400, 500, 500, 0, 0, 0, 0});
  p = CameraToImage(fisheye, Eigen::Vector2d(1, 0));
  EXPECT_NEAR(p.x(), 500 + 400 * M_PI / 4, 1e-10);
  EXPECT_NEAR(p.y(), 500, 1e-12);
  const Eigen::Vector2d n = ImageToCamera(fisheye, Eigen::Vector2d(500, 500 + 400 * M_PI / 3));  // 60 degrees
  EXPECT_NEAR(n.x(), 0, 1e-15);
  EXPECT_NEAR(n.y(), std::tan(M_PI / 3), 1e-12);
}

struct RoundTripCase {
  const char* label;
  CameraIntrinsics camera;
};

TEST(CameraModels, RoundTripOverTheImage) {
  const int w = 1920, h = 1080;
  const std::vector<RoundTripCase> cases = {
      {"SIMPLE_PINHOLE", MakeCamera(0, w, h, {1600, 960, 540})},
      {"PINHOLE", MakeCamera(1, w, h, {1580, 1620, 955.5, 543.2})},
      {"SIMPLE_RADIAL barrel", MakeCamera(2, w, h, {1500, 960, 540, -0.08})},
      {"SIMPLE_RADIAL pincushion", MakeCamera(2, w, h, {1500, 960, 540, 0.05})},
      {"RADIAL", MakeCamera(3, w, h, {1400, 962, 538, -0.12, 0.03})},
      {"OPENCV", MakeCamera(4, w, h, {1450, 1440, 958, 545, -0.18, 0.04, 0.0012, -0.0008})},
      {"FULL_OPENCV",
       MakeCamera(6, w, h, {1450, 1445, 961, 539, -0.25, 0.08, 0.0009, -0.0006, -0.01, 0.05, 0.01, 0.002})},
      {"OPENCV_FISHEYE", MakeCamera(5, w, h, {800, 798, 962, 541, 0.05, -0.01, 0.002, -0.0005})},
      {"SIMPLE_RADIAL_FISHEYE", MakeCamera(8, w, h, {780, 960, 540, 0.04})},
      {"RADIAL_FISHEYE", MakeCamera(9, w, h, {790, 960, 540, 0.03, -0.004})},
  };
  const int kStep = 16;
  for (const RoundTripCase& c : cases) {
    double max_pixel_error = 0, max_camera_error = 0;
    int num_points = 0;
    for (int y = 0; y <= h; y += kStep) {
      for (int x = 0; x <= w; x += kStep) {
        // Pixel centres and the exact corners (0, 0) / (W, H) of the image.
        const Eigen::Vector2d p(std::min<double>(x + 0.5, w), std::min<double>(y + 0.5, h));
        const Eigen::Vector2d n = ImageToCamera(c.camera, p);
        ASSERT_TRUE(n.allFinite()) << c.label;
        const Eigen::Vector2d back = CameraToImage(c.camera, n);
        max_pixel_error = std::max(max_pixel_error, (back - p).norm());
        // And the other direction, for the same normalised point.
        const Eigen::Vector2d n2 = ImageToCamera(c.camera, CameraToImage(c.camera, n));
        max_camera_error = std::max(max_camera_error, (n2 - n).norm());
        ++num_points;
      }
    }
    std::printf("[ rates    ] %-26s %d points: max |CameraToImage(ImageToCamera(p)) - p| = %.2e px, "
                "camera-side %.2e\n",
                c.label, num_points, max_pixel_error, max_camera_error);
    EXPECT_LT(max_pixel_error, 1e-9) << c.label;
    EXPECT_LT(max_camera_error, 1e-12) << c.label;
  }
}

TEST(CameraModels, UndistortionRemovesBarrelDistortion) {
  // A strongly distorting camera: the corner's undistorted radius is larger than its distorted one (barrel), and the
  // result is a fixed point of the distortion model, not just a first-order approximation.
  const CameraIntrinsics camera = MakeCamera(3, 1920, 1080, {1000, 960, 540, -0.2, 0.02});
  const Eigen::Vector2d corner(0, 0);
  const Eigen::Vector2d n = ImageToCamera(camera, corner);
  const Eigen::Vector2d naive((0 - 960) / 1000.0, (0 - 540) / 1000.0);
  EXPECT_GT(n.norm(), naive.norm() * 1.1);
  EXPECT_LT((CameraToImage(camera, n) - corner).norm(), 1e-9);
}

TEST(CameraModels, UnsupportedModelsThrowNamingThem) {
  const struct {
    CameraIntrinsics camera;
    const char* name;
  } kCases[] = {{MakeCamera(7, 100, 100, {100, 100, 50, 50, 0.5}), "FOV"},
                {MakeCamera(10, 100, 100, std::vector<double>(12, 0.1)), "THIN_PRISM_FISHEYE"},
                {MakeCamera(12, 100, 100, {100, 50, 50, 0.1}), "SIMPLE_DIVISION"},
                {MakeCamera(42, 100, 100, {100, 50, 50}), "UNKNOWN(42)"}};
  for (const auto& c : kCases) {
    for (int direction = 0; direction < 2; ++direction) {
      try {
        if (direction == 0) {
          ImageToCamera(c.camera, Eigen::Vector2d(10, 10));
        } else {
          CameraToImage(c.camera, Eigen::Vector2d(0.1, 0.1));
        }
        ADD_FAILURE() << "no exception for " << c.name;
      } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find(c.name), std::string::npos) << e.what();
      }
    }
  }
  // Supported model with the wrong number of parameters.
  EXPECT_THROW(ImageToCamera(MakeCamera(4, 100, 100, {100, 100, 50, 50}), Eigen::Vector2d(1, 1)),
               std::invalid_argument);
}

}  // namespace
}  // namespace madsfm::colmap
