#include "colmap_ext/exe/model_compare_command.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

#include "colmap_ext/exe/option_parser.h"
#include "colmap_ext/model/model_comparison.h"
#include "colmap_ext/model/reconstruction.h"
#include "madsfm/io/json_writer.h"

namespace madsfm {
namespace {

std::string Fmt(double v, int precision) {
  if (std::isnan(v)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", precision, v);
  return buf;
}

// NaN (nothing to measure) becomes null.
nlohmann::json Number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json ComparisonJson(const colmap::ModelComparison& c) {
  nlohmann::json j;
  j["num_gt_images"] = c.num_gt_images;
  j["num_registered"] = c.num_registered;
  j["num_model_images"] = c.num_model_images;
  j["num_model_images_not_in_gt"] = c.num_model_images_not_in_gt;
  j["unregistered_images"] = c.unregistered_names;
  j["num_pairs"] = c.num_pairs;
  j["median_rot_err_deg"] = Number(c.median_rot_err_deg);
  j["max_rot_err_deg"] = Number(c.max_rot_err_deg);
  j["num_trans_pairs"] = c.num_trans_pairs;
  j["median_trans_err_deg"] = Number(c.median_trans_err_deg);
  j["max_trans_err_deg"] = Number(c.max_trans_err_deg);
  j["num_focal"] = c.num_focal;
  j["median_focal_err"] = Number(c.median_focal_err);
  j["max_focal_err"] = Number(c.max_focal_err);
  j["num_points3D"] = c.num_points3D;
  j["mean_reproj_error"] = Number(c.mean_reproj_error);
  return j;
}

std::string ComparisonText(const colmap::ModelComparison& c) {
  std::string s;
  s += "Ground-truth images:          " + std::to_string(c.num_gt_images) + "\n";
  s += "Registered images:            " + std::to_string(c.num_registered) + " (the model has " +
       std::to_string(c.num_model_images) + " images, " + std::to_string(c.num_model_images_not_in_gt) +
       " not in the ground truth)\n";
  if (!c.unregistered_names.empty()) {
    s += "Unregistered images:         ";
    const size_t shown = std::min<size_t>(c.unregistered_names.size(), 10);
    for (size_t i = 0; i < shown; ++i) s += " " + c.unregistered_names[i];
    if (shown < c.unregistered_names.size()) s += " ... (" + std::to_string(c.unregistered_names.size()) + " in all)";
    s += "\n";
  }
  s += "Image pairs:                  " + std::to_string(c.num_pairs) + "\n";
  s += "Rotation error [deg]:         median " + Fmt(c.median_rot_err_deg, 4) + "  max " + Fmt(c.max_rot_err_deg, 4) +
       "  (relative rotations of all pairs, no alignment)\n";
  s += "Translation dir. error [deg]: median " + Fmt(c.median_trans_err_deg, 4) + "  max " +
       Fmt(c.max_trans_err_deg, 4) + "  (relative translation directions, " + std::to_string(c.num_trans_pairs) +
       " pairs, no alignment)\n";
  s += "Focal error [relative]:       median " + Fmt(c.median_focal_err, 6) + "  max " + Fmt(c.max_focal_err, 6) +
       "  (" + std::to_string(c.num_focal) + " images, |f - f_gt| / f_gt)\n";
  s += "3-D points:                   " + std::to_string(c.num_points3D) + "\n";
  s += "Mean reprojection error [px]: " + Fmt(c.mean_reproj_error, 4) + "\n";
  return s;
}

}  // namespace

int RunModelCompare(int argc, char** argv) {
  std::string input_path, ground_truth_path, output_format = "text";
  OptionParser parser(
      "model_compare",
      "Compares a COLMAP sparse model (.bin or .txt files) with ground-truth world->camera poses (x_cam = R x + t)\n"
      "and focal lengths given as JSON {\"images\": [{\"name\": ..., \"R\": [9, row-major], \"t\": [3], \"f\": px}]}.\n"
      "Images are matched by name. Prints the number of ground-truth and registered images, the median / max\n"
      "relative-rotation error and relative-translation-direction error over all pairs of registered images\n"
      "(both need no alignment; the translation error is the angle between the model's and the ground truth's\n"
      "t_ij = R_j (c_i - c_j), the larger of it and the same for t_ji), the median / max focal error\n"
      "|f - f_gt| / f_gt (f: the model camera's f, or the mean of fx and fy), the number of 3-D points and the\n"
      "mean of their reprojection errors. Exit code 1 on bad options or unreadable / malformed files.");
  parser.AddRequired("input_path", &input_path, "COLMAP model directory (cameras/images/points3D .bin or .txt).");
  parser.AddRequired("ground_truth_path", &ground_truth_path, "Ground-truth JSON file.");
  parser.AddDefault("output_format", &output_format, "text | json.");
  if (!parser.Parse(argc, argv, 2)) return EXIT_FAILURE;
  if (parser.help_requested()) return EXIT_SUCCESS;
  try {
    if (output_format != "text" && output_format != "json") {
      throw std::invalid_argument("--output_format must be text or json, got '" + output_format + "'");
    }
    const colmap::GroundTruth ground_truth = colmap::ReadGroundTruthJson(ground_truth_path);
    const colmap::Reconstruction model = colmap::ReadReconstruction(input_path);
    const colmap::ModelComparison comparison = colmap::CompareToGroundTruth(model, ground_truth);
    if (output_format == "json") {
      std::cout << madsfm::DumpJson(ComparisonJson(comparison), 2) << std::endl;
    } else {
      std::cout << ComparisonText(comparison) << std::flush;
    }
    return EXIT_SUCCESS;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "madsfm model_compare: error: %s\n", e.what());
    return EXIT_FAILURE;
  }
}

}  // namespace madsfm
