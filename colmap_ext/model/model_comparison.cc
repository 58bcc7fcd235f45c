#include "colmap_ext/model/model_comparison.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "madsfm/geometry/pose_error.h"
#include "madsfm/io/json_writer.h"

namespace madsfm::colmap {
namespace {

using json = nlohmann::json;

constexpr double kRadToDeg = 180.0 / M_PI;

[[noreturn]] void Fail(const std::string& path, const std::string& message) {
  throw std::runtime_error(path + ": " + message);
}

std::vector<double> NumberArray(const json& entry, const char* key, size_t size, const std::string& path,
                                const std::string& where) {
  if (!entry.contains(key)) Fail(path, where + ": missing \"" + key + "\"");
  const json& value = entry.at(key);
  if (!value.is_array() || value.size() != size) {
    Fail(path, where + ": \"" + key + "\" must be an array of " + std::to_string(size) + " numbers");
  }
  std::vector<double> out;
  for (const json& v : value) {
    if (!v.is_number()) {
      Fail(path, where + ": \"" + key + "\" must be an array of " + std::to_string(size) + " numbers");
    }
    out.push_back(v.get<double>());
    if (!std::isfinite(out.back())) Fail(path, where + ": \"" + key + "\" holds a non-finite number");
  }
  return out;
}

double Median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  const size_t n = v.size();
  std::nth_element(v.begin(), v.begin() + n / 2, v.end());
  const double upper = v[n / 2];
  if (n % 2 == 1) return upper;
  const double lower = *std::max_element(v.begin(), v.begin() + n / 2);
  return 0.5 * (lower + upper);
}

double Max(const std::vector<double>& v) { return v.empty() ? std::nan("") : *std::max_element(v.begin(), v.end()); }

// Full angle between two directions in [0, 180]; a zero or non-finite vector gives 180.
double DirectionAngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  if (!a.allFinite() || !b.allFinite()) return 180.0;
  const double na = a.norm(), nb = b.norm();
  if (!(na > 0.0) || !(nb > 0.0)) return 180.0;
  const Eigen::Vector3d ua = a / na, ub = b / nb;
  const double angle = std::atan2(ua.cross(ub).norm(), ua.dot(ub)) * kRadToDeg;
  return std::isfinite(angle) ? angle : 180.0;
}

}  // namespace

GroundTruth ReadGroundTruthJson(const std::string& path) {
  std::ifstream in(path);
  if (!in) Fail(path, "cannot open ground-truth file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  json root;
  try {
    root = json::parse(buffer.str());
  } catch (const json::exception& e) {
    Fail(path, std::string("invalid JSON: ") + e.what());
  }
  if (!root.is_object() || !root.contains("images") || !root.at("images").is_array()) {
    Fail(path, "expected an object with an \"images\" array");
  }
  GroundTruth gt;
  std::set<std::string> names;
  const json& images = root.at("images");
  for (size_t i = 0; i < images.size(); ++i) {
    const json& entry = images[i];
    std::string where = "images[" + std::to_string(i) + "]";
    if (!entry.is_object()) Fail(path, where + " must be an object");
    if (!entry.contains("name") || !entry.at("name").is_string() || entry.at("name").get<std::string>().empty()) {
      Fail(path, where + ": missing or empty \"name\" string");
    }
    GroundTruthImage image;
    image.name = entry.at("name").get<std::string>();
    where += " (" + image.name + ")";
    const std::vector<double> R = NumberArray(entry, "R", 9, path, where);
    const std::vector<double> t = NumberArray(entry, "t", 3, path, where);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) image.R(r, c) = R[3 * r + c];
      image.t(r) = t[r];
    }
    // Published ground truth is often printed with 6 significant digits (Strecha's .camera files: |R R^T - I|
    // about 1e-6), so a near-rotation is accepted and replaced by the nearest rotation (SVD).
    const double orthogonality = (image.R * image.R.transpose() - Eigen::Matrix3d::Identity()).norm();
    if (!(orthogonality < 1e-3) || !(image.R.determinant() > 0.0)) {
      Fail(path, where + ": \"R\" is not a rotation matrix (|R R^T - I| = " + std::to_string(orthogonality) +
                     ", det = " + std::to_string(image.R.determinant()) + ")");
    }
    if (orthogonality > 1e-12) {
      const Eigen::JacobiSVD<Eigen::Matrix3d> svd(image.R, Eigen::ComputeFullU | Eigen::ComputeFullV);
      image.R = svd.matrixU() * svd.matrixV().transpose();
    }
    if (entry.contains("f") && !entry.at("f").is_null()) {
      const json& f = entry.at("f");
      if (!f.is_number() || !(f.get<double>() > 0.0) || !std::isfinite(f.get<double>())) {
        Fail(path, where + ": \"f\" must be a positive number (focal length in pixels)");
      }
      image.focal = f.get<double>();
    }
    if (!names.insert(image.name).second) Fail(path, where + ": duplicate image name");
    gt.images.push_back(std::move(image));
  }
  return gt;
}

void WriteGroundTruthJson(const GroundTruth& ground_truth, const std::string& path) {
  json images = json::array();
  for (const GroundTruthImage& image : ground_truth.images) {
    json entry;
    entry["name"] = image.name;
    std::vector<double> R(9);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) R[3 * r + c] = image.R(r, c);
    entry["R"] = R;
    entry["t"] = {image.t.x(), image.t.y(), image.t.z()};
    if (std::isfinite(image.focal)) entry["f"] = image.focal;
    images.push_back(std::move(entry));
  }
  std::ofstream out(path, std::ios::trunc);
  if (!out) Fail(path, "cannot create ground-truth file");
  out << madsfm::DumpJson(json{{"images", images}}, 2) << "\n";
  out.close();
  if (!out) Fail(path, "write error");
}

ModelComparison CompareToGroundTruth(const Reconstruction& model, const GroundTruth& ground_truth) {
  ModelComparison result;
  result.num_gt_images = static_cast<int>(ground_truth.images.size());
  result.num_model_images = static_cast<int>(model.images.size());

  std::unordered_map<std::string, const ModelImage*> by_name;
  for (const auto& [id, image] : model.images) {
    if (!by_name.emplace(image.name, &image).second) {
      throw std::runtime_error("model has two images named '" + image.name + "'");
    }
    if (model.cameras.count(image.camera_id) == 0) {
      throw std::runtime_error("model image '" + image.name + "' (image_id " + std::to_string(id) +
                               ") uses camera_id " + std::to_string(image.camera_id) + ", which the model does not "
                               "contain");
    }
  }

  // Registered ground-truth images, in ground-truth order.
  struct Registered {
    const GroundTruthImage* gt;
    Eigen::Matrix3d R;
    Eigen::Vector3d t, c, c_gt;
    double focal;
  };
  std::vector<Registered> registered;
  std::set<std::string> gt_names;
  for (const GroundTruthImage& gt : ground_truth.images) {
    gt_names.insert(gt.name);
    const auto it = by_name.find(gt.name);
    if (it == by_name.end()) {
      result.unregistered_names.push_back(gt.name);
      continue;
    }
    const ModelImage& image = *it->second;
    Registered r;
    r.gt = &gt;
    r.R = QuaternionToRotation(image.qvec);
    r.t = image.tvec;
    r.c = -r.R.transpose() * r.t;
    r.c_gt = -gt.R.transpose() * gt.t;
    const CameraIntrinsics& camera = model.cameras.at(image.camera_id).intrinsics;
    try {
      r.focal = 0.5 * (camera.FocalX() + camera.FocalY());
    } catch (const std::exception&) {
      r.focal = std::nan("");  // a model without a focal length (e.g. equirectangular): no focal error
    }
    registered.push_back(r);
  }
  result.num_registered = static_cast<int>(registered.size());
  for (const auto& [id, image] : model.images) result.num_model_images_not_in_gt += gt_names.count(image.name) == 0;

  // Scene size of the ground truth, to tell a zero baseline from a short one.
  double scene_size = 0.0;
  if (!registered.empty()) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const Registered& r : registered) centroid += r.c_gt;
    centroid /= static_cast<double>(registered.size());
    for (const Registered& r : registered) scene_size = std::max(scene_size, (r.c_gt - centroid).norm());
  }
  const double min_baseline = 1e-9 * scene_size;

  std::vector<double> rot_errors, trans_errors;
  const size_t n = registered.size();
  const size_t num_pairs = n > 1 ? n * (n - 1) / 2 : 0;
  rot_errors.reserve(num_pairs);
  trans_errors.reserve(num_pairs);
  result.pair_errors.reserve(num_pairs);
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = i + 1; j < n; ++j) {
      const Registered& a = registered[i];
      const Registered& b = registered[j];
      PairError e;
      e.name_i = a.gt->name;
      e.name_j = b.gt->name;
      e.rot_err_deg = RotationErrorDeg(a.R * b.R.transpose(), a.gt->R * b.gt->R.transpose());
      rot_errors.push_back(e.rot_err_deg);
      const Eigen::Vector3d baseline_gt = a.c_gt - b.c_gt;
      if (baseline_gt.norm() > min_baseline) {
        // t_ij seen from camera j and t_ji seen from camera i; the larger error (order-independent).
        const Eigen::Vector3d baseline = a.c - b.c;
        e.trans_err_deg = std::max(DirectionAngleDeg(b.R * baseline, b.gt->R * baseline_gt),
                                   DirectionAngleDeg(a.R * baseline, a.gt->R * baseline_gt));
        trans_errors.push_back(e.trans_err_deg);
      } else {
        e.trans_err_deg = std::nan("");
      }
      result.pair_errors.push_back(std::move(e));
    }
  }
  result.num_pairs = static_cast<int>(rot_errors.size());
  result.median_rot_err_deg = Median(rot_errors);
  result.max_rot_err_deg = Max(rot_errors);
  result.num_trans_pairs = static_cast<int>(trans_errors.size());
  result.median_trans_err_deg = Median(trans_errors);
  result.max_trans_err_deg = Max(trans_errors);

  std::vector<double> focal_errors;
  for (const Registered& r : registered) {
    if (std::isfinite(r.gt->focal) && r.gt->focal > 0.0 && std::isfinite(r.focal)) {
      focal_errors.push_back(std::abs(r.focal - r.gt->focal) / r.gt->focal);
    }
  }
  result.num_focal = static_cast<int>(focal_errors.size());
  result.median_focal_err = Median(focal_errors);
  result.max_focal_err = Max(focal_errors);

  result.num_points3D = static_cast<int>(model.points3D.size());
  if (!model.points3D.empty()) {
    double sum = 0.0;
    for (const auto& [id, point] : model.points3D) sum += point.error;
    result.mean_reproj_error = sum / static_cast<double>(model.points3D.size());
  }
  return result;
}

}  // namespace madsfm::colmap
