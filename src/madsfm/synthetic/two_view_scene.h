// Synthetic two-view problems with monocular-depth-like priors, for the estimator tests and benchmarks.
//
// In: a SyntheticPairOptions (scene type, image size, camera setup, pose ranges, matches, outliers, pixel noise and
// how the depth priors are corrupted) and a 64-bit seed. Out: a SyntheticPair = the PairData an estimator sees
// (K0, K1, T_0to1, pixel matches p0/p1, one depth-prior map per view at a lower resolution than the image, image
// sizes) plus the ground truth (inlier mask, true 3-D points and depths of the inliers, the per-view affine
// parameters of the priors, focal lengths, rendered true depth maps, masks of the wildly wrong regions).
// Generation is deterministic for a seed (std::mt19937_64 with portable uniform/normal sampling, no global state)
// and takes a few milliseconds per pair.
//
// Scene. An analytic scene of planes and (yawed) boxes in a z-up world, ray cast exactly:
//  * indoor: a room 3.5-8 m x 3.5-8 m x 2.4-3.2 m (floor, ceiling, four walls) with crates, tables (top + legs)
//    and cabinets against the walls; cameras at 1.1-1.8 m height, depths ~0.5-10 m.
//  * outdoor: a ground plane, building blocks 15-100 m away, small street objects 4-30 m away and a distant
//    background (a vertical cylinder of radius 150-200 m, "hills"/treeline) with sky above; depths ~2-200 m.
// Cameras look at a random object / facade; camera 1 is displaced by a baseline of baseline_min..max times the
// median depth of view 0 (over a coarse 16 x 12 grid of rays) and looks at the same region, with an extra random
// yaw/tilt so that the relative rotation reaches max_rotation_deg; poses with less than min_overlap co-visible area,
// or where a view sees sky in more than half of the coarse grid, are redrawn. Presets that differ only in the prior
// corruption or in kCalibrated vs kSharedFocal give the same scene, cameras and matches for the same seed (paired
// comparisons).
//
// Conventions.
//  * Pixel centres are at integer coordinates: the image spans [-0.5, W - 0.5] x [-0.5, H - 0.5]. Depth-map pixel
//    (u, v) of a W' x H' map looks along the ray of image point ((u + 0.5) W / W' - 0.5, (v + 0.5) H / H' - 0.5),
//    the sampling rule of docs/design.md section 5. Depths are z-depths (along the optical axis), in metres.
//  * Cameras: x right, y down, z forward. T_0to1 = [R t; 0 1] maps camera 0 to camera 1: X1 = R X0 + t (metres).
//  * Priors (kDepth): for view i with true (metric) depth z, the noise-free prior is d = (z - b_i) / a_i, i.e.
//    z = a_i d + b_i (the paper's eq. 1). In AffineDepthPose terms (TrueModel()): shift0 = b0 / a0,
//    scale = a1 / a0, shift1 = b1 / a1 and t_model = t / a0. kDisparity: the map holds an affine-invariant
//    disparity s = (1 / z - b_i) / a_i, i.e. 1 / z = a_i s + b_i; inverting it does NOT give an affine depth.
//  * The priors are positive everywhere (sky included: MDE models predict a far value there); the rendered true
//    depth maps are 0 where a pixel sees no surface (sky).
//
// What each corruption of the priors models (all per view, independently, in this order, on the true depth z):
//  1. per-surface offsets: every planar surface (each wall, the floor, each box face, the ground, each facade)
//     gets its own small relative scale and additive depth offset. MDE models get the relative depth WITHIN an
//     object/surface right but the placement of objects/surfaces relative to each other less so; this is the
//     effect that makes different image regions prefer different shifts (paper, supplementary "limitations").
//  2. smooth non-affine distortion: a low-order polynomial plus one low-frequency sinusoid in image position
//     (multiplicative) and a monotone warp of the depth range, z * (1 + 2 gamma (r - 1) / (r + 1)) with
//     r = z / median. Models the global bending of planes, scene-layout bias and the compression/expansion of
//     the depth range that MDE outputs show after the best affine fit.
//  3. wildly wrong regions: a few blobs covering a small fraction of the map whose depth is multiplied by a factor
//     of 1.5-4 (or its inverse). Models mirrors, windows and glass, textureless or over-exposed regions and
//     object/sky confusions, where MDE output is simply wrong.
//  4. fine noise: small iid relative noise per map pixel (network output jitter).
//  5. the unknown affine transform per view (scale a_i log-uniform, shift b_i up to +-max_shift_fraction of the
//     median) into the model's output space (depth or disparity): affine-invariant training losses.
//  6. blur (Gaussian, in map pixels): MDE outputs are low-resolution and smooth, depth discontinuities are
//     smeared (flying pixels) so keypoints on object boundaries get mixed depths.
// The "bad prior" corruption (DepthPriorCorruption::Bad()) makes 2, 1 and 3 large so that priors are nearly
// useless and a point-only estimator should win. These corruptions are generic stand-ins for real MDE errors, not a
// model of any particular network: use them to exercise code paths and compare methods, and do not tune an
// estimator to their specific form (the project is evaluated on real data).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "madsfm/geometry/affine_depth_pose.h"
#include "madsfm/io/depth_map.h"
#include "madsfm/io/pair_directory.h"

namespace madsfm {

// kPlanar: a large empty room (10-20 m) whose camera 0 faces one wall from 1.5-5 m, level or looking down at the
// floor: the views see one dominant plane, often two (wall + floor), rarely three. The case that breaks point-only
// solvers (the planar ambiguity of the essential matrix) and makes the priors the tie-breaker.
enum class SyntheticSceneType { kIndoor, kOutdoor, kPlanar };

// kCalibrated: K0, K1 known to the estimator (one shared camera unless calibrated_same_camera = false).
// kSharedFocal: one camera (K0 == K1), focal unknown to the estimator. kTwoFocal: two cameras with independent
// focal lengths and principal points. PairData always carries the TRUE intrinsics; the setup says what an
// estimator should assume.
enum class SyntheticCameraSetup { kCalibrated, kSharedFocal, kTwoFocal };

// What the prior maps hold: affine-invariant depth, or affine-invariant disparity (inverse depth).
enum class SyntheticPriorType { kDepth, kDisparity };

// How the monocular-depth-like priors are corrupted (see the file comment for what each term models).
struct DepthPriorCorruption {
  SyntheticPriorType type = SyntheticPriorType::kDepth;
  // Unknown affine transform per view: a_i log-uniform in [min_scale, max_scale]; b_i uniform in
  // [-max_shift_fraction, +max_shift_fraction] * median (of the model's output quantity), with the upper end
  // lowered where needed so that every prior stays positive (as real MDE outputs are).
  double min_scale = 0.1;
  double max_scale = 10.0;
  double max_shift_fraction = 0.5;
  // Smooth non-affine distortion: typical relative magnitude of the image-position polynomial/sinusoid and of
  // the depth exponent gamma (uniform in +-distortion). 0 disables.
  double distortion = 0.03;
  // Per-surface relative scale (std. dev.) and additive offset (std. dev., fraction of the view's median depth).
  double surface_scale_sigma = 0.02;
  double surface_offset_sigma = 0.03;
  // Fraction of the map covered by wildly wrong regions (split into 1-3 elliptic blobs). 0 disables.
  double wild_region_fraction = 0.02;
  // Relative std. dev. of iid per-pixel noise.
  double noise = 0.005;
  // Gaussian blur std. dev. in depth-map pixels (0 disables).
  double blur_sigma_px = 1.0;
  // true: blur the logarithm of the prior (multiplicative smearing, as networks that regress log depth do).
  bool blur_log_depth = false;

  // Ranges drawn per view (each upper end used only when above the lower value above): distortion uniform in
  // [distortion, max_distortion], surface offset sigma uniform in [surface_offset_sigma, max_surface_offset_sigma].
  double max_distortion = 0.0;
  double max_surface_offset_sigma = 0.0;
  // > 0: the scale of view 1 is a_1 = a_0 * r with r log-uniform in [1 / max_scale_ratio, max_scale_ratio]
  // (instead of an independent draw): views whose depth scales differ by at most that factor.
  double max_scale_ratio = 0.0;
  // Share of pairs whose priors are nearly metric instead: a_i log-uniform in [0.8, 1.25], |b_i| <= 5% of the
  // median (both views of the pair).
  double metric_fraction = 0.0;

  // The defaults: a decent modern MDE model.
  static DepthPriorCorruption Typical() { return DepthPriorCorruption(); }
  // Only the affine transform (and its positivity): prior = (z - b) / a exactly. For tests.
  static DepthPriorCorruption AffineOnly();
  // Nearly useless priors: distortion 0.4, per-surface offsets 25% of the median, 20% wild regions, blur 3 px.
  static DepthPriorCorruption Bad();
};

struct SyntheticPairOptions {
  SyntheticSceneType scene = SyntheticSceneType::kIndoor;
  // Image size in pixels (both views); 0 = scene default (640 x 480 indoor, 1024 x 768 outdoor).
  int image_width = 0;
  int image_height = 0;
  // Depth-map size relative to the image (map size = round(image size * scale)); 0 = scene default
  // (1/2 indoor, 1/4 outdoor). Must be in (0, 1].
  double depth_map_scale = 0.0;

  SyntheticCameraSetup camera_setup = SyntheticCameraSetup::kCalibrated;
  bool calibrated_same_camera = true;  // kCalibrated only: false draws two cameras as kTwoFocal does
  // Horizontal field of view range (degrees) the focal lengths are drawn from, per camera; square pixels.
  double min_fov_deg = 50.0;
  double max_fov_deg = 100.0;
  // Principal point = image centre + uniform +-principal_point_jitter * (W, H).
  double principal_point_jitter = 0.02;

  // Relative pose: baseline uniform in [baseline_min, baseline_max] * median depth of view 0; relative rotation
  // angle at most max_rotation_deg (look-at plus a random extra yaw/tilt); camera roll within +-max_roll_deg;
  // at least min_overlap of view 0 (coarse grid of surface points) must be visible in view 1.
  double baseline_min = 0.05;
  double baseline_max = 0.30;
  double max_rotation_deg = 45.0;
  double max_roll_deg = 5.0;
  double min_overlap = 0.3;

  // Matches: num_matches in total, of which round(outlier_ratio * num_matches) are outliers, with outlier_ratio
  // uniform in [min_outlier_ratio, max_outlier_ratio] per pair (set both equal for a fixed ratio). Inliers are
  // co-visible scene points drawn uniformly over image 0 (occlusion checked by exact ray casting from camera 1). If
  // the views overlap too little to find enough inliers (not observed with the presets), fewer matches are
  // returned with the same outlier ratio.
  int num_matches = 500;
  // > num_matches: the number of matches is drawn per pair, uniform in [num_matches, max_num_matches].
  int max_num_matches = 0;
  // Share of the inliers whose keypoint in view 0 lies within one depth-map pixel of a depth discontinuity (a
  // jump of more than 5% between neighbouring map pixels), uniform in [min_edge_fraction, max_edge_fraction] per
  // pair: keypoints concentrate on object boundaries, where blurred priors mix foreground and background depth.
  double min_edge_fraction = 0.0;
  double max_edge_fraction = 0.0;
  double min_outlier_ratio = 0.1;
  double max_outlier_ratio = 0.6;
  // Share of the outliers that are mismatched features (p1 = projection of a different co-visible scene point);
  // the others are random pixels in image 1 for a scene point seen in image 0. Every outlier's p1 lies at least
  // outlier_min_offset_px from the true projection of its p0 (when that projection exists and the image is large
  // enough to allow it).
  double mismatch_fraction = 0.5;
  double outlier_min_offset_px = 20.0;
  // Gaussian pixel noise on p0 and p1 (each coordinate), truncated at 3 sigma; sigma uniform in
  // [min_pixel_noise, max_pixel_noise] per pair.
  double min_pixel_noise = 0.5;
  double max_pixel_noise = 1.0;

  DepthPriorCorruption prior;

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

struct SyntheticPair {
  // What an estimator sees. depth0/depth1 are the prior maps; T_0to1 is set; path = "synthetic:<seed>".
  PairData pair;

  // Ground truth per match (same order as pair.p0/p1). For inliers: points0 = true 3-D point in camera 0
  // (metres), true_depth0/1 = its z in camera 0/1, p0_clean/p1_clean = its exact projections (before noise). For
  // outliers these are 0 / the noise-free pixels that were drawn.
  std::vector<uint8_t> is_inlier;
  std::vector<Eigen::Vector3d> points0;
  std::vector<double> true_depth0, true_depth1;
  std::vector<Eigen::Vector2d> p0_clean, p1_clean;
  int num_inliers = 0;
  double outlier_ratio = 0.0;  // actual share of outliers
  double pixel_noise = 0.0;    // sigma used for this pair (pixels)

  // The priors' affine parameters (see the file comment): kDepth z = a d + b, kDisparity 1/z = a s + b.
  SyntheticPriorType prior_type = SyntheticPriorType::kDepth;
  double prior_scale0 = 1.0, prior_shift0 = 0.0;  // a_0, b_0
  double prior_scale1 = 1.0, prior_shift1 = 0.0;  // a_1, b_1

  SyntheticSceneType scene = SyntheticSceneType::kIndoor;
  SyntheticCameraSetup camera_setup = SyntheticCameraSetup::kCalibrated;
  double focal0 = 0.0, focal1 = 0.0;  // pixels (= K0(0,0), K1(0,0))
  double rotation_deg = 0.0;          // angle of R
  double baseline = 0.0;              // |C1 - C0| in metres (= |t|)
  double median_depth0 = 0.0, median_depth1 = 0.0;  // median of the valid true depth-map pixels

  // Rendered true z-depth at the prior maps' resolution (0 = sky), and the masks (1 = wildly wrong) of
  // corruption 3, row-major like DepthMap.
  DepthMap true_depth_map0, true_depth_map1;
  std::vector<uint8_t> wild_mask0, wild_mask1;

  // The ground-truth AffineDepthPose for kDepth priors: R, t / a0, scale a1 / a0, shifts b0 / a0, b1 / a1 and
  // f0, f1 = focal0, focal1 in pixels (use 1 when comparing with a model estimated in normalised coordinates).
  // For kDisparity priors inverted by the caller (D = 1 / s) the model is exact only if b_i = 0: it returns
  // scale a0 / a1, zero shifts and t * a0.
  AffineDepthPose TrueModel() const;
};

// One pair. Throws std::invalid_argument if options.Check() fails.
SyntheticPair GenerateTwoViewPair(const SyntheticPairOptions& options, uint64_t seed);

// count pairs; pair i uses a seed derived from (seed, i), so a set is a prefix of any larger set with the same seed.
std::vector<SyntheticPair> GenerateTwoViewSet(const SyntheticPairOptions& options, int count, uint64_t seed);

// Named presets (all with the defaults above unless said otherwise; outlier ratio 0.1-0.6, pixel noise 0.5-1 px):
//  * "indoor_calibrated":   indoor room, 640 x 480, depth maps 320 x 240, one calibrated camera, typical priors.
//  * "outdoor_calibrated":  outdoor street, 1024 x 768, depth maps 256 x 192, one calibrated camera, typical priors.
//  * "indoor_shared_focal": as indoor_calibrated, one camera whose focal is unknown (kSharedFocal).
//  * "indoor_two_focal":    as indoor_calibrated, two cameras with independent unknown focals (kTwoFocal).
//  * "outdoor_two_focal":   as outdoor_calibrated, two cameras with independent unknown focals (kTwoFocal).
//  * "indoor_bad_prior":    as indoor_calibrated with DepthPriorCorruption::Bad(): the point-only method should win.
// The "hard_*" presets (issue 12) vary everything per pair: 150-2000 matches, pixel noise 0.5-1.5 px, outliers
// 10-60%, horizontal FOV 50-100 deg, depth maps at half resolution, calibrated pairs with two different cameras,
// per-view depth scales within 2x of each other, half of the pairs with nearly metric priors (scale 0.8-1.25),
// smooth distortion 2-10%, per-surface offsets 1-5% of the median depth, blur in log depth, 3-15% of the keypoints
// at depth edges:
//  * "hard_indoor_calibrated", "hard_outdoor_calibrated", "hard_planar_calibrated" (one or two planes),
//  * "hard_indoor_shared_focal", "hard_outdoor_shared_focal", "hard_planar_shared_focal",
//  * "hard_indoor_two_focal", "hard_outdoor_two_focal",
//  * "hard_low_parallax_calibrated", "hard_low_parallax_shared_focal": indoor, baseline 0.5-3% of the median depth.
// Returns std::nullopt for an unknown name.
std::optional<SyntheticPairOptions> SyntheticPairPreset(const std::string& name);
std::vector<std::string> SyntheticPairPresetNames();

}  // namespace madsfm
