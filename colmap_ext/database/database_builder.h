// Writing a new COLMAP database (of any release in database_schema.h) from scratch (cameras, images, keypoints, matches), for importers, the
// synthetic projects of `madsfm synth_project` and tests. Existing databases are only ever changed through
// Database (database.h); this class creates a file that did not exist.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "colmap_ext/database/database_schema.h"

struct sqlite3;
struct sqlite3_stmt;

namespace madsfm::colmap {

class DatabaseBuilder {
 public:
  // Creates `path` with the schema of `release` (3.8: exactly that of `colmap database_creator` 3.8); throws
  // std::runtime_error naming the file if it exists or cannot be created.
  explicit DatabaseBuilder(const std::string& path, ColmapRelease release = ColmapRelease::k3_8);
  ~DatabaseBuilder();
  DatabaseBuilder(const DatabaseBuilder&) = delete;
  DatabaseBuilder& operator=(const DatabaseBuilder&) = delete;

  // Return the new row ids (cameras and images are numbered from 1 in insertion order). From 3.12 on, each camera
  // also gets a rig of its own (rig_id = camera_id, the camera as its reference sensor) and each image a frame
  // (frame_id = image_id) with one frame_data row, as COLMAP's feature extractor makes them for single cameras.
  uint32_t AddCamera(int model_id, int width, int height, const std::vector<double>& params, bool prior_focal);
  uint32_t AddImage(const std::string& name, uint32_t camera_id);
  // Keypoints in COLMAP's convention (pixel centres at +0.5), stored as rows x 6 float32 (x, y and an identity
  // affine shape, as SIFT writes them).
  void AddKeypoints(uint32_t image_id, const std::vector<Eigen::Vector2d>& keypoints);
  // matches[i] = (keypoint of image_id1, keypoint of image_id2); stored with the smaller image id first.
  void AddMatches(uint32_t image_id1, uint32_t image_id2, const std::vector<std::array<uint32_t, 2>>& matches);
  void Exec(const std::string& sql);
  sqlite3* handle() { return db_; }
  const std::string& path() const { return path_; }
  ColmapRelease release() const { return release_; }

 private:
  bool HasRigs() const;
  sqlite3_stmt* Prepare(int which, const char* sql);
  void Step(sqlite3_stmt* st, const std::string& what);
  std::string path_;
  ColmapRelease release_;
  sqlite3* db_ = nullptr;
  sqlite3_stmt* statements_[4] = {nullptr, nullptr, nullptr, nullptr};
  std::map<uint32_t, std::string> names_;  // image names, for messages
};

}  // namespace madsfm::colmap
