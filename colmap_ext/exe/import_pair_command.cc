#include "colmap_ext/exe/import_pair_command.h"

#include <sqlite3.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "colmap_ext/database/database_schema.h"
#include "colmap_ext/exe/option_parser.h"
#include "madsfm/io/depth_map_io.h"
#include "madsfm/io/json_writer.h"
#include "madsfm/io/pair_directory.h"

namespace madsfm {
namespace {

namespace fs = std::filesystem;

void Step(sqlite3* db, sqlite3_stmt* st, const std::string& what) {
  if (sqlite3_step(st) != SQLITE_DONE) throw std::runtime_error(what + ": " + sqlite3_errmsg(db));
  sqlite3_reset(st);
}

}  // namespace

int RunImportPair(int argc, char** argv) {
  std::string pair_path, output_path;
  bool known_focal = false;
  OptionParser parser("import_pair",
                      "Makes a COLMAP project of a pair directory: <output_path>/database.db (one keypoint per match,\n"
                      "the raw matches; one SIMPLE_PINHOLE camera per image with the principal point of K and, unless\n"
                      "--known_focal 1, COLMAP's default focal guess 1.2 max(W, H) without a prior), images/,\n"
                      "depths/<image>.npy and ground_truth.json (world = camera 0).");
  parser.AddRequired("pair_path", &pair_path, "Pair directory with image0.png / image1.png.");
  parser.AddRequired("output_path", &output_path, "Project folder to create.");
  parser.AddDefault("known_focal", &known_focal, "Write the true focal lengths with prior_focal_length = 1.");
  if (!parser.Parse(argc, argv, 2)) return EXIT_FAILURE;
  if (parser.help_requested()) return EXIT_SUCCESS;
  try {
    const PairData pair = ReadPairDirectory(pair_path);
    if (!pair.HasDepth()) throw std::runtime_error("pair '" + pair_path + "' has no depth maps");
    fs::create_directories(fs::path(output_path) / "images");
    fs::create_directories(fs::path(output_path) / "depths");
    const std::string names[2] = {"image0.png", "image1.png"};
    for (const std::string& n : names) {
      const fs::path src = fs::path(pair_path) / n;
      if (!fs::exists(src)) throw std::runtime_error("pair '" + pair_path + "' has no " + n);
      fs::copy_file(src, fs::path(output_path) / "images" / n, fs::copy_options::overwrite_existing);
    }
    WriteDepthMapNpy(*pair.depth0, (fs::path(output_path) / "depths" / "image0.png.npy").string());
    WriteDepthMapNpy(*pair.depth1, (fs::path(output_path) / "depths" / "image1.png.npy").string());

    const std::string db_path = (fs::path(output_path) / "database.db").string();
    colmap::CreateColmap38Database(db_path);
    sqlite3* db = nullptr;
    sqlite3_open(db_path.c_str(), &db);
    sqlite3_exec(db, "BEGIN", nullptr, nullptr, nullptr);
    sqlite3_stmt *cam, *img, *kp, *mt;
    sqlite3_prepare_v2(db, "INSERT INTO cameras(model, width, height, params, prior_focal_length) VALUES(0,?,?,?,?)", -1,
                       &cam, nullptr);
    sqlite3_prepare_v2(db, "INSERT INTO images(name, camera_id) VALUES(?,?)", -1, &img, nullptr);
    sqlite3_prepare_v2(db, "INSERT INTO keypoints(image_id, rows, cols, data) VALUES(?,?,2,?)", -1, &kp, nullptr);
    sqlite3_prepare_v2(db, "INSERT INTO matches(pair_id, rows, cols, data) VALUES(?,?,2,?)", -1, &mt, nullptr);
    const Eigen::Matrix3d* K[2] = {&pair.K0, &pair.K1};
    const int W[2] = {pair.width0, pair.width1}, H[2] = {pair.height0, pair.height1};
    const std::vector<Eigen::Vector2d>* pts[2] = {&pair.p0, &pair.p1};
    nlohmann::json gt;
    for (int v = 0; v < 2; ++v) {
      const double f = known_focal ? 0.5 * ((*K[v])(0, 0) + (*K[v])(1, 1)) : 1.2 * std::max(W[v], H[v]);
      // COLMAP puts the upper-left pixel centre at (0.5, 0.5): shift the principal point and keypoints.
      const double params[3] = {f, (*K[v])(0, 2) + 0.5, (*K[v])(1, 2) + 0.5};
      sqlite3_bind_int(cam, 1, W[v]);
      sqlite3_bind_int(cam, 2, H[v]);
      sqlite3_bind_blob(cam, 3, params, sizeof(params), SQLITE_TRANSIENT);
      sqlite3_bind_int(cam, 4, known_focal ? 1 : 0);
      Step(db, cam, "insert camera");
      sqlite3_bind_text(img, 1, names[v].c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_int(img, 2, v + 1);
      Step(db, img, "insert image");
      std::vector<float> data;
      for (const auto& p : *pts[v]) data.insert(data.end(), {float(p.x() + 0.5), float(p.y() + 0.5)});
      sqlite3_bind_int(kp, 1, v + 1);
      sqlite3_bind_int(kp, 2, static_cast<int>(pts[v]->size()));
      sqlite3_bind_blob(kp, 3, data.data(), static_cast<int>(data.size() * sizeof(float)), SQLITE_TRANSIENT);
      Step(db, kp, "insert keypoints");
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
    std::vector<uint32_t> m;
    for (uint32_t i = 0; i < pair.p0.size(); ++i) m.insert(m.end(), {i, i});
    sqlite3_bind_int64(mt, 1, 2147483649LL);
    sqlite3_bind_int(mt, 2, static_cast<int>(pair.p0.size()));
    sqlite3_bind_blob(mt, 3, m.data(), static_cast<int>(m.size() * sizeof(uint32_t)), SQLITE_TRANSIENT);
    Step(db, mt, "insert matches");
    for (sqlite3_stmt* st : {cam, img, kp, mt}) sqlite3_finalize(st);
    sqlite3_exec(db, "COMMIT", nullptr, nullptr, nullptr);
    sqlite3_close(db);
    std::ofstream(fs::path(output_path) / "ground_truth.json") << madsfm::DumpJson(gt, 2) << "\n";
    std::ofstream(fs::path(output_path) / "pairs.txt") << "image0.png image1.png\n";
    std::printf("import_pair: %zu matches -> %s\n", pair.p0.size(), output_path.c_str());
    return EXIT_SUCCESS;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "madsfm import_pair: error: %s\n", e.what());
    return EXIT_FAILURE;
  }
}

}  // namespace madsfm
