#include "colmap_ext/synthetic/pair_project.h"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <vector>

#include "colmap_ext/database/database_builder.h"
#include "colmap_ext/io/file_copy.h"
#include "madsfm/io/depth_map_io.h"
#include "madsfm/io/json_writer.h"
#include "madsfm/io/pair_directory.h"

namespace madsfm::colmap {

namespace fs = std::filesystem;

PairProjectSummary WritePairProject(const std::string& pair_path, const std::string& output_path, bool known_focal) {
  const PairData pair = ReadPairDirectory(pair_path);
  if (!pair.HasDepth()) throw std::runtime_error("pair '" + pair_path + "' has no depth maps");
  const std::string names[2] = {"image0.png", "image1.png"};
  for (const std::string& n : names) {
    if (!fs::exists(fs::path(pair_path) / n)) throw std::runtime_error("pair '" + pair_path + "' has no " + n);
  }
  PairProjectSummary summary;
  summary.database_path = (fs::path(output_path) / "database.db").string();
  if (fs::exists(summary.database_path)) {
    throw std::runtime_error("'" + summary.database_path + "' already exists (nothing is overwritten)");
  }
  fs::create_directories(fs::path(output_path) / "images");
  fs::create_directories(fs::path(output_path) / "depths");
  for (const std::string& n : names) {
    CopyFileContents(fs::path(pair_path) / n, fs::path(output_path) / "images" / n);
  }
  WriteDepthMapNpy(*pair.depth0, (fs::path(output_path) / "depths" / "image0.png.npy").string());
  WriteDepthMapNpy(*pair.depth1, (fs::path(output_path) / "depths" / "image1.png.npy").string());

  DatabaseBuilder db(summary.database_path);
  db.Exec("BEGIN");
  const Eigen::Matrix3d* K[2] = {&pair.K0, &pair.K1};
  const int W[2] = {pair.width0, pair.width1}, H[2] = {pair.height0, pair.height1};
  const std::vector<Eigen::Vector2d>* pts[2] = {&pair.p0, &pair.p1};
  uint32_t image_ids[2];
  nlohmann::json gt;
  for (int v = 0; v < 2; ++v) {
    const double f = known_focal ? 0.5 * ((*K[v])(0, 0) + (*K[v])(1, 1)) : 1.2 * std::max(W[v], H[v]);
    // COLMAP puts the upper-left pixel centre at (0.5, 0.5): shift the principal point and keypoints.
    const uint32_t cam = db.AddCamera(0, W[v], H[v], {f, (*K[v])(0, 2) + 0.5, (*K[v])(1, 2) + 0.5}, known_focal);
    image_ids[v] = db.AddImage(names[v], cam);
    std::vector<Eigen::Vector2d> keypoints;
    for (const auto& p : *pts[v]) keypoints.push_back(p + Eigen::Vector2d(0.5, 0.5));
    db.AddKeypoints(image_ids[v], keypoints);
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
    if (v == 1 && pair.T_0to1) {
      R = pair.T_0to1->topLeftCorner<3, 3>();
      t = pair.T_0to1->topRightCorner<3, 1>();
    }
    nlohmann::json e;
    e["name"] = names[v];
    e["R"] = {R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2)};
    e["t"] = {t.x(), t.y(), t.z()};
    e["f"] = 0.5 * ((*K[v])(0, 0) + (*K[v])(1, 1));
    gt["images"].push_back(e);
  }
  std::vector<std::array<uint32_t, 2>> matches;
  for (uint32_t i = 0; i < pair.p0.size(); ++i) matches.push_back({i, i});
  db.AddMatches(image_ids[0], image_ids[1], matches);
  db.Exec("COMMIT");
  std::ofstream(fs::path(output_path) / "ground_truth.json") << DumpJson(gt, 2) << "\n";
  std::ofstream(fs::path(output_path) / "pairs.txt") << "image0.png image1.png\n";
  summary.num_matches = static_cast<int>(pair.p0.size());
  return summary;
}

}  // namespace madsfm::colmap
