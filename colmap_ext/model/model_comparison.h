// Compares a COLMAP sparse model with ground-truth camera poses and focal lengths (what `madsfm model_compare`
// prints). In: a Reconstruction and a GroundTruth (images matched by name). Out: counts of images / pairs / points
// and the rotation, translation-direction and focal errors defined below.
//
// Ground-truth JSON (ReadGroundTruthJson / WriteGroundTruthJson):
//   {"images": [{"name": "img_000.png", "R": [9 numbers, row-major], "t": [3 numbers], "f": focal_px}, ...]}
// R, t map world to camera: x_cam = R x_world + t (COLMAP's convention). "f" is optional (focal errors are then
// not computed for that image); when present it must be a positive number.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "colmap_ext/model/reconstruction.h"

namespace madsfm::colmap {

struct GroundTruthImage {
  std::string name;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // world -> camera rotation
  Eigen::Vector3d t = Eigen::Vector3d::Zero();      // world -> camera translation
  double focal = std::numeric_limits<double>::quiet_NaN();  // pixels; NaN: unknown
};

struct GroundTruth {
  std::vector<GroundTruthImage> images;
};

// Throws std::runtime_error naming `path` and the problem (missing file, bad JSON, a field of the wrong type or
// size, R not a rotation within 1e-6, non-positive focal, duplicate names).
GroundTruth ReadGroundTruthJson(const std::string& path);
// Writes with full double precision (17 significant digits); images without a known focal get no "f".
void WriteGroundTruthJson(const GroundTruth& ground_truth, const std::string& path);

// Errors of one pair of registered images (i before j in ground-truth order).
struct PairError {
  std::string name_i, name_j;
  double rot_err_deg = 0.0;    // angle of (R_i R_j^T) (R_i,gt R_j,gt^T)^T
  double trans_err_deg = 0.0;  // see ModelComparison; NaN when the ground-truth baseline is zero
};

struct ModelComparison {
  int num_gt_images = 0;
  int num_model_images = 0;             // images in the model (all of them are registered in COLMAP's sense)
  int num_registered = 0;               // ground-truth images present in the model (matched by name)
  int num_model_images_not_in_gt = 0;   // model images whose name the ground truth does not list (ignored)
  std::vector<std::string> unregistered_names;  // ground-truth images missing from the model

  // Over all unordered pairs of registered images.
  int num_pairs = 0;
  double median_rot_err_deg = std::numeric_limits<double>::quiet_NaN();
  double max_rot_err_deg = std::numeric_limits<double>::quiet_NaN();
  // Relative-translation direction, no alignment: for a pair (i, j) the angle between the model's and the ground
  // truth's t_ij = t_j - R_j R_i^T t_i (= R_j (c_i - c_j), the baseline seen from camera j), full angle in
  // [0, 180] (the sign is known in a reconstruction); the larger of this and the same angle for t_ji (seen from
  // camera i), so the error does not depend on the pair's order (the two agree when the relative rotation is
  // exact). Invariant to a similarity transform of the model. Pairs whose ground-truth baseline is zero (relative
  // to the scene size) are skipped; a zero model baseline counts as 180 degrees.
  int num_trans_pairs = 0;
  double median_trans_err_deg = std::numeric_limits<double>::quiet_NaN();
  double max_trans_err_deg = std::numeric_limits<double>::quiet_NaN();
  std::vector<PairError> pair_errors;

  // |f - f_gt| / f_gt over registered images with a known ground-truth focal; f is the model camera's focal
  // (f, or the mean of fx and fy for models with two focals; images whose camera has no focal length are skipped).
  int num_focal = 0;
  double median_focal_err = std::numeric_limits<double>::quiet_NaN();
  double max_focal_err = std::numeric_limits<double>::quiet_NaN();

  int num_points3D = 0;
  double mean_reproj_error = std::numeric_limits<double>::quiet_NaN();  // mean of the points3D error fields
};

// Throws std::runtime_error if the model has two images with the same name or an image whose camera is missing.
ModelComparison CompareToGroundTruth(const Reconstruction& model, const GroundTruth& ground_truth);

}  // namespace madsfm::colmap
