#include "colmap_ext/database/database_schema.h"

#include <sqlite3.h>

#include <filesystem>
#include <stdexcept>

namespace madsfm::colmap {
namespace {

bool AtLeast(ColmapRelease release, ColmapRelease first) { return static_cast<int>(release) >= static_cast<int>(first); }

// One statement per table; columns, constraints and indexes as the release creates them (docs/formats.md).
std::string CamerasTable() {
  return "CREATE TABLE cameras (camera_id INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, model INTEGER NOT NULL, "
         "width INTEGER NOT NULL, height INTEGER NOT NULL, params BLOB, prior_focal_length INTEGER NOT NULL);\n";
}

std::string ImagesTable(ColmapRelease release) {
  std::string sql =
      "CREATE TABLE images (image_id INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, name TEXT NOT NULL UNIQUE, "
      "camera_id INTEGER NOT NULL, ";
  // Up to 3.9 the pose prior lived in the images table.
  if (!AtLeast(release, ColmapRelease::k3_10)) {
    sql += "prior_qw REAL, prior_qx REAL, prior_qy REAL, prior_qz REAL, prior_tx REAL, prior_ty REAL, prior_tz REAL, ";
  }
  sql += "CONSTRAINT image_id_check CHECK(image_id >= 0 and image_id < 2147483647), "
         "FOREIGN KEY(camera_id) REFERENCES cameras(camera_id));\n"
         "CREATE UNIQUE INDEX index_name ON images(name);\n";
  return sql;
}

std::string RigAndFrameTables() {
  return "CREATE TABLE rigs (rig_id INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, ref_sensor_id INTEGER NOT NULL, "
         "ref_sensor_type INTEGER NOT NULL);\n"
         "CREATE UNIQUE INDEX rig_ref_sensor_assignment ON rigs(ref_sensor_id, ref_sensor_type);\n"
         "CREATE TABLE rig_sensors (rig_id INTEGER NOT NULL, sensor_id INTEGER NOT NULL, sensor_type INTEGER NOT NULL, "
         "sensor_from_rig BLOB, FOREIGN KEY(rig_id) REFERENCES rigs(rig_id) ON DELETE CASCADE);\n"
         "CREATE UNIQUE INDEX rig_sensor_assignment ON rig_sensors(sensor_id, sensor_type);\n"
         "CREATE TABLE frames (frame_id INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, rig_id INTEGER NOT NULL, "
         "FOREIGN KEY(rig_id) REFERENCES rigs(rig_id) ON DELETE CASCADE);\n"
         "CREATE TABLE frame_data (frame_id INTEGER NOT NULL, data_id INTEGER NOT NULL, sensor_id INTEGER NOT NULL, "
         "sensor_type INTEGER NOT NULL, FOREIGN KEY(frame_id) REFERENCES frames(frame_id) ON DELETE CASCADE);\n"
         "CREATE UNIQUE INDEX frame_sensor_assignment ON frame_data(data_id, sensor_type);\n";
}

std::string PosePriorsTable(ColmapRelease release) {
  if (!AtLeast(release, ColmapRelease::k3_10)) return "";
  if (AtLeast(release, ColmapRelease::k4_0)) {
    return "CREATE TABLE pose_priors (pose_prior_id INTEGER PRIMARY KEY NOT NULL, corr_data_id INTEGER NOT NULL, "
           "corr_sensor_id INTEGER NOT NULL, corr_sensor_type INTEGER NOT NULL, position BLOB, "
           "position_covariance BLOB, gravity BLOB, coordinate_system INTEGER NOT NULL);\n"
           "CREATE UNIQUE INDEX pose_prior_data_assignment ON "
           "pose_priors(corr_data_id, corr_sensor_id, corr_sensor_type);\n";
  }
  std::string sql = "CREATE TABLE pose_priors (image_id INTEGER PRIMARY KEY NOT NULL, position BLOB, "
                    "coordinate_system INTEGER NOT NULL, ";
  if (AtLeast(release, ColmapRelease::k3_11)) sql += "position_covariance BLOB, ";
  sql += "FOREIGN KEY(image_id) REFERENCES images(image_id) ON DELETE CASCADE);\n";
  return sql;
}

std::string FeatureTables(ColmapRelease release) {
  std::string sql =
      "CREATE TABLE keypoints (image_id INTEGER PRIMARY KEY NOT NULL, rows INTEGER NOT NULL, cols INTEGER NOT NULL, "
      "data BLOB, FOREIGN KEY(image_id) REFERENCES images(image_id) ON DELETE CASCADE);\n"
      "CREATE TABLE descriptors (image_id INTEGER PRIMARY KEY NOT NULL, ";
  if (AtLeast(release, ColmapRelease::k4_0)) sql += "type INTEGER NOT NULL, ";  // the feature extractor type
  sql += "rows INTEGER NOT NULL, cols INTEGER NOT NULL, data BLOB, "
         "FOREIGN KEY(image_id) REFERENCES images(image_id) ON DELETE CASCADE);\n";
  return sql;
}

std::string MatchTables(ColmapRelease release) {
  std::string sql =
      "CREATE TABLE matches (pair_id INTEGER PRIMARY KEY NOT NULL, rows INTEGER NOT NULL, cols INTEGER NOT NULL, "
      "data BLOB);\n"
      "CREATE TABLE two_view_geometries (pair_id INTEGER PRIMARY KEY NOT NULL, rows INTEGER NOT NULL, "
      "cols INTEGER NOT NULL, data BLOB, config INTEGER NOT NULL, F BLOB, E BLOB, H BLOB, qvec BLOB, tvec BLOB";
  if (AtLeast(release, ColmapRelease::kMain)) sql += ", camera1 BLOB, camera2 BLOB";
  sql += ");\n";
  return sql;
}

}  // namespace

std::vector<ColmapRelease> AllColmapReleases() {
  return {ColmapRelease::k3_8,  ColmapRelease::k3_9, ColmapRelease::k3_10, ColmapRelease::k3_11, ColmapRelease::k3_12,
          ColmapRelease::k3_13, ColmapRelease::k4_0, ColmapRelease::k4_1,  ColmapRelease::kMain};
}

std::string ColmapReleaseName(ColmapRelease release) {
  switch (release) {
    case ColmapRelease::k3_8: return "3.8";
    case ColmapRelease::k3_9: return "3.9";
    case ColmapRelease::k3_10: return "3.10";
    case ColmapRelease::k3_11: return "3.11";
    case ColmapRelease::k3_12: return "3.12";
    case ColmapRelease::k3_13: return "3.13";
    case ColmapRelease::k4_0: return "4.0";
    case ColmapRelease::k4_1: return "4.1";
    case ColmapRelease::kMain: return "main";
  }
  return "unknown";
}

ColmapRelease ParseColmapRelease(const std::string& name, const std::string& option) {
  std::string names;
  for (ColmapRelease r : AllColmapReleases()) {
    if (ColmapReleaseName(r) == name) return r;
    names += (names.empty() ? "" : ", ") + ColmapReleaseName(r);
  }
  throw std::invalid_argument("unknown " + option + " '" + name + "' (known: " + names + ")");
}

int ColmapReleaseUserVersion(ColmapRelease release) {
  switch (release) {
    case ColmapRelease::k3_8: return 3800;
    case ColmapRelease::k3_9:
    case ColmapRelease::k3_10:
    case ColmapRelease::k3_11:
    case ColmapRelease::k3_12:
    case ColmapRelease::k3_13: return 3900;  // hard-coded from 3.9 to 3.13.0
    // From 4.0: major * 1000000 + minor * 10000 + patch * 100 + schema revision (0).
    case ColmapRelease::k4_0: return 4000400;
    case ColmapRelease::k4_1: return 4010100;
    case ColmapRelease::kMain: return 4020000;
  }
  return 0;
}

std::string ColmapSchemaSql(ColmapRelease release) {
  std::string sql;
  if (AtLeast(release, ColmapRelease::k3_12)) sql += RigAndFrameTables();
  sql += CamerasTable() + ImagesTable(release) + PosePriorsTable(release) + FeatureTables(release) +
         MatchTables(release);
  sql += "PRAGMA user_version = " + std::to_string(ColmapReleaseUserVersion(release)) + ";\n";
  return sql;
}

std::string Colmap38SchemaSql() { return ColmapSchemaSql(ColmapRelease::k3_8); }

void CreateColmapDatabase(const std::string& path, ColmapRelease release) {
  if (std::filesystem::exists(path)) throw std::runtime_error("database '" + path + "' already exists");
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) != SQLITE_OK) {
    const std::string msg = db ? sqlite3_errmsg(db) : "out of memory";
    sqlite3_close(db);
    throw std::runtime_error("cannot create database '" + path + "': " + msg);
  }
  char* err = nullptr;
  const std::string sql = "BEGIN;\n" + ColmapSchemaSql(release) + "COMMIT;\n";
  const int rc = sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &err);
  const std::string msg = err ? err : "";
  sqlite3_free(err);
  sqlite3_close(db);
  if (rc != SQLITE_OK) throw std::runtime_error("cannot create database '" + path + "': " + msg);
}

void CreateColmap38Database(const std::string& path) { CreateColmapDatabase(path, ColmapRelease::k3_8); }

}  // namespace madsfm::colmap
