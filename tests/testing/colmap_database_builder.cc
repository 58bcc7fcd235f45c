#include "testing/colmap_database_builder.h"

#include <sqlite3.h>

#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace madsfm::testing {
namespace {

const char* kSchema38 = R"SQL(
CREATE TABLE cameras (camera_id INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, model INTEGER NOT NULL, width INTEGER NOT NULL, height INTEGER NOT NULL, params BLOB, prior_focal_length INTEGER NOT NULL);
CREATE TABLE images (image_id INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, name TEXT NOT NULL UNIQUE, camera_id INTEGER NOT NULL, prior_qw REAL, prior_qx REAL, prior_qy REAL, prior_qz REAL, prior_tx REAL, prior_ty REAL, prior_tz REAL, CONSTRAINT image_id_check CHECK(image_id >= 0 and image_id < 2147483647), FOREIGN KEY(camera_id) REFERENCES cameras(camera_id));
CREATE UNIQUE INDEX index_name ON images(name);
CREATE TABLE keypoints (image_id INTEGER PRIMARY KEY NOT NULL, rows INTEGER NOT NULL, cols INTEGER NOT NULL, data BLOB, FOREIGN KEY(image_id) REFERENCES images(image_id) ON DELETE CASCADE);
CREATE TABLE descriptors (image_id INTEGER PRIMARY KEY NOT NULL, rows INTEGER NOT NULL, cols INTEGER NOT NULL, data BLOB, FOREIGN KEY(image_id) REFERENCES images(image_id) ON DELETE CASCADE);
CREATE TABLE matches (pair_id INTEGER PRIMARY KEY NOT NULL, rows INTEGER NOT NULL, cols INTEGER NOT NULL, data BLOB);
CREATE TABLE two_view_geometries (pair_id INTEGER PRIMARY KEY NOT NULL, rows INTEGER NOT NULL, cols INTEGER NOT NULL, data BLOB, config INTEGER NOT NULL, F BLOB, E BLOB, H BLOB, qvec BLOB, tvec BLOB);
PRAGMA user_version = 3800;
)SQL";

void Check(int rc, sqlite3* db, const std::string& what) {
  if (rc != SQLITE_OK && rc != SQLITE_DONE && rc != SQLITE_ROW) {
    throw std::runtime_error(what + ": " + sqlite3_errmsg(db));
  }
}

uint64_t PairId(uint32_t a, uint32_t b) {
  if (a > b) std::swap(a, b);
  return 2147483647ull * a + b;
}

}  // namespace

ColmapDatabaseBuilder::ColmapDatabaseBuilder(const std::string& path) {
  std::remove(path.c_str());
  Check(sqlite3_open(path.c_str(), &db_), db_, "open " + path);
  Exec(kSchema38);
}

ColmapDatabaseBuilder::~ColmapDatabaseBuilder() { sqlite3_close(db_); }

void ColmapDatabaseBuilder::Exec(const std::string& sql) {
  char* err = nullptr;
  if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
    const std::string msg = err ? err : "?";
    sqlite3_free(err);
    throw std::runtime_error("sql: " + msg);
  }
}

uint32_t ColmapDatabaseBuilder::AddCamera(int model_id, int width, int height, const std::vector<double>& params,
                                          bool prior_focal) {
  sqlite3_stmt* st;
  Check(sqlite3_prepare_v2(db_, "INSERT INTO cameras(model, width, height, params, prior_focal_length) VALUES(?,?,?,?,?)",
                           -1, &st, nullptr), db_, "prepare");
  sqlite3_bind_int(st, 1, model_id);
  sqlite3_bind_int(st, 2, width);
  sqlite3_bind_int(st, 3, height);
  sqlite3_bind_blob(st, 4, params.data(), static_cast<int>(params.size() * sizeof(double)), SQLITE_TRANSIENT);
  sqlite3_bind_int(st, 5, prior_focal ? 1 : 0);
  Check(sqlite3_step(st), db_, "insert camera");
  sqlite3_finalize(st);
  return static_cast<uint32_t>(sqlite3_last_insert_rowid(db_));
}

uint32_t ColmapDatabaseBuilder::AddImage(const std::string& name, uint32_t camera_id) {
  sqlite3_stmt* st;
  Check(sqlite3_prepare_v2(db_, "INSERT INTO images(name, camera_id) VALUES(?,?)", -1, &st, nullptr), db_, "prepare");
  sqlite3_bind_text(st, 1, name.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_int(st, 2, static_cast<int>(camera_id));
  Check(sqlite3_step(st), db_, "insert image");
  sqlite3_finalize(st);
  return static_cast<uint32_t>(sqlite3_last_insert_rowid(db_));
}

void ColmapDatabaseBuilder::AddKeypoints(uint32_t image_id, const std::vector<Eigen::Vector2d>& keypoints) {
  std::vector<float> data;
  for (const auto& k : keypoints) {
    data.insert(data.end(), {static_cast<float>(k.x()), static_cast<float>(k.y()), 1.0f, 0.0f, 0.0f, 1.0f});
  }
  sqlite3_stmt* st;
  Check(sqlite3_prepare_v2(db_, "INSERT INTO keypoints(image_id, rows, cols, data) VALUES(?,?,6,?)", -1, &st, nullptr),
        db_, "prepare");
  sqlite3_bind_int(st, 1, static_cast<int>(image_id));
  sqlite3_bind_int(st, 2, static_cast<int>(keypoints.size()));
  sqlite3_bind_blob(st, 3, data.data(), static_cast<int>(data.size() * sizeof(float)), SQLITE_TRANSIENT);
  Check(sqlite3_step(st), db_, "insert keypoints");
  sqlite3_finalize(st);
}

void ColmapDatabaseBuilder::AddMatches(uint32_t a, uint32_t b, const std::vector<std::array<uint32_t, 2>>& matches) {
  std::vector<uint32_t> data;
  for (const auto& m : matches) {
    if (a < b) data.insert(data.end(), {m[0], m[1]});
    else data.insert(data.end(), {m[1], m[0]});
  }
  sqlite3_stmt* st;
  Check(sqlite3_prepare_v2(db_, "INSERT INTO matches(pair_id, rows, cols, data) VALUES(?,?,2,?)", -1, &st, nullptr),
        db_, "prepare");
  sqlite3_bind_int64(st, 1, static_cast<sqlite3_int64>(PairId(a, b)));
  sqlite3_bind_int(st, 2, static_cast<int>(matches.size()));
  sqlite3_bind_blob(st, 3, data.data(), static_cast<int>(data.size() * sizeof(uint32_t)), SQLITE_TRANSIENT);
  Check(sqlite3_step(st), db_, "insert matches");
  sqlite3_finalize(st);
}

void ExecSql(const std::string& path, const std::string& sql) {
  sqlite3* db;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE, nullptr) != SQLITE_OK) {
    sqlite3_close(db);
    throw std::runtime_error("cannot open " + path);
  }
  char* err = nullptr;
  const int rc = sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &err);
  const std::string msg = err ? err : "";
  sqlite3_free(err);
  sqlite3_close(db);
  if (rc != SQLITE_OK) throw std::runtime_error("sql: " + msg);
}

std::string IntegrityCheck(const std::string& path) {
  sqlite3* db;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) return "cannot open";
  sqlite3_stmt* st;
  std::string result = "no result";
  if (sqlite3_prepare_v2(db, "PRAGMA integrity_check", -1, &st, nullptr) == SQLITE_OK) {
    if (sqlite3_step(st) == SQLITE_ROW) result = reinterpret_cast<const char*>(sqlite3_column_text(st, 0));
    sqlite3_finalize(st);
  }
  sqlite3_close(db);
  return result;
}

std::string DumpTable(const std::string& path, const std::string& table) {
  sqlite3* db;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) return "cannot open";
  sqlite3_stmt* st;
  std::ostringstream out;
  if (sqlite3_prepare_v2(db, ("SELECT * FROM " + table + " ORDER BY 1").c_str(), -1, &st, nullptr) == SQLITE_OK) {
    while (sqlite3_step(st) == SQLITE_ROW) {
      for (int c = 0; c < sqlite3_column_count(st); ++c) {
        if (sqlite3_column_type(st, c) == SQLITE_BLOB) {
          const auto* b = static_cast<const unsigned char*>(sqlite3_column_blob(st, c));
          char hex[3];
          for (int i = 0; i < sqlite3_column_bytes(st, c); ++i) {
            std::snprintf(hex, sizeof(hex), "%02x", b[i]);
            out << hex;
          }
        } else if (sqlite3_column_type(st, c) == SQLITE_NULL) {
          out << "NULL";
        } else {
          out << sqlite3_column_text(st, c);
        }
        out << '|';
      }
      out << '\n';
    }
    sqlite3_finalize(st);
  } else {
    out << "no table " << table;
  }
  sqlite3_close(db);
  return out.str();
}

}  // namespace madsfm::testing
