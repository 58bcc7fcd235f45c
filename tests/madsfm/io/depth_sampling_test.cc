#include "madsfm/io/depth_sampling.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "madsfm/io/io_test_util.h"

namespace madsfm {
namespace {

using io_test::Contains;
using io_test::ErrorOf;

// An affine function of image coordinates; at integer and half-integer points its values are exact in float.
double Affine(double x, double y) { return 2.0 + 0.25 * x + 0.5 * y; }

// A W' x H' map of Affine sampled at the image coordinates of the map's pixel centres, for an image of W x H:
// map pixel i has its centre at image x = (i + 0.5) * W / W' - 0.5.
DepthMap AffineMap(int map_width, int map_height, int image_width, int image_height) {
  DepthMap map;
  map.width = map_width;
  map.height = map_height;
  map.data.resize(static_cast<size_t>(map_width) * map_height);
  for (int v = 0; v < map_height; ++v) {
    for (int u = 0; u < map_width; ++u) {
      const double x = (u + 0.5) * image_width / map_width - 0.5;
      const double y = (v + 0.5) * image_height / map_height - 0.5;
      map.data[static_cast<size_t>(v) * map_width + u] = static_cast<float>(Affine(x, y));
    }
  }
  return map;
}

TEST(DepthSampling, BilinearIsExactOnAnAffineFunction) {
  const int W = 40, H = 30;
  const DepthMap map = AffineMap(W, H, W, H);  // same resolution: map pixel = image pixel
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> ux(0.0, W - 1.0), uy(0.0, H - 1.0);
  double max_error = 0;
  for (int i = 0; i < 10000; ++i) {
    const double x = ux(rng), y = uy(rng);
    max_error = std::max(max_error, std::abs(SampleDepth(map, x, y, W, H) - Affine(x, y)));
  }
  std::printf("same resolution: max |sample - affine| over 10000 points = %.3g\n", max_error);
  EXPECT_LT(max_error, 1e-12);
  // Exactly at pixel centres the stored value comes back.
  EXPECT_EQ(SampleDepth(map, 7, 9, W, H), map.At(7, 9));
  EXPECT_EQ(SampleDepth(map, W - 1, H - 1, W, H), map.At(W - 1, H - 1));
}

TEST(DepthSampling, LowerResolutionMapFollowsTheResolutionMapping) {
  struct Case {
    int map_width, map_height, image_width, image_height;
  };
  // Half resolution, and a non-integer ratio with slightly different x/y scale (aspect within 1%).
  for (const Case& c : {Case{320, 240, 640, 480}, Case{518, 345, 720, 480}, Case{640, 480, 640, 480}}) {
    const DepthMap map = AffineMap(c.map_width, c.map_height, c.image_width, c.image_height);
    // Interior: map coordinates in [0, W' - 1] <=> image x in [W/(2W') - 0.5, W - W/(2W') - 0.5].
    const double margin_x = 0.5 * c.image_width / c.map_width, margin_y = 0.5 * c.image_height / c.map_height;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> ux(margin_x - 0.5, c.image_width - margin_x - 0.5);
    std::uniform_real_distribution<double> uy(margin_y - 0.5, c.image_height - margin_y - 0.5);
    std::vector<Eigen::Vector2d> points;
    for (int i = 0; i < 10000; ++i) points.emplace_back(ux(rng), uy(rng));
    const std::vector<double> depths = SampleDepths(map, points, c.image_width, c.image_height);
    ASSERT_EQ(depths.size(), points.size());
    double max_error = 0;
    for (size_t i = 0; i < points.size(); ++i) {
      max_error = std::max(max_error, std::abs(depths[i] - Affine(points[i].x(), points[i].y())));
      ASSERT_EQ(depths[i], SampleDepth(map, points[i].x(), points[i].y(), c.image_width, c.image_height));
    }
    std::printf("map %dx%d for image %dx%d: max |sample - affine| over 10000 interior points = %.3g\n",
                c.map_width, c.map_height, c.image_width, c.image_height, max_error);
    // The map stores floats: tolerance = float rounding of the stored values (|f| < 600, eps 6e-8).
    EXPECT_LT(max_error, 1e-4);
  }
  // Half resolution at exactly representable values: the map pixel (i, j) centre is image (2i + 0.5, 2j + 0.5).
  const DepthMap half = AffineMap(320, 240, 640, 480);
  EXPECT_EQ(SampleDepth(half, 2 * 10 + 0.5, 2 * 20 + 0.5, 640, 480), half.At(10, 20));
  EXPECT_EQ(SampleDepth(half, 100, 50, 640, 480), Affine(100, 50));
  EXPECT_EQ(SampleDepth(half, 101, 51, 640, 480), Affine(101, 51));
}

TEST(DepthSampling, BorderClampAndOutsideImage) {
  const DepthMap map = AffineMap(320, 240, 640, 480);
  const int W = 640, H = 480;
  // Within half a map pixel of the border (one image pixel here) the edge value is used.
  EXPECT_EQ(SampleDepth(map, -0.5, 100.5, W, H), map.At(0, 50));
  EXPECT_EQ(SampleDepth(map, 0.0, 100.5, W, H), map.At(0, 50));
  EXPECT_EQ(SampleDepth(map, 0.5, 100.5, W, H), map.At(0, 50));
  EXPECT_EQ(SampleDepth(map, W - 0.5, H - 0.5, W, H), map.At(319, 239));
  EXPECT_EQ(SampleDepth(map, W - 1.5, -0.5, W, H), map.At(319, 0));
  // Outside the image, or non-finite coordinates: NaN.
  const double outside[][2] = {{-0.51, 10}, {10, -0.51}, {W - 0.49, 10}, {10, H - 0.49}, {1e9, 1e9},
                               {std::nan(""), 10}, {10, std::numeric_limits<double>::infinity()}};
  for (const auto& p : outside) EXPECT_TRUE(std::isnan(SampleDepth(map, p[0], p[1], W, H))) << p[0] << " " << p[1];
  // Empty map or image size: NaN, no crash.
  EXPECT_TRUE(std::isnan(SampleDepth(DepthMap(), 1, 1, W, H)));
  EXPECT_TRUE(std::isnan(SampleDepth(map, 1, 1, 0, H)));
  EXPECT_TRUE(SampleDepths(DepthMap(), {Eigen::Vector2d(1, 1)}, W, H).size() == 1);
}

TEST(DepthSampling, InvalidTapsGiveNaN) {
  const int W = 10, H = 10;
  for (const float bad : {std::numeric_limits<float>::quiet_NaN(), 0.0f, -1.0f,
                          std::numeric_limits<float>::infinity()}) {
    DepthMap map = AffineMap(W, H, W, H);
    map.data[5 * W + 5] = bad;  // pixel (5, 5)
    EXPECT_TRUE(std::isnan(SampleDepth(map, 5, 5, W, H))) << bad;
    EXPECT_TRUE(std::isnan(SampleDepth(map, 4.5, 5, W, H))) << bad;    // weight 0.5 on (5, 5)
    EXPECT_TRUE(std::isnan(SampleDepth(map, 5, 5.9, W, H))) << bad;
    EXPECT_TRUE(std::isnan(SampleDepth(map, 4.01, 4.01, W, H))) << bad;  // tiny weight is still a weight
    EXPECT_TRUE(std::isnan(SampleDepth(map, 5.99, 5.99, W, H))) << bad;
    // Taps with zero weight do not matter.
    EXPECT_EQ(SampleDepth(map, 4, 5, W, H), map.At(4, 5)) << bad;
    EXPECT_EQ(SampleDepth(map, 6, 5.5, W, H), 0.5 * map.At(6, 5) + 0.5 * map.At(6, 6)) << bad;
    EXPECT_EQ(SampleDepth(map, 5.5, 4, W, H), 0.5 * map.At(5, 4) + 0.5 * map.At(6, 4)) << bad;
    EXPECT_FALSE(std::isnan(SampleDepth(map, 6.01, 6.01, W, H))) << bad;
  }
}

TEST(DepthSampling, AspectRatioCheck) {
  const auto map_of = [](int w, int h) {
    DepthMap map;
    map.width = w;
    map.height = h;
    map.data.assign(static_cast<size_t>(w) * h, 1.0f);
    return map;
  };
  EXPECT_NO_THROW(CheckAspectRatio(map_of(320, 240), 640, 480, "d.npy"));
  EXPECT_NO_THROW(CheckAspectRatio(map_of(518, 392), 640, 480, "d.npy"));  // 0.9% off
  EXPECT_NO_THROW(CheckAspectRatio(map_of(1009, 1000), 1000, 1000, "d.npy"));
  std::string message = ErrorOf([&] { CheckAspectRatio(map_of(1011, 1000), 1000, 1000, "x/d.npy"); });
  EXPECT_TRUE(Contains(message, "depth file 'x/d.npy': ")) << message;
  EXPECT_TRUE(Contains(message, "differ by more than 1%")) << message;
  message = ErrorOf([&] { CheckAspectRatio(map_of(480, 640), 640, 480, "rotated.npy"); });
  EXPECT_TRUE(Contains(message, "depth file 'rotated.npy': the depth map is 480x640")) << message;
  EXPECT_TRUE(Contains(ErrorOf([&] { CheckAspectRatio(DepthMap(), 640, 480, "e.npy"); }), "'e.npy'"));
  EXPECT_TRUE(Contains(ErrorOf([&] { CheckAspectRatio(map_of(4, 3), 0, 480, "z.npy"); }), "invalid image size"));
}

}  // namespace
}  // namespace madsfm
