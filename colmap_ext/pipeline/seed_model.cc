#include "colmap_ext/pipeline/seed_model.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <array>
#include <map>
#include <stdexcept>

#include "colmap_ext/depth/keypoint_depths.h"
#include "colmap_ext/model/reconstruction.h"
#include "madsfm/geometry/triangulation.h"

namespace madsfm {
namespace {

struct Candidate {
  colmap::MadsfmPairRow row;
  double tri_angle_deg = 0.0;
  double score = -1.0;
  bool depth_backed = false;
};

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// The corrected priors of one inlier match expressed as depths along the ray of image 1: image 1's own corrected
// prior (d1 + shift1) and image 2's (scale (d2 + shift2)) carried into camera 1 along image 2's ray. False when a
// prior is missing or a corrected depth is not positive.
bool PriorDepthsInCamera1(const colmap::MadsfmPairRow& row, double d1, double d2, const Eigen::Vector2d& x2,
                          double* z_from_1, double* z_from_2) {
  if (!(d1 > 0.0) || !(d2 > 0.0)) return false;
  *z_from_1 = d1 + row.shift1;
  const double z2 = row.scale * (d2 + row.shift2);
  if (!(*z_from_1 > 0.0) || !(z2 > 0.0)) return false;
  *z_from_2 = (row.R.transpose() * (z2 * x2.homogeneous() - row.t)).z();
  return *z_from_2 > 0.0 && std::isfinite(*z_from_1) && std::isfinite(*z_from_2);
}

}  // namespace

SeedModelSummary RunSeedModelImpl(const SeedModelOptions& options) {
  auto db = colmap::Database::Open(options.database_path, /*read_only=*/true);
  std::map<colmap::camera_t, colmap::Camera> cameras;
  for (const auto& c : db->ReadCameras()) cameras[c.camera_id] = c;
  std::map<colmap::image_t, colmap::Image> images;
  for (const auto& im : db->ReadImages()) images[im.image_id] = im;

  std::vector<Candidate> candidates;
  for (const auto& row : db->ReadMadsfmPairs()) {
    if (row.status == 0 && row.num_inliers >= options.min_num_inliers) candidates.push_back({row});
  }
  if (candidates.empty()) {
    throw std::runtime_error("database '" + options.database_path + "': no pair estimated by two_view_estimator has " +
                             std::to_string(options.min_num_inliers) + " inliers; run two_view_estimator first");
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const Candidate& a, const Candidate& b) { return a.row.num_inliers > b.row.num_inliers; });
  if (static_cast<int>(candidates.size()) > options.num_candidates) candidates.resize(options.num_candidates);

  // Normalised, undistorted keypoints with the database's current intrinsics (after focal_estimator).
  std::map<colmap::image_t, std::vector<Eigen::Vector2d>> keypoints, normalized;
  std::map<colmap::image_t, std::vector<double>> depths;  // priors at the keypoints (NaN: none), with depth_path
  const bool use_depth = !options.depth_path.empty() && options.min_depth_tri_angle_deg > 0.0 &&
                         options.min_depth_tri_angle_deg < options.min_tri_angle_deg;
  const colmap::DepthType depth_type = colmap::ParseDepthType(options.depth_type);
  auto load = [&](colmap::image_t id) {
    if (keypoints.count(id)) return;
    keypoints[id] = db->ReadKeypoints(id);
    const auto& cam = cameras.at(images.at(id).camera_id).intrinsics;
    auto& n = normalized[id];
    for (const auto& kp : keypoints[id]) n.push_back(colmap::ImageToCamera(cam, kp));
    if (use_depth) {
      depths[id] = colmap::LoadKeypointDepths(options.depth_path, images.at(id).name, cam.width, cam.height,
                                              keypoints[id], depth_type)
                       .depth;
    }
  };
  auto prior_depths = [&](const colmap::MadsfmPairRow& row, colmap::image_t a, colmap::image_t b,
                          const std::array<uint32_t, 2>& m, double* z_from_1, double* z_from_2) {
    return use_depth && PriorDepthsInCamera1(row, depths[a][m[0]], depths[b][m[1]], normalized[b][m[1]], z_from_1,
                                             z_from_2);
  };

  Candidate* best = nullptr;
  std::vector<std::array<uint32_t, 2>> best_inliers;
  for (Candidate& c : candidates) {
    colmap::image_t i1, i2;
    colmap::PairIdToImagePair(c.row.pair_id, &i1, &i2);
    load(i1);
    load(i2);
    const auto geometry = db->ReadTwoViewGeometry(c.row.pair_id);
    if (!geometry) continue;
    std::vector<double> angles;
    for (const auto& m : geometry->inlier_matches) {
      const Eigen::Vector3d r1 = normalized[i1][m[0]].homogeneous().normalized();
      const Eigen::Vector3d r2 = c.row.R.transpose() * normalized[i2][m[1]].homogeneous().normalized();
      double z1, z2;
      if (!TriangulateDepths(c.row.R, c.row.t, normalized[i1][m[0]], normalized[i2][m[1]], &z1, &z2)) continue;
      if (z1 <= 0 || z2 <= 0) continue;
      angles.push_back(std::acos(std::clamp(r1.dot(r2), -1.0, 1.0)) * 180.0 / M_PI);
    }
    c.tri_angle_deg = Median(angles);
    if (c.tri_angle_deg < options.min_tri_angle_deg) {
      // Low parallax: usable only when the depth priors carry the structure.
      const int depth_inliers = std::min(c.row.num_inliers_reproj1, c.row.num_inliers_reproj2);
      // depth_observable 0: the estimator said the pair does not determine scale and shifts (-1: a row written
      // before madsfm stored it, judged by its depth inliers alone).
      if (!use_depth || c.row.method != 0 || c.row.depth_observable == 0 ||
          c.tri_angle_deg < options.min_depth_tri_angle_deg ||
          depth_inliers < options.min_depth_inlier_ratio * c.row.num_inliers) {
        continue;
      }
      int with_priors = 0;
      double za, zb;
      for (const auto& m : geometry->inlier_matches) with_priors += prior_depths(c.row, i1, i2, m, &za, &zb);
      if (with_priors < options.min_num_inliers) continue;
      c.depth_backed = true;
    }
    const double depth_ratio =
        c.row.num_inliers > 0
            ? std::min(1.0, 0.5 * (c.row.num_inliers_reproj1 + c.row.num_inliers_reproj2) / c.row.num_inliers)
            : 0.0;
    // Many inliers, a good triangulation angle (saturating at 16 deg, COLMAP's init_min_tri_angle), and depth
    // priors that agree with the pose (a consistent scale): all three make a stable seed.
    c.score = c.row.num_inliers * std::min(1.0, c.tri_angle_deg / 16.0) * (0.5 + 0.5 * depth_ratio);
    if (!best || c.score > best->score) {
      best = &c;
      best_inliers = geometry->inlier_matches;
    }
  }
  if (!best) {
    char angles[160];
    if (use_depth) {
      std::snprintf(angles, sizeof(angles),
                    "a median triangulation angle of at least %g deg (%g deg with depth priors that agree with the "
                    "pose)",
                    options.min_tri_angle_deg, options.min_depth_tri_angle_deg);
    } else {
      std::snprintf(angles, sizeof(angles), "a median triangulation angle of at least %g deg",
                    options.min_tri_angle_deg);
    }
    throw std::runtime_error("database '" + options.database_path + "': no estimated pair has " + angles +
                             " among the " + std::to_string(candidates.size()) + " pairs with the most inliers");
  }

  colmap::image_t i1, i2;
  colmap::PairIdToImagePair(best->row.pair_id, &i1, &i2);
  const colmap::Image& im1 = images.at(i1);
  const colmap::Image& im2 = images.at(i2);
  colmap::Reconstruction model;
  for (colmap::camera_t cid : {im1.camera_id, im2.camera_id}) {
    model.cameras[cid] = colmap::ModelCamera{cid, cameras.at(cid).intrinsics};
  }
  const Eigen::Matrix3d& R = best->row.R;
  const Eigen::Vector3d& t = best->row.t;
  for (const colmap::Image* im : {&im1, &im2}) {
    colmap::ModelImage mi;
    mi.image_id = im->image_id;
    mi.camera_id = im->camera_id;
    mi.name = im->name;
    mi.points2D = keypoints[im->image_id];
    mi.point3D_ids.assign(mi.points2D.size(), colmap::kInvalidPoint3DId);
    if (im == &im2) {
      mi.qvec = colmap::RotationToQuaternion(R);
      mi.tvec = t;
    }
    model.images[im->image_id] = mi;
  }
  const auto& cam1 = cameras.at(im1.camera_id).intrinsics;
  const auto& cam2 = cameras.at(im2.camera_id).intrinsics;
  // Depth-backed seed: the relative spread of one corrected prior, from how the two views' priors disagree
  // (robust: 1.4826 MAD of the log ratio, over sqrt(2) for one prior), at least 2% (errors common to both views,
  // such as those of the pair's scale and shifts, do not show in the disagreement).
  double prior_sigma = 0.0;
  if (best->depth_backed) {
    std::vector<double> log_ratio;
    double za, zb;
    for (const auto& m : best_inliers) {
      if (prior_depths(best->row, i1, i2, m, &za, &zb)) log_ratio.push_back(std::log(za / zb));
    }
    const double med = Median(log_ratio);
    for (double& r : log_ratio) r = std::abs(r - med);
    prior_sigma = std::max(0.02, 1.4826 * Median(log_ratio) / std::sqrt(2.0));
  }
  const double focal1 = 0.5 * (cam1.FocalX() + cam1.FocalY());
  int s_fused = 0;  // fused points kept in the model
  uint64_t next_id = 1;
  for (const auto& m : best_inliers) {
    double z1 = 0.0, z2 = 0.0;
    const bool triangulated =
        TriangulateDepths(R, t, normalized[i1][m[0]], normalized[i2][m[1]], &z1, &z2) && z1 > 0 && z2 > 0;
    double za, zb;
    const bool fuse = best->depth_backed && prior_depths(best->row, i1, i2, m, &za, &zb);
    if (fuse) {
      // Inverse-variance fusion in log depth: the mean of the two corrected priors (relative sigma prior_sigma /
      // sqrt(2)) and, when the rays meet in front of both cameras, the triangulation (relative sigma
      // sqrt(2) keypoint_sigma / (f angle)).
      const double log_prior = 0.5 * (std::log(za) + std::log(zb));
      const double var_prior = 0.5 * prior_sigma * prior_sigma;
      double log_z = log_prior;
      if (triangulated) {
        const Eigen::Vector3d r1 = normalized[i1][m[0]].homogeneous().normalized();
        const Eigen::Vector3d r2 = R.transpose() * normalized[i2][m[1]].homogeneous().normalized();
        const double angle = std::acos(std::clamp(r1.dot(r2), -1.0, 1.0));
        const double sigma_tri = std::sqrt(2.0) * options.keypoint_sigma_px / (focal1 * std::max(angle, 1e-9));
        const double w_tri = 1.0 / (sigma_tri * sigma_tri), w_prior = 1.0 / var_prior;
        log_z = (w_tri * std::log(z1) + w_prior * log_prior) / (w_tri + w_prior);
      }
      z1 = std::exp(log_z);
    } else if (!triangulated) {
      continue;
    }
    const Eigen::Vector3d X = z1 * normalized[i1][m[0]].homogeneous();
    const Eigen::Vector3d X2 = R * X + t;
    if (X2.z() <= 0) continue;
    const double e1 = (colmap::CameraToImage(cam1, X.hnormalized()) - keypoints[i1][m[0]]).norm();
    const double e2 = (colmap::CameraToImage(cam2, X2.hnormalized()) - keypoints[i2][m[1]]).norm();
    if (!(e1 < options.max_reproj_error && e2 < options.max_reproj_error)) continue;
    if (model.images[i1].point3D_ids[m[0]] != colmap::kInvalidPoint3DId ||
        model.images[i2].point3D_ids[m[1]] != colmap::kInvalidPoint3DId) {
      continue;  // a keypoint in two matches: keep the first
    }
    if (fuse) ++s_fused;
    colmap::ModelPoint3D p;
    p.xyz = X;
    p.error = 0.5 * (e1 + e2);
    p.track = {{i1, m[0]}, {i2, m[1]}};
    model.points3D[next_id] = p;
    model.images[i1].point3D_ids[m[0]] = next_id;
    model.images[i2].point3D_ids[m[1]] = next_id;
    ++next_id;
  }
  colmap::WriteReconstructionBinary(model, options.output_path);

  SeedModelSummary s;
  s.image_id1 = i1;
  s.image_id2 = i2;
  s.name1 = im1.name;
  s.name2 = im2.name;
  s.num_inliers = best->row.num_inliers;
  s.num_points3D = static_cast<int>(model.points3D.size());
  s.median_tri_angle_deg = best->tri_angle_deg;
  s.score = best->score;
  s.depth_backed = best->depth_backed;
  s.num_fused_points = s_fused;
  s.prior_sigma = prior_sigma;
  return s;
}

}  // namespace madsfm
