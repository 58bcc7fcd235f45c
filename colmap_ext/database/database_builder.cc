#include "colmap_ext/database/database_builder.h"

#include <sqlite3.h>

#include <stdexcept>

#include "colmap_ext/database/database.h"
#include "colmap_ext/database/database_schema.h"

namespace madsfm::colmap {
namespace {

constexpr int kSensorTypeCamera = 0;  // COLMAP's SensorType::CAMERA (INVALID = -1, CAMERA = 0, IMU = 1)

}  // namespace

bool DatabaseBuilder::HasRigs() const {
  return static_cast<int>(release_) >= static_cast<int>(ColmapRelease::k3_12);
}

DatabaseBuilder::DatabaseBuilder(const std::string& path, ColmapRelease release) : path_(path), release_(release) {
  CreateColmapDatabase(path, release);
  if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READWRITE, nullptr) != SQLITE_OK) {
    const std::string msg = sqlite3_errmsg(db_);
    sqlite3_close(db_);
    db_ = nullptr;
    throw std::runtime_error("cannot open new database '" + path + "': " + msg);
  }
}

DatabaseBuilder::~DatabaseBuilder() {
  for (sqlite3_stmt* st : statements_) sqlite3_finalize(st);
  sqlite3_close(db_);
}

void DatabaseBuilder::Exec(const std::string& sql) {
  char* err = nullptr;
  if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
    const std::string msg = err ? err : "?";
    sqlite3_free(err);
    throw std::runtime_error("database '" + path_ + "': " + msg);
  }
}

sqlite3_stmt* DatabaseBuilder::Prepare(int which, const char* sql) {
  if (!statements_[which] && sqlite3_prepare_v2(db_, sql, -1, &statements_[which], nullptr) != SQLITE_OK) {
    throw std::runtime_error("database '" + path_ + "': " + sqlite3_errmsg(db_));
  }
  return statements_[which];
}

void DatabaseBuilder::Step(sqlite3_stmt* st, const std::string& what) {
  const int rc = sqlite3_step(st);
  sqlite3_reset(st);
  sqlite3_clear_bindings(st);
  if (rc != SQLITE_DONE) throw std::runtime_error("database '" + path_ + "': " + what + ": " + sqlite3_errmsg(db_));
}

uint32_t DatabaseBuilder::AddCamera(int model_id, int width, int height, const std::vector<double>& params,
                                    bool prior_focal) {
  sqlite3_stmt* st =
      Prepare(0, "INSERT INTO cameras(model, width, height, params, prior_focal_length) VALUES(?,?,?,?,?)");
  sqlite3_bind_int(st, 1, model_id);
  sqlite3_bind_int(st, 2, width);
  sqlite3_bind_int(st, 3, height);
  sqlite3_bind_blob(st, 4, params.data(), static_cast<int>(params.size() * sizeof(double)), SQLITE_TRANSIENT);
  sqlite3_bind_int(st, 5, prior_focal ? 1 : 0);
  Step(st, "insert camera");
  const uint32_t camera_id = static_cast<uint32_t>(sqlite3_last_insert_rowid(db_));
  if (HasRigs()) {
    Exec("INSERT INTO rigs(rig_id, ref_sensor_id, ref_sensor_type) VALUES(" + std::to_string(camera_id) + ", " +
         std::to_string(camera_id) + ", " + std::to_string(kSensorTypeCamera) + ")");
  }
  return camera_id;
}

uint32_t DatabaseBuilder::AddImage(const std::string& name, uint32_t camera_id) {
  sqlite3_stmt* st = Prepare(1, "INSERT INTO images(name, camera_id) VALUES(?,?)");
  sqlite3_bind_text(st, 1, name.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_int64(st, 2, camera_id);
  Step(st, "insert image '" + name + "'");
  const uint32_t image_id = static_cast<uint32_t>(sqlite3_last_insert_rowid(db_));
  names_[image_id] = name;
  if (HasRigs()) {
    const std::string id = std::to_string(image_id), camera = std::to_string(camera_id);
    Exec("INSERT INTO frames(frame_id, rig_id) VALUES(" + id + ", " + camera + "); "
         "INSERT INTO frame_data(frame_id, data_id, sensor_id, sensor_type) VALUES(" + id + ", " + id + ", " + camera +
         ", " + std::to_string(kSensorTypeCamera) + ")");
  }
  return image_id;
}

void DatabaseBuilder::AddKeypoints(uint32_t image_id, const std::vector<Eigen::Vector2d>& keypoints) {
  std::vector<float> data;
  data.reserve(6 * keypoints.size());
  for (const auto& k : keypoints) {
    data.insert(data.end(), {static_cast<float>(k.x()), static_cast<float>(k.y()), 1.0f, 0.0f, 0.0f, 1.0f});
  }
  sqlite3_stmt* st = Prepare(2, "INSERT INTO keypoints(image_id, rows, cols, data) VALUES(?,?,6,?)");
  sqlite3_bind_int64(st, 1, image_id);
  sqlite3_bind_int(st, 2, static_cast<int>(keypoints.size()));
  sqlite3_bind_blob(st, 3, data.data(), static_cast<int>(data.size() * sizeof(float)), SQLITE_TRANSIENT);
  const auto name = names_.find(image_id);
  Step(st, "insert keypoints of " +
               (name == names_.end() ? std::string() : "'" + name->second + "' ") + "(image_id " +
               std::to_string(image_id) + ")");
}

void DatabaseBuilder::AddMatches(uint32_t a, uint32_t b, const std::vector<std::array<uint32_t, 2>>& matches) {
  std::vector<uint32_t> data;
  data.reserve(2 * matches.size());
  for (const auto& m : matches) {
    if (a < b) data.insert(data.end(), {m[0], m[1]});
    else data.insert(data.end(), {m[1], m[0]});
  }
  sqlite3_stmt* st = Prepare(3, "INSERT INTO matches(pair_id, rows, cols, data) VALUES(?,?,2,?)");
  sqlite3_bind_int64(st, 1, static_cast<sqlite3_int64>(ImagePairToPairId(a, b)));
  sqlite3_bind_int(st, 2, static_cast<int>(matches.size()));
  sqlite3_bind_blob(st, 3, data.data(), static_cast<int>(data.size() * sizeof(uint32_t)), SQLITE_TRANSIENT);
  const auto label = [&](uint32_t id) {
    const auto name = names_.find(id);
    return (name == names_.end() ? std::string() : "'" + name->second + "' ") + "(image_id " + std::to_string(id) + ")";
  };
  Step(st, "insert matches of " + label(a) + ", " + label(b));
}

}  // namespace madsfm::colmap
