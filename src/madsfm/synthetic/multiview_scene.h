// Synthetic multi-view scenes rendered by ray casting, for the end-to-end COLMAP demo (`madsfm render_scene`).
//
// In: a MultiViewSceneOptions (scene type, number of images, image size, field of view, prior corruption) and a
// 64-bit seed. Out: a MultiViewScene that holds the analytic scene and the cameras (fast to build) and renders,
// per image on demand, a MultiViewImage: an 8-bit RGB image with dense, non-repetitive procedural texture (for
// SIFT), the exact z-depth map at full resolution and a monocular-depth-like prior at a lower resolution. Every
// output is deterministic for a seed (portable sampling on std::mt19937_64 and integer hashing, no global state;
// rendering splits rows over threads but each pixel is a pure function of the scene).
//
// Scenes (z-up world, metres):
//  * kRoom: a closed room (about 8 m x 7 m x 3 m) with cabinets against the far wall and crates (some stacked) in
//    the middle. The cameras stand near the near wall on an arc of 60 degrees around a point in the room, all
//    looking at it (with small jitter of height, aim and roll); depths ~1-7 m.
//  * kStreet: a street with building blocks on both sides, a closing building far ahead, parked cars and poles
//    on a textured ground, and an untextured sky. The cameras walk 7 m along the street looking across it at
//    the facades (and a little forward); depths ~3-60 m, sky where the rays hit nothing.
// Neighbouring images overlap by far more than 50% for every supported num_images (8-15 is the intended range).
//
// Textures: every planar face (each wall, box face, facade, the floor, the ground) gets its own palette and a
// sum of layers evaluated analytically in face coordinates (metres): multi-octave gradient noise, random
// elliptic blobs, letter-like glyphs made of strokes, rare small stripe patches and a fine multiplicative grain
// over everything, all placed by hashing cells (no repetition). Each layer is pre-filtered with the footprint of
// the pixel on the surface (octaves and strokes finer than the footprint fade to their mean), and every pixel
// averages supersampling^2 rays, so there is no aliasing. Shading is Lambertian with a fixed light (view-independent,
// consistent across images).
//
// Conventions.
//  * Pixel coordinates follow COLMAP: the upper-left pixel's centre is at (0.5, 0.5); the image spans [0, W] x
//    [0, H]; the principal point is the image centre (W / 2, H / 2); square pixels, one focal length f (pixels)
//    shared by all images, no distortion.
//  * Cameras: x right, y down, z forward; world -> camera x_cam = R x_world + t.
//  * Depth maps are z-depths (metres), row-major (DepthMap), 0 where a pixel sees no surface (sky). Full
//    resolution pixel (x, y) holds the depth of the ray through (x + 0.5, y + 0.5). A W' x H' map pixel (u, v)
//    holds the depth of the ray through ((u + 0.5) W / W', (v + 0.5) H / H'), which is the sampling rule of
//    docs/design.md section 5.
//  * Prior: with the exact depth z at a prior-map pixel at image position (x, y), the distorted depth is
//    z' = z (1 + delta(x, y)) (1 + 2 gamma (r - 1) / (r + 1)), r = z / median (delta: a smooth low-order
//    polynomial plus one low-frequency sinusoid of the normalised image position, gamma: a monotone warp of the
//    depth range, both of magnitude ~prior_distortion), and the stored prior is d = (z' - b) / a with an unknown
//    per-image scale a and shift b (z' = a d + b, the paper's eq. 1). Where there is no surface (sky) the prior
//    holds the value of z = 2 x the largest depth of the map (an MDE model predicts "far" there). Every prior
//    value is positive. With prior_distortion = 0, a d + b reproduces the exact depth (to float precision).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "madsfm/io/depth_map.h"

namespace madsfm {

enum class MultiViewSceneType { kRoom, kStreet };

// How the cameras move (kRoom only; the street always walks along the street).
//  * kArc: the default 60-degree arc around the target (see above).
//  * kSideways: a straight walk across the viewing direction at the arc's distance d from the target, all cameras
//    looking the same way (+-1 degree jitter); the whole path is baseline_fraction x d long (low parallax: 0.05-0.1).
//  * kHandheld: small hand-held motion: camera centres uniform in a ball of radius baseline_fraction x d / 2 around
//    the arc's middle position, each aimed at the target with up to 3 degrees of aim jitter and 5 degrees of roll.
//  * kForward: a straight, level walk towards the target from the arc's middle position, all cameras heading along
//    the walk (+-1 degree jitter) and pitched towards the target's height (a few degrees down); the path is
//    baseline_fraction x d long (0.1-0.3: the epipoles are in the images and most points have small triangulation
//    angles).
enum class MultiViewMotion { kArc, kSideways, kHandheld, kForward };

struct MultiViewSceneOptions {
  MultiViewSceneType scene = MultiViewSceneType::kRoom;
  int num_images = 10;  // >= 2
  int image_width = 640;
  int image_height = 480;
  // Horizontal field of view in degrees; 0 draws it uniformly in [60, 70] from the seed.
  double fov_deg = 0.0;
  MultiViewMotion motion = MultiViewMotion::kArc;
  double baseline_fraction = 0.08;  // kSideways, kHandheld, kForward: see MultiViewMotion
  // > 0: every image has its own focal length, from a horizontal field of view drawn uniformly in
  // [per_image_fov_min_deg, per_image_fov_max_deg] (a separate random stream: the scene and poses do not change).
  double per_image_fov_min_deg = 0.0;
  double per_image_fov_max_deg = 0.0;
  // Rays per pixel along each axis (1 = one ray through the pixel centre).
  int supersampling = 2;
  // Prior-map size = round(image size * depth_map_scale), in (0, 1].
  double depth_map_scale = 0.5;
  // Magnitude of the smooth non-affine prior distortion (0 disables; 0.03 = a few percent).
  double prior_distortion = 0.03;
  // Unknown affine transform of the priors: a log-uniform in [prior_min_scale, prior_max_scale], b uniform in
  // +-prior_max_shift_fraction x the median distorted depth (kept below the smallest depth so d > 0).
  double prior_min_scale = 0.2;
  double prior_max_scale = 5.0;
  double prior_max_shift_fraction = 0.3;
  // Threads used by Render (0 = std::thread::hardware_concurrency()).
  int num_threads = 0;

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

// A pinhole camera in COLMAP pixel coordinates (see the file comment).
struct MultiViewCamera {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // world -> camera rotation
  Eigen::Vector3d t = Eigen::Vector3d::Zero();      // world -> camera translation
  double focal = 1.0;                               // pixels
  double cx = 0.0, cy = 0.0;                        // principal point (pixels)
  int width = 0, height = 0;

  Eigen::Vector3d Center() const { return -R.transpose() * t; }
  // World direction of the ray through image point (x, y), scaled so that its ray parameter is the z-depth.
  Eigen::Vector3d RayDirection(double x, double y) const;
  // Projects a world point; false if it is not in front of the camera (z <= 1e-9). *depth = its z in the camera.
  bool Project(const Eigen::Vector3d& X, Eigen::Vector2d* pixel, double* depth) const;
  bool InImage(const Eigen::Vector2d& p) const {
    return p.x() >= 0.0 && p.y() >= 0.0 && p.x() <= width && p.y() <= height;
  }
};

struct MultiViewImage {
  std::string name;  // "img_000.png", ...
  MultiViewCamera camera;
  std::vector<uint8_t> rgb;    // width * height * 3, row-major, interleaved R, G, B
  DepthMap depth;              // exact z-depth at full resolution (0 = sky)
  DepthMap prior;              // the prior (see the file comment), prior resolution
  DepthMap prior_true_depth;   // exact z-depth at the prior pixels (0 = sky)
  DepthMap prior_undistorted;  // (z - b) / a at the prior pixels: the prior without the non-affine distortion
  double prior_scale = 1.0;    // a: z' = a d + b
  double prior_shift = 0.0;    // b
  double median_depth = 0.0;   // median of the valid prior_true_depth pixels
};

class MultiViewScene {
 public:
  // Builds the scene and the cameras (milliseconds). Throws std::invalid_argument if options.Check() fails.
  MultiViewScene(const MultiViewSceneOptions& options, uint64_t seed);
  ~MultiViewScene();
  MultiViewScene(MultiViewScene&&) noexcept;
  MultiViewScene& operator=(MultiViewScene&&) noexcept;

  const MultiViewSceneOptions& options() const;
  int NumImages() const;
  const MultiViewCamera& Camera(int image) const;
  double Focal() const;                     // shared focal length (pixels); per-image focals: Camera(i).focal
  static std::string ImageName(int image);  // "img_000.png"

  // First surface hit along origin + s * direction (s > 0); false if none (sky). *s in units of |direction|.
  bool CastRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double* s) const;
  // Exact z-depth of the ray of camera `image` through image point (x, y) (COLMAP coordinates); 0 if none.
  double DepthAt(int image, double x, double y) const;

  // Renders one image with its depth map and prior (about 2 s of CPU at 640 x 480 with 2 x 2 supersampling;
  // rows are split over options().num_threads threads).
  MultiViewImage Render(int image) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

const char* MultiViewSceneTypeName(MultiViewSceneType type);  // "room", "street"
const char* MultiViewMotionName(MultiViewMotion motion);      // "arc", "sideways", "handheld", "forward"

}  // namespace madsfm
