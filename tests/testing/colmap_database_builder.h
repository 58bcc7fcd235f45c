// Builds COLMAP 3.8 databases for tests with raw SQL (the exact schema of `colmap database_creator` 3.8,
// ../shared/docs/colmap.md), and fills them from synthetic pairs.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

struct sqlite3;

namespace madsfm::testing {

class ColmapDatabaseBuilder {
 public:
  explicit ColmapDatabaseBuilder(const std::string& path);  // creates the file with the 3.8 schema
  ~ColmapDatabaseBuilder();
  uint32_t AddCamera(int model_id, int width, int height, const std::vector<double>& params, bool prior_focal);
  uint32_t AddImage(const std::string& name, uint32_t camera_id);
  // Keypoints in COLMAP's convention (pixel centres at +0.5), stored as rows x 2 float32... x 6 like SIFT.
  void AddKeypoints(uint32_t image_id, const std::vector<Eigen::Vector2d>& keypoints);
  void AddMatches(uint32_t image_id1, uint32_t image_id2, const std::vector<std::array<uint32_t, 2>>& matches);
  void Exec(const std::string& sql);
  sqlite3* handle() { return db_; }

 private:
  sqlite3* db_ = nullptr;
};

// Executes SQL on an existing database file (throws on error).
void ExecSql(const std::string& path, const std::string& sql);
// Runs PRAGMA integrity_check; returns its first result row ("ok" when healthy).
std::string IntegrityCheck(const std::string& path);
// Dumps a table (all columns, blobs as hex) sorted by its first column, to compare databases.
std::string DumpTable(const std::string& path, const std::string& table);

}  // namespace madsfm::testing
