#include "madsfm/synthetic/multiview_scene.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <vector>

namespace madsfm {
namespace {

MultiViewSceneOptions SmallOptions(MultiViewSceneType type, int width, int height) {
  MultiViewSceneOptions o;
  o.scene = type;
  o.image_width = width;
  o.image_height = height;
  return o;
}

const MultiViewSceneType kTypes[] = {MultiViewSceneType::kRoom, MultiViewSceneType::kStreet};

TEST(MultiViewScene, OptionsCheck) {
  MultiViewSceneOptions o;
  EXPECT_NO_THROW(o.Check());
  o.num_images = 1;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o = MultiViewSceneOptions();
  o.depth_map_scale = 0.0;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o = MultiViewSceneOptions();
  o.supersampling = 0;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o = MultiViewSceneOptions();
  o.prior_min_scale = 2.0;
  o.prior_max_scale = 1.0;
  EXPECT_THROW((MultiViewScene(o, 0)), std::invalid_argument);
}

TEST(MultiViewScene, CamerasAndConventions) {
  for (const MultiViewSceneType type : kTypes) {
    const MultiViewScene scene(MultiViewSceneOptions{type}, 3);
    ASSERT_EQ(scene.NumImages(), 10);
    const double fov = 2.0 * std::atan(320.0 / scene.Focal()) * 180.0 / M_PI;
    EXPECT_GE(fov, 60.0);
    EXPECT_LE(fov, 70.0);
    for (int i = 0; i < scene.NumImages(); ++i) {
      const MultiViewCamera& cam = scene.Camera(i);
      EXPECT_EQ(scene.ImageName(i), (i < 10 ? "img_00" : "img_0") + std::to_string(i) + ".png");
      EXPECT_EQ(cam.width, 640);
      EXPECT_EQ(cam.height, 480);
      EXPECT_DOUBLE_EQ(cam.cx, 320.0);
      EXPECT_DOUBLE_EQ(cam.cy, 240.0);
      EXPECT_DOUBLE_EQ(cam.focal, scene.Focal());
      EXPECT_LT((cam.R * cam.R.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
      EXPECT_NEAR(cam.R.determinant(), 1.0, 1e-12);
      // The ray through (x, y) at z-depth z projects back to (x, y) with depth z (x_cam = R x_world + t).
      const Eigen::Vector3d X = cam.Center() + 4.0 * cam.RayDirection(100.5, 200.5);
      const Eigen::Vector3d Xc = cam.R * X + cam.t;
      EXPECT_NEAR(Xc.z(), 4.0, 1e-12);
      EXPECT_NEAR(cam.focal * Xc.x() / Xc.z() + cam.cx, 100.5, 1e-9);
      EXPECT_NEAR(cam.focal * Xc.y() / Xc.z() + cam.cy, 200.5, 1e-9);
      // The camera's "up" (-y) points up in the world (z-up), small roll.
      EXPECT_GT(-cam.R.row(1).z(), 0.9);
    }
  }
}

TEST(MultiViewScene, DeterministicForASeed) {
  for (const MultiViewSceneType type : kTypes) {
    MultiViewSceneOptions o = SmallOptions(type, 160, 120);
    o.num_images = 3;
    const MultiViewScene a(o, 42), b(o, 42), c(o, 43);
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(a.Camera(i).R, b.Camera(i).R);
      EXPECT_EQ(a.Camera(i).t, b.Camera(i).t);
    }
    o.num_threads = 1;
    const MultiViewScene a1(o, 42);
    const MultiViewImage ia = a.Render(2), ib = b.Render(2), ia1 = a1.Render(2), ic = c.Render(2);
    EXPECT_EQ(ia.rgb, ib.rgb);
    EXPECT_EQ(ia.rgb, ia1.rgb) << "the number of threads must not change the image";
    EXPECT_EQ(ia.depth.data, ib.depth.data);
    EXPECT_EQ(ia.prior.data, ib.prior.data);
    EXPECT_EQ(ia.prior_scale, ib.prior_scale);
    EXPECT_EQ(ia.prior_shift, ib.prior_shift);
    EXPECT_NE(ia.rgb, ic.rgb);
    EXPECT_NE(ia.prior_scale, ic.prior_scale);
  }
}

// Bilinear interpolation of 1 / depth at image point p (COLMAP convention: pixel (x, y) is centred at
// (x + 0.5, y + 0.5)). Returns false near the border, on sky, or if the four neighbours are not (numerically) on
// one plane: 1 / z is affine in the image on a plane, so there bilinear interpolation of 1 / z is exact.
bool PlanarInverseDepth(const DepthMap& depth, const Eigen::Vector2d& p, double* inv_depth) {
  const double u = p.x() - 0.5, v = p.y() - 0.5;
  const int x0 = static_cast<int>(std::floor(u)), y0 = static_cast<int>(std::floor(v));
  if (x0 < 0 || y0 < 0 || x0 + 1 >= depth.width || y0 + 1 >= depth.height) return false;
  const double z00 = depth.At(x0, y0), z10 = depth.At(x0 + 1, y0), z01 = depth.At(x0, y0 + 1),
               z11 = depth.At(x0 + 1, y0 + 1);
  if (z00 <= 0 || z10 <= 0 || z01 <= 0 || z11 <= 0) return false;
  const double i00 = 1 / z00, i10 = 1 / z10, i01 = 1 / z01, i11 = 1 / z11;
  if (std::abs(i00 + i11 - i10 - i01) > 1e-6 * i00) return false;
  const double ax = u - x0, ay = v - y0;
  *inv_depth = (1 - ay) * ((1 - ax) * i00 + ax * i10) + ay * ((1 - ax) * i01 + ax * i11);
  return true;
}

// Scene points at the rendered depth of view i, projected into view j, land at view j's rendered depth when
// visible, and never behind it.
TEST(MultiViewScene, ProjectionsLandAtTheRenderedDepth) {
  for (const MultiViewSceneType type : kTypes) {
    MultiViewSceneOptions o = SmallOptions(type, 320, 240);
    o.supersampling = 1;
    const MultiViewScene scene(o, 7);
    std::mt19937 rng(11);
    int num_points = 0, num_in_view = 0, num_visible_cast = 0, num_behind_cast = 0;
    int num_planar = 0, num_planar_visible = 0, num_planar_occluded = 0, num_planar_violations = 0;
    for (const auto& [i, j] : std::vector<std::pair<int, int>>{{0, 1}, {4, 5}, {8, 9}, {2, 6}, {9, 3}}) {
      const MultiViewImage vi = scene.Render(i), vj = scene.Render(j);
      const MultiViewCamera &ci = vi.camera, &cj = vj.camera;
      // Exact depth = the ray cast through the pixel centre.
      for (int k = 0; k < 200; ++k) {
        const int x = rng() % ci.width, y = rng() % ci.height;
        EXPECT_EQ(vi.depth.At(x, y), static_cast<float>(scene.DepthAt(i, x + 0.5, y + 0.5)));
      }
      for (int k = 0; k < 2000; ++k) {
        const int x = rng() % ci.width, y = rng() % ci.height;
        const double z = vi.depth.At(x, y);
        if (z <= 0.0) continue;
        ++num_points;
        const Eigen::Vector3d X = ci.Center() + z * ci.RayDirection(x + 0.5, y + 0.5);
        Eigen::Vector2d p;
        double zi, zj;
        ASSERT_TRUE(ci.Project(X, &p, &zi));
        EXPECT_NEAR(p.x(), x + 0.5, 1e-4);
        EXPECT_NEAR(p.y(), y + 0.5, 1e-4);
        EXPECT_NEAR(zi, z, 1e-6 * z);
        if (!cj.Project(X, &p, &zj) || !cj.InImage(p)) continue;
        ++num_in_view;
        const double cast = scene.DepthAt(j, p.x(), p.y());
        if (std::abs(cast - zj) <= 1e-5 * zj) ++num_visible_cast;
        if (cast > zj * (1 + 1e-5) || cast <= 0.0) ++num_behind_cast;
        double inv;
        if (!PlanarInverseDepth(vj.depth, p, &inv)) continue;
        ++num_planar;
        const double zr = 1.0 / inv;
        if (std::abs(zr - zj) <= 1e-4 * zj) {
          ++num_planar_visible;
        } else if (zr < zj) {
          ++num_planar_occluded;
        } else {
          ++num_planar_violations;
        }
      }
    }
    std::printf(
        "[%s] %d points at rendered depths, %d project into the other view: %.1f%% visible by exact "
        "casting, %d behind the surface; %d on planar depth cells: %.1f%% at the rendered depth (<1e-4), "
        "%.1f%% occluded, %d behind it\n",
        MultiViewSceneTypeName(type), num_points, num_in_view, 100.0 * num_visible_cast / num_in_view, num_behind_cast,
        num_planar, 100.0 * num_planar_visible / num_planar, 100.0 * num_planar_occluded / num_planar,
        num_planar_violations);
    EXPECT_GT(num_points, 9000);
    EXPECT_EQ(num_behind_cast, 0);
    EXPECT_GT(num_visible_cast, 0.8 * num_in_view);
    EXPECT_EQ(num_planar_violations, 0);
    EXPECT_GT(num_planar_visible, 0.8 * num_planar);
  }
}

// Share of view i's surface points (a grid of pixel centres) that are visible in view j.
double Overlap(const MultiViewScene& scene, int i, int j) {
  const MultiViewCamera &ci = scene.Camera(i), &cj = scene.Camera(j);
  int valid = 0, visible = 0;
  for (int gy = 0; gy < 24; ++gy) {
    for (int gx = 0; gx < 32; ++gx) {
      const double x = (gx + 0.5) * ci.width / 32.0, y = (gy + 0.5) * ci.height / 24.0;
      const double z = scene.DepthAt(i, x, y);
      if (z <= 0.0) continue;
      ++valid;
      const Eigen::Vector3d X = ci.Center() + z * ci.RayDirection(x, y);
      Eigen::Vector2d p;
      double zj;
      if (!cj.Project(X, &p, &zj) || !cj.InImage(p)) continue;
      if (std::abs(scene.DepthAt(j, p.x(), p.y()) - zj) <= 1e-6 * zj) ++visible;
    }
  }
  return valid > 0 ? static_cast<double>(visible) / valid : 0.0;
}

TEST(MultiViewScene, NeighbouringViewsOverlapByMoreThanHalf) {
  for (const MultiViewSceneType type : kTypes) {
    for (const int num_images : {8, 10, 15}) {
      double min_overlap = 1.0, min_end_to_end = 1.0, min_sky_free = 1.0;
      for (uint64_t seed = 0; seed < 5; ++seed) {
        MultiViewSceneOptions o;
        o.scene = type;
        o.num_images = num_images;
        const MultiViewScene scene(o, seed);
        for (int i = 0; i + 1 < num_images; ++i) {
          const double forward = Overlap(scene, i, i + 1), backward = Overlap(scene, i + 1, i);
          EXPECT_GT(forward, 0.5) << MultiViewSceneTypeName(type) << " seed " << seed << " views " << i;
          EXPECT_GT(backward, 0.5) << MultiViewSceneTypeName(type) << " seed " << seed << " views " << i;
          min_overlap = std::min({min_overlap, forward, backward});
        }
        min_end_to_end = std::min(min_end_to_end, Overlap(scene, 0, num_images - 1));
        // Most of every view sees a surface (not the sky).
        for (int i = 0; i < num_images; ++i) {
          int surface = 0;
          for (int g = 0; g < 400; ++g) surface += scene.DepthAt(i, (g % 20 + 0.5) * 32, (g / 20 + 0.5) * 24) > 0;
          min_sky_free = std::min(min_sky_free, surface / 400.0);
        }
      }
      std::printf(
          "[%s, %d images, seeds 0-4] min neighbour overlap %.1f%%, min first/last overlap %.1f%%, "
          "min surface share %.1f%%\n",
          MultiViewSceneTypeName(type), num_images, 100.0 * min_overlap, 100.0 * min_end_to_end, 100.0 * min_sky_free);
      EXPECT_GT(min_sky_free, 0.7);
    }
  }
}

TEST(MultiViewScene, PriorIsAnAffineTransformOfTheDepthPlusASmoothDistortion) {
  for (const MultiViewSceneType type : kTypes) {
    MultiViewSceneOptions o = SmallOptions(type, 320, 240);
    o.supersampling = 1;
    o.num_images = 8;
    // Without distortion: a d + b reproduces the exact depth.
    o.prior_distortion = 0.0;
    const MultiViewScene exact(o, 5);
    double max_rel = 0.0;
    for (int i = 0; i < exact.NumImages(); ++i) {
      const MultiViewImage im = exact.Render(i);
      ASSERT_EQ(im.prior.width, 160);
      ASSERT_EQ(im.prior.height, 120);
      EXPECT_GE(im.prior_scale, o.prior_min_scale);
      EXPECT_LE(im.prior_scale, o.prior_max_scale);
      EXPECT_LE(std::abs(im.prior_shift), o.prior_max_shift_fraction * 3.0 * im.median_depth);
      for (size_t k = 0; k < im.prior.data.size(); ++k) {
        const double d = im.prior.data[k], z = im.prior_true_depth.data[k];
        ASSERT_TRUE(std::isfinite(d) && d > 0.0);
        if (z <= 0.0) continue;
        max_rel = std::max(max_rel, std::abs(im.prior_scale * d + im.prior_shift - z) / z);
      }
    }
    std::printf("[%s] no distortion: max |a d + b - z| / z = %.2e\n", MultiViewSceneTypeName(type), max_rel);
    EXPECT_LT(max_rel, 1e-5);

    // With the default distortion (3%): the undistorted prior maps back exactly, the prior is a few percent off
    // and not affine (the best affine fit leaves a residual).
    o.prior_distortion = 0.03;
    const MultiViewScene distorted(o, 5);
    double max_undistorted = 0.0, max_distortion = 0.0;
    std::vector<double> median_distortions, fit_residuals;
    for (int i = 0; i < distorted.NumImages(); ++i) {
      const MultiViewImage im = distorted.Render(i);
      std::vector<double> rel;
      Eigen::Matrix2d AtA = Eigen::Matrix2d::Zero();
      Eigen::Vector2d Atz = Eigen::Vector2d::Zero();
      std::vector<std::pair<double, double>> dz;
      for (size_t k = 0; k < im.prior.data.size(); ++k) {
        const double d = im.prior.data[k], u = im.prior_undistorted.data[k], z = im.prior_true_depth.data[k];
        ASSERT_TRUE(std::isfinite(d) && d > 0.0);
        if (z <= 0.0) continue;
        max_undistorted = std::max(max_undistorted, std::abs(im.prior_scale * u + im.prior_shift - z) / z);
        rel.push_back(std::abs(im.prior_scale * d + im.prior_shift - z) / z);
        // Relative least squares z ~ alpha d + beta (weights 1 / z).
        const Eigen::Vector2d row(d / z, 1.0 / z);
        AtA += row * row.transpose();
        Atz += row;
        dz.emplace_back(d, z);
      }
      const Eigen::Vector2d ab = AtA.ldlt().solve(Atz);
      double ss = 0.0;
      for (const auto& [d, z] : dz) ss += std::pow((ab[0] * d + ab[1] - z) / z, 2);
      fit_residuals.push_back(std::sqrt(ss / dz.size()));
      max_distortion = std::max(max_distortion, *std::max_element(rel.begin(), rel.end()));
      std::nth_element(rel.begin(), rel.begin() + rel.size() / 2, rel.end());
      median_distortions.push_back(rel[rel.size() / 2]);
    }
    std::sort(median_distortions.begin(), median_distortions.end());
    std::sort(fit_residuals.begin(), fit_residuals.end());
    std::printf(
        "[%s] distortion 0.03: undistorted max rel error %.2e; |a d + b - z| / z: per-image medians "
        "%.2f%%-%.2f%%, max %.2f%%; RMS relative residual of the best affine fit %.2f%%-%.2f%%\n",
        MultiViewSceneTypeName(type), max_undistorted, 100 * median_distortions.front(),
        100 * median_distortions.back(), 100 * max_distortion, 100 * fit_residuals.front(), 100 * fit_residuals.back());
    EXPECT_LT(max_undistorted, 1e-5);
    EXPECT_LT(max_distortion, 0.2);
    EXPECT_LT(median_distortions.back(), 0.1);
    EXPECT_GT(fit_residuals.front(), 0.002) << "the distortion must not be affine";
  }
}

// Texture everywhere: nearly every 16 x 16 block that sees a surface has visible grey-level contrast.
TEST(MultiViewScene, SurfacesAreTextured) {
  for (const MultiViewSceneType type : kTypes) {
    MultiViewSceneOptions o;
    o.scene = type;
    o.num_images = 8;
    const MultiViewScene scene(o, 1);
    int blocks = 0, textured = 0;
    for (const int i : {0, 7}) {
      const MultiViewImage im = scene.Render(i);
      for (int by = 0; by + 16 <= im.camera.height; by += 16) {
        for (int bx = 0; bx + 16 <= im.camera.width; bx += 16) {
          double sum = 0, sum2 = 0;
          bool sky = false;
          for (int y = by; y < by + 16; ++y) {
            for (int x = bx; x < bx + 16; ++x) {
              sky |= im.depth.At(x, y) <= 0.0f;
              const uint8_t* px = &im.rgb[(static_cast<size_t>(y) * im.camera.width + x) * 3];
              const double g = 0.299 * px[0] + 0.587 * px[1] + 0.114 * px[2];
              sum += g, sum2 += g * g;
            }
          }
          if (sky) continue;
          ++blocks;
          const double mean = sum / 256;
          textured += std::sqrt(std::max(0.0, sum2 / 256 - mean * mean)) > 4.0;
        }
      }
    }
    std::printf("[%s] %.1f%% of %d surface blocks (16 x 16) have grey std. dev. > 4\n", MultiViewSceneTypeName(type),
                100.0 * textured / blocks, blocks);
    EXPECT_GT(textured, 0.95 * blocks);
  }
}

// A straight 8-image walk of the room (sideways or forward) whose length is baseline_fraction x the distance to the
// target, which is drawn in [3.3, 3.7] m.
MultiViewScene StraightWalk(MultiViewMotion motion, double baseline_fraction, uint64_t seed) {
  MultiViewSceneOptions o = SmallOptions(MultiViewSceneType::kRoom, 160, 120);
  o.num_images = 8;
  o.motion = motion;
  o.baseline_fraction = baseline_fraction;
  MultiViewScene walk(o, seed);
  const double length = (walk.Camera(7).Center() - walk.Camera(0).Center()).norm();
  EXPECT_GT(length, baseline_fraction * 3.3 * 0.95);
  EXPECT_LT(length, baseline_fraction * 3.7 * 1.05);
  return walk;
}

// Issue 14's hard motions: a sideways walk of baseline_fraction x the distance with parallel views, hand-held
// centres inside a ball of that diameter, and per-image focal lengths in the requested FOV range that leave the
// scene and the poses of the seed unchanged.
TEST(MultiViewScene, SidewaysHandheldAndPerImageFocal) {
  for (uint64_t seed : {0, 1, 2}) {
    const MultiViewScene walk = StraightWalk(MultiViewMotion::kSideways, 0.08, seed);
    MultiViewSceneOptions o = SmallOptions(MultiViewSceneType::kRoom, 160, 120);
    for (int i = 0; i < 8; ++i) {
      const Eigen::Vector3d z0 = walk.Camera(0).R.row(2).transpose(), zi = walk.Camera(i).R.row(2).transpose();
      EXPECT_LT(std::acos(std::clamp(z0.dot(zi), -1.0, 1.0)) * 180.0 / M_PI, 3.0) << "views stay parallel";
    }
    o.motion = MultiViewMotion::kHandheld;
    o.baseline_fraction = 0.06;
    o.num_images = 5;
    const MultiViewScene hand(o, seed);
    for (int i = 0; i < 5; ++i) {
      for (int j = i + 1; j < 5; ++j) {
        EXPECT_LE((hand.Camera(i).Center() - hand.Camera(j).Center()).norm(), 0.06 * 3.7 + 1e-9);
      }
    }
    MultiViewSceneOptions arc = SmallOptions(MultiViewSceneType::kRoom, 160, 120);
    const MultiViewScene shared(arc, seed);
    arc.per_image_fov_min_deg = 85.0;
    arc.per_image_fov_max_deg = 100.0;
    const MultiViewScene per_image(arc, seed);
    std::vector<double> focals;
    for (int i = 0; i < per_image.NumImages(); ++i) {
      const double fov = 2.0 * std::atan(0.5 * 160 / per_image.Camera(i).focal) * 180.0 / M_PI;
      EXPECT_GE(fov, 85.0 - 1e-9);
      EXPECT_LE(fov, 100.0 + 1e-9);
      focals.push_back(per_image.Camera(i).focal);
      EXPECT_TRUE(per_image.Camera(i).R.isApprox(shared.Camera(i).R));
      EXPECT_TRUE(per_image.Camera(i).t.isApprox(shared.Camera(i).t));
    }
    std::sort(focals.begin(), focals.end());
    EXPECT_GT(focals.back() / focals.front(), 1.02) << "the focals differ per image";
  }
  MultiViewSceneOptions bad;
  bad.scene = MultiViewSceneType::kStreet;
  bad.motion = MultiViewMotion::kForward;
  EXPECT_THROW(bad.Check(), std::invalid_argument);
  bad.motion = MultiViewMotion::kSideways;
  EXPECT_THROW(bad.Check(), std::invalid_argument);
  bad = MultiViewSceneOptions();
  bad.per_image_fov_min_deg = 90.0;
  bad.per_image_fov_max_deg = 80.0;
  EXPECT_THROW(bad.Check(), std::invalid_argument);
}

// Forward motion: a straight walk of baseline_fraction x the distance along the viewing direction, so that the
// epipole of every pair lies near the image centre and the points ahead have small triangulation angles.
TEST(MultiViewScene, ForwardWalkLooksAlongItsPath) {
  for (uint64_t seed : {0, 1, 2}) {
    const MultiViewScene walk = StraightWalk(MultiViewMotion::kForward, 0.2, seed);
    const Eigen::Vector3d c0 = walk.Camera(0).Center(), c7 = walk.Camera(7).Center();
    for (int i = 0; i < 8; ++i) {
      const MultiViewCamera& cam = walk.Camera(i);
      // The end of the walk seen from camera i (i < 7) or its start seen from camera 7: the epipole of the pair.
      const Eigen::Vector3d other = i < 7 ? c7 : c0;
      const Eigen::Vector3d dir = (i < 7 ? 1.0 : -1.0) * (other - cam.Center()).normalized();
      const Eigen::Vector3d axis = cam.R.row(2).transpose();
      // Heading along the walk (within the +-1 degree jitter); the pitch towards the target's height (about 8
      // degrees down) keeps the epipole in the upper half of the image.
      const Eigen::Vector3d along = (c7 - c0).normalized();
      const Eigen::Vector2d heading = axis.head<2>().normalized(), path = along.head<2>().normalized();
      EXPECT_LT(std::acos(std::clamp(heading.dot(path), -1.0, 1.0)) * 180.0 / M_PI, 3.0) << "camera " << i;
      EXPECT_LT(std::acos(std::clamp(axis.dot(along), -1.0, 1.0)) * 180.0 / M_PI, 15.0) << "camera " << i;
      Eigen::Vector2d epipole;
      double depth = 0.0;
      ASSERT_TRUE(cam.Project(cam.Center() + dir, &epipole, &depth));
      EXPECT_TRUE(cam.InImage(epipole)) << "camera " << i << ": " << epipole.transpose();
    }
  }
}

}  // namespace
}  // namespace madsfm
