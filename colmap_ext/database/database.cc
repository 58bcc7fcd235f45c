#include "colmap_ext/database/database.h"

#include <sqlite3.h>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <set>
#include <stdexcept>
#include <utility>

#include "colmap_ext/database/sqlite_util.h"

namespace madsfm::colmap {
namespace {

using sqlite::Exec;
using sqlite::Statement;
using sqlite::ThrowSqlite;

constexpr uint64_t kMaxNumImages = 2147483647;

// madsfm's own tables (COLMAP's tables are never created, altered or dropped).
constexpr const char* kBackupTwoViewTable = "madsfm_backup_two_view_geometries";
constexpr const char* kBackupCamerasTable = "madsfm_backup_cameras";
constexpr const char* kMadsfmPairsTable = "madsfm_two_view_geometries";
constexpr const char* kCreatedMatchesTable = "madsfm_created_matches";
constexpr const char* kWrittenPairsTable = "madsfm_written_two_view_geometries";

// two_view_geometries columns of every schema, and with COLMAP main's camera1 / camera2.
std::string TwoViewColumns(bool cameras) {
  return std::string("pair_id, rows, cols, data, config, F, E, H, qvec, tvec") + (cameras ? ", camera1, camera2" : "");
}
constexpr const char* kCameraColumns = "camera_id, model, width, height, params, prior_focal_length";

// Makes one write operation atomic: BEGIN IMMEDIATE ... COMMIT when no transaction is open, otherwise a savepoint
// inside the caller's transaction (so a failed operation leaves the caller's earlier writes intact). Rolls back on
// destruction unless committed; never throws from the destructor.
class ScopedTransaction {
 public:
  ScopedTransaction(sqlite3* db, const std::string& path) : db_(db), path_(path) {
    savepoint_ = sqlite3_get_autocommit(db_) == 0;
    Exec(db_, path_, savepoint_ ? "SAVEPOINT madsfm_write" : "BEGIN IMMEDIATE");
    open_ = true;
  }
  ~ScopedTransaction() {
    if (!open_) return;
    if (savepoint_) {
      sqlite3_exec(db_, "ROLLBACK TO madsfm_write", nullptr, nullptr, nullptr);
      sqlite3_exec(db_, "RELEASE madsfm_write", nullptr, nullptr, nullptr);
    } else {
      sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
    }
  }
  void Commit() {
    Exec(db_, path_, savepoint_ ? "RELEASE madsfm_write" : "COMMIT");
    open_ = false;
  }

 private:
  sqlite3* db_;
  const std::string& path_;
  bool savepoint_ = false;
  bool open_ = false;
};

bool TableExists(sqlite3* db, const std::string& path, const std::string& table) {
  Statement stmt(db, path, "SELECT 1 FROM sqlite_master WHERE type='table' AND name=?");
  stmt.BindText(1, table);
  return stmt.Step();
}

std::set<std::string> TableColumns(sqlite3* db, const std::string& path, const std::string& table) {
  std::set<std::string> columns;
  Statement stmt(db, path, "PRAGMA table_info(\"" + table + "\")");
  while (stmt.Step()) columns.insert(stmt.Text(1));
  return columns;
}

// Row-major float64 3x3 blob <-> Eigen.
std::array<double, 9> RowMajor(const Eigen::Matrix3d& m) {
  std::array<double, 9> out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out[3 * r + c] = m(r, c);
  return out;
}

bool AllZero(const double* v, int n) {
  for (int i = 0; i < n; ++i)
    if (v[i] != 0.0) return false;
  return true;
}

// Reads a float64 blob of exactly n values; NULL / empty -> false; other sizes -> error.
using What = std::function<std::string()>;  // error context, built only when an error is thrown

bool ReadDoubles(const Statement& stmt, int col, int n, double* out, const std::string& path, const What& what) {
  size_t num_bytes = 0;
  const void* data = stmt.Blob(col, &num_bytes);
  if (num_bytes == 0) return false;
  if (num_bytes != n * sizeof(double)) {
    throw std::runtime_error("'" + path + "': " + what() + " has " + std::to_string(num_bytes) + " bytes, expected " +
                             std::to_string(n * sizeof(double)) + " (" + std::to_string(n) + " float64)");
  }
  std::memcpy(out, data, num_bytes);
  return true;
}

// rows x 2 uint32 matches blob (columns rows, cols, data at col0, col0+1, col0+2).
std::vector<std::array<uint32_t, 2>> ReadMatchesBlob(const Statement& stmt, int col0, const std::string& path,
                                                     const What& what) {
  const int64_t rows = stmt.Int64(col0);
  const int64_t cols = stmt.Int64(col0 + 1);
  size_t num_bytes = 0;
  const void* data = stmt.Blob(col0 + 2, &num_bytes);
  std::vector<std::array<uint32_t, 2>> matches;
  if (rows < 0) throw std::runtime_error("'" + path + "': " + what() + " has rows = " + std::to_string(rows));
  if (rows == 0) {
    if (num_bytes != 0) {
      throw std::runtime_error("'" + path + "': " + what() + " has rows = 0 but a blob of " +
                               std::to_string(num_bytes) + " bytes");
    }
    return matches;
  }
  if (cols != 2) {
    throw std::runtime_error("'" + path + "': " + what() + " has cols = " + std::to_string(cols) + ", expected 2");
  }
  const size_t expected = static_cast<size_t>(rows) * 2 * sizeof(uint32_t);
  if (num_bytes != expected) {
    throw std::runtime_error("'" + path + "': " + what() + " blob has " + std::to_string(num_bytes) +
                             " bytes, expected " + std::to_string(expected) + " (" + std::to_string(rows) +
                             " x 2 uint32)");
  }
  matches.resize(static_cast<size_t>(rows));
  std::memcpy(matches.data(), data, expected);
  return matches;
}

// Little-endian writer / reader of the camera blob.
class LittleEndianWriter {
 public:
  template <typename T>
  void Put(T value) {
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    uint16_t probe = 1;
    unsigned char first;
    std::memcpy(&first, &probe, 1);
    if (first == 0) std::reverse(bytes, bytes + sizeof(T));  // big-endian host
    out_.insert(out_.end(), bytes, bytes + sizeof(T));
  }
  std::vector<unsigned char> Take() { return std::move(out_); }

 private:
  std::vector<unsigned char> out_;
};

template <typename T>
T GetLittleEndian(const unsigned char* p) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, p, sizeof(T));
  uint16_t probe = 1;
  unsigned char first;
  std::memcpy(&first, &probe, 1);
  if (first == 0) std::reverse(bytes, bytes + sizeof(T));
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

constexpr size_t kCameraBlobHeader = 4 + 4 + 8 + 8 + 1 + 8;

bool AllFinite(const double* v, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

void BindMatchesBlob(Statement* stmt, int i, const std::vector<std::array<uint32_t, 2>>& matches) {
  stmt->BindBlob(i, matches.data(), matches.size() * sizeof(matches[0]));
}

std::string CreateTwoViewTableSql(const std::string& name, bool cameras) {
  return "CREATE TABLE IF NOT EXISTS " + name +
         " (pair_id INTEGER PRIMARY KEY NOT NULL, rows INTEGER NOT NULL, cols INTEGER NOT NULL, data BLOB, "
         "config INTEGER NOT NULL, F BLOB, E BLOB, H BLOB, qvec BLOB, tvec BLOB" +
         std::string(cameras ? ", camera1 BLOB, camera2 BLOB" : "") + ")";
}

}  // namespace

pair_t ImagePairToPairId(image_t id1, image_t id2) {
  if (id1 > id2) std::swap(id1, id2);
  return kMaxNumImages * static_cast<uint64_t>(id1) + static_cast<uint64_t>(id2);
}

void PairIdToImagePair(pair_t pair_id, image_t* id1, image_t* id2) {
  *id2 = static_cast<image_t>(pair_id % kMaxNumImages);
  *id1 = static_cast<image_t>((pair_id - *id2) / kMaxNumImages);
}

bool ConfigHasPose(int config) {
  // COLMAP's ConfigurationType: CALIBRATED 2, UNCALIBRATED 3, PLANAR 4, PANORAMIC 5, PLANAR_OR_PANORAMIC 6,
  // CALIBRATED_RIG 9 carry a pose; UNDEFINED 0, DEGENERATE 1, WATERMARK 7, MULTIPLE 8 do not.
  return (config >= 2 && config <= 6) || config == 9;
}

std::vector<unsigned char> EncodeCameraBlob(const Camera& camera) {
  LittleEndianWriter w;
  w.Put<uint32_t>(camera.camera_id);
  w.Put<int32_t>(camera.intrinsics.model_id);
  w.Put<uint64_t>(static_cast<uint64_t>(camera.intrinsics.width));
  w.Put<uint64_t>(static_cast<uint64_t>(camera.intrinsics.height));
  w.Put<uint8_t>(camera.prior_focal_length ? 1 : 0);
  w.Put<uint64_t>(camera.intrinsics.params.size());
  for (double p : camera.intrinsics.params) w.Put<double>(p);
  return w.Take();
}

Camera DecodeCameraBlob(const void* data, size_t num_bytes, const std::string& what) {
  const unsigned char* p = static_cast<const unsigned char*>(data);
  if (num_bytes < kCameraBlobHeader) {
    throw std::runtime_error(what + " has " + std::to_string(num_bytes) + " bytes, less than the " +
                             std::to_string(kCameraBlobHeader) + " of a camera without params");
  }
  Camera camera;
  camera.camera_id = GetLittleEndian<uint32_t>(p);
  camera.intrinsics.model_id = GetLittleEndian<int32_t>(p + 4);
  const uint64_t width = GetLittleEndian<uint64_t>(p + 8), height = GetLittleEndian<uint64_t>(p + 16);
  camera.prior_focal_length = p[24] != 0;
  const uint64_t num_params = GetLittleEndian<uint64_t>(p + 25);
  if (num_params > (num_bytes - kCameraBlobHeader) / sizeof(double) ||
      num_bytes != kCameraBlobHeader + num_params * sizeof(double)) {
    throw std::runtime_error(what + " has " + std::to_string(num_bytes) + " bytes, but says " +
                             std::to_string(num_params) + " params (expected " + std::to_string(kCameraBlobHeader) +
                             " + 8 per param)");
  }
  if (width > static_cast<uint64_t>(std::numeric_limits<int>::max()) ||
      height > static_cast<uint64_t>(std::numeric_limits<int>::max())) {
    throw std::runtime_error(what + " has an implausible size " + std::to_string(width) + " x " +
                             std::to_string(height));
  }
  camera.intrinsics.width = static_cast<int>(width);
  camera.intrinsics.height = static_cast<int>(height);
  camera.intrinsics.params.resize(num_params);
  for (uint64_t i = 0; i < num_params; ++i) {
    camera.intrinsics.params[i] = GetLittleEndian<double>(p + kCameraBlobHeader + i * sizeof(double));
  }
  return camera;
}

std::string SchemaVersionName(SchemaVersion v) {
  switch (v) {
    case SchemaVersion::kColmap38:
      return "COLMAP 3.8/3.9";
    case SchemaVersion::kColmap310:
      return "COLMAP 3.10/3.11";
    case SchemaVersion::kColmap312:
      return "COLMAP 3.12/3.13";
    case SchemaVersion::kColmap4:
      return "COLMAP 4.x";
  }
  return "unknown";
}

std::unique_ptr<Database> Database::Open(const std::string& path, bool read_only, int busy_timeout_ms) {
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) {
    throw std::runtime_error("'" + path + "' does not exist (COLMAP database expected)");
  }
  if (!S_ISREG(st.st_mode)) throw std::runtime_error("'" + path + "' is not a regular file (COLMAP database expected)");
  {
    // Every SQLite 3 file starts with this 16-byte header (an empty file is rejected too: it holds no tables).
    char header[16] = {0};
    std::ifstream file(path, std::ios::binary);
    if (!file) throw std::runtime_error("'" + path + "' cannot be read");
    file.read(header, sizeof(header));
    if (file.gcount() != static_cast<std::streamsize>(sizeof(header)) ||
        std::memcmp(header, "SQLite format 3", 16) != 0) {
      throw std::runtime_error("'" + path + "' is not a SQLite database");
    }
  }
  if (!read_only && (st.st_mode & (S_IWUSR | S_IWGRP | S_IWOTH)) == 0) {
    // Respected even for root, who could write anyway: a database made read-only is meant to stay untouched.
    throw std::runtime_error("'" + path + "' is a read-only file and cannot be opened for writing");
  }

  if (read_only) sqlite::RollBackHotJournal(path, busy_timeout_ms);

  std::unique_ptr<Database> database(new Database());
  database->path_ = path;
  // Serialized threading mode: several threads may read through one Database (each call prepares its own
  // statements). Writes belong to one thread.
  const int flags = (read_only ? SQLITE_OPEN_READONLY : SQLITE_OPEN_READWRITE) | SQLITE_OPEN_FULLMUTEX;
  if (sqlite3_open_v2(path.c_str(), &database->db_, flags, nullptr) != SQLITE_OK) {
    ThrowSqlite(path, database->db_, "cannot open");
  }
  sqlite3_extended_result_codes(database->db_, 1);
  if (!read_only && sqlite3_db_readonly(database->db_, "main") == 1) {
    throw std::runtime_error("'" + path + "' cannot be opened for writing (read-only file or directory)");
  }
  sqlite3_busy_timeout(database->db_, busy_timeout_ms);

  // Schema detection from tables and columns (see colmap.md).
  std::set<std::string> tables;
  {
    sqlite3_stmt* stmt = nullptr;
    if (sqlite3_prepare_v2(database->db_, "SELECT name FROM sqlite_master WHERE type='table'", -1, &stmt, nullptr) !=
        SQLITE_OK) {
      const int code = sqlite3_errcode(database->db_) & 0xff;
      if (code == SQLITE_NOTADB) throw std::runtime_error("'" + path + "' is not a SQLite database");
      ThrowSqlite(path, database->db_, "cannot read the schema");
    }
    int rc;
    while ((rc = sqlite3_step(stmt)) == SQLITE_ROW) {
      tables.insert(reinterpret_cast<const char*>(sqlite3_column_text(stmt, 0)));
    }
    sqlite3_finalize(stmt);
    if (rc != SQLITE_DONE) ThrowSqlite(path, database->db_, "cannot read the schema");
  }
  std::string missing;
  for (const char* required : {"cameras", "images", "keypoints", "matches", "two_view_geometries"}) {
    if (tables.count(required) == 0) missing += std::string(missing.empty() ? "" : ", ") + required;
  }
  if (!missing.empty()) {
    throw std::runtime_error("'" + path + "' has an unknown schema (not a COLMAP database): missing table(s) " +
                             missing);
  }
  sqlite3* db = database->db_;
  const bool descriptors_type =
      tables.count("descriptors") != 0 && TableColumns(db, path, "descriptors").count("type") != 0;
  std::set<std::string> pose_prior_columns;
  if (tables.count("pose_priors") != 0) pose_prior_columns = TableColumns(db, path, "pose_priors");
  if (descriptors_type || pose_prior_columns.count("corr_data_id") != 0) {
    database->schema_ = SchemaVersion::kColmap4;
  } else if (tables.count("rigs") != 0 || tables.count("frames") != 0) {
    database->schema_ = SchemaVersion::kColmap312;
  } else if (pose_prior_columns.count("image_id") != 0) {
    // 3.10/3.11 (databases migrated from 3.8 keep their images.prior_* columns).
    database->schema_ = SchemaVersion::kColmap310;
  } else if (TableColumns(db, path, "images").count("prior_qw") != 0) {
    database->schema_ = SchemaVersion::kColmap38;
  } else {
    // No prior columns anywhere (e.g. a hand-made database): the columns madsfm uses are the same as 3.10's.
    database->schema_ = SchemaVersion::kColmap310;
  }
  const std::set<std::string> two_view_columns = TableColumns(db, path, "two_view_geometries");
  database->two_view_cameras_ = two_view_columns.count("camera1") != 0 && two_view_columns.count("camera2") != 0;
  {
    Statement stmt(db, path, "PRAGMA user_version");
    if (stmt.Step()) database->user_version_ = static_cast<int>(stmt.Int64(0));
  }
  return database;
}

std::string Database::DescribeImage(image_t image_id) const {
  Statement stmt(db_, path_, "SELECT name FROM images WHERE image_id = ?");
  stmt.BindInt64(1, image_id);
  if (!stmt.Step()) return "image_id " + std::to_string(image_id) + " (not in the images table)";
  return "'" + stmt.Text(0) + "' (image_id " + std::to_string(image_id) + ")";
}

std::string Database::DescribeCamera(camera_t camera_id) const {
  const std::string id = "camera_id " + std::to_string(camera_id);
  {
    Statement stmt(db_, path_, "SELECT 1 FROM cameras WHERE camera_id = ?");
    stmt.BindInt64(1, camera_id);
    if (!stmt.Step()) return id + " (not in the cameras table)";
  }
  constexpr int kMaxNames = 3;
  Statement stmt(db_, path_, "SELECT name FROM images WHERE camera_id = ? ORDER BY image_id");
  stmt.BindInt64(1, camera_id);
  std::string names;
  int count = 0;
  while (stmt.Step()) {
    if (count < kMaxNames) names += (count > 0 ? ", '" : "'") + stmt.Text(0) + "'";
    ++count;
  }
  if (count == 0) return id + " (used by no image)";
  if (count > kMaxNames) names += " and " + std::to_string(count - kMaxNames) + " more";
  return id + " (used by " + names + ")";
}

std::string Database::DescribePair(pair_t pair_id) const {
  image_t id1, id2;
  PairIdToImagePair(pair_id, &id1, &id2);
  return "pair " + std::to_string(pair_id) + " (" + DescribeImage(id1) + ", " + DescribeImage(id2) + ")";
}

Database::~Database() {
  if (db_ != nullptr) sqlite3_close_v2(db_);
}

std::vector<Camera> Database::ReadCameras() const {
  std::vector<Camera> cameras;
  Statement stmt(db_, path_, std::string("SELECT ") + kCameraColumns + " FROM cameras ORDER BY camera_id");
  while (stmt.Step()) {
    Camera camera;
    camera.camera_id = static_cast<camera_t>(stmt.Int64(0));
    camera.intrinsics.model_id = static_cast<int>(stmt.Int64(1));
    const int64_t width = stmt.Int64(2), height = stmt.Int64(3);
    if (width < 1 || height < 1 || width > std::numeric_limits<int>::max() ||
        height > std::numeric_limits<int>::max()) {
      throw std::runtime_error("'" + path_ + "': " + DescribeCamera(camera.camera_id) + " has an invalid size " +
                               std::to_string(width) + " x " + std::to_string(height) +
                               " (width and height must be positive pixel counts)");
    }
    camera.intrinsics.width = static_cast<int>(width);
    camera.intrinsics.height = static_cast<int>(height);
    size_t num_bytes = 0;
    const void* data = stmt.Blob(4, &num_bytes);
    if (num_bytes % sizeof(double) != 0) {
      throw std::runtime_error("'" + path_ + "': params of " + DescribeCamera(camera.camera_id) + " have " +
                               std::to_string(num_bytes) +
                               " bytes, not a whole number of float64");
    }
    const int num_params = CameraModelNumParams(camera.intrinsics.model_id);
    if (num_params >= 0 && num_bytes != num_params * sizeof(double)) {
      throw std::runtime_error("'" + path_ + "': params of " + DescribeCamera(camera.camera_id) + " have " +
                               std::to_string(num_bytes / sizeof(double)) + " values, camera model " +
                               CameraModelName(camera.intrinsics.model_id) + " needs " + std::to_string(num_params));
    }
    camera.intrinsics.params.resize(num_bytes / sizeof(double));
    if (num_bytes > 0) std::memcpy(camera.intrinsics.params.data(), data, num_bytes);
    camera.prior_focal_length = stmt.Int64(5) != 0;
    cameras.push_back(std::move(camera));
  }
  return cameras;
}

std::vector<Image> Database::ReadImages() const {
  std::vector<Image> images;
  Statement stmt(db_, path_, "SELECT image_id, name, camera_id FROM images ORDER BY image_id");
  while (stmt.Step()) {
    Image image;
    image.image_id = static_cast<image_t>(stmt.Int64(0));
    image.name = stmt.Text(1);
    image.camera_id = static_cast<camera_t>(stmt.Int64(2));
    images.push_back(std::move(image));
  }
  return images;
}

std::vector<Eigen::Vector2d> Database::ReadKeypoints(image_t image_id) const {
  std::vector<Eigen::Vector2d> keypoints;
  Statement stmt(db_, path_, "SELECT rows, cols, data FROM keypoints WHERE image_id = ?");
  stmt.BindInt64(1, image_id);
  if (!stmt.Step()) return keypoints;  // no keypoints row: no keypoints
  const auto what = [&] { return "keypoints of " + DescribeImage(image_id); };
  const int64_t rows = stmt.Int64(0);
  const int64_t cols = stmt.Int64(1);
  size_t num_bytes = 0;
  const void* data = stmt.Blob(2, &num_bytes);
  if (rows < 0) throw std::runtime_error("'" + path_ + "': " + what() + ": rows = " + std::to_string(rows));
  if (rows == 0) return keypoints;
  if (cols != 2 && cols != 4 && cols != 6) {
    throw std::runtime_error("'" + path_ + "': " + what() + ": cols = " + std::to_string(cols) +
                             ", expected 2, 4 or 6");
  }
  const size_t expected = static_cast<size_t>(rows) * static_cast<size_t>(cols) * sizeof(float);
  if (num_bytes != expected) {
    throw std::runtime_error("'" + path_ + "': " + what() + ": blob has " + std::to_string(num_bytes) +
                             " bytes, expected " + std::to_string(expected) + " (" + std::to_string(rows) + " x " +
                             std::to_string(cols) + " float32)");
  }
  keypoints.resize(static_cast<size_t>(rows));
  const unsigned char* bytes = static_cast<const unsigned char*>(data);
  for (int64_t i = 0; i < rows; ++i) {
    float xy[2];
    std::memcpy(xy, bytes + static_cast<size_t>(i * cols) * sizeof(float), sizeof(xy));
    keypoints[static_cast<size_t>(i)] = Eigen::Vector2d(xy[0], xy[1]);
  }
  return keypoints;
}

std::vector<std::pair<pair_t, int>> Database::ReadMatchedPairs() const {
  std::vector<std::pair<pair_t, int>> pairs;
  Statement stmt(db_, path_, "SELECT pair_id, rows FROM matches WHERE rows > 0 ORDER BY pair_id");
  while (stmt.Step()) pairs.emplace_back(static_cast<pair_t>(stmt.Int64(0)), static_cast<int>(stmt.Int64(1)));
  return pairs;
}

std::vector<std::array<uint32_t, 2>> Database::ReadMatches(pair_t pair_id) const {
  Statement stmt(db_, path_, "SELECT rows, cols, data FROM matches WHERE pair_id = ?");
  stmt.BindInt64(1, static_cast<int64_t>(pair_id));
  if (!stmt.Step()) return {};
  return ReadMatchesBlob(stmt, 0, path_, [&] { return "matches of " + DescribePair(pair_id); });
}

std::optional<std::vector<std::array<uint32_t, 2>>> Database::ReadColmapInlierMatches(pair_t pair_id) const {
  const std::string table = HasBackup() ? kBackupTwoViewTable : "two_view_geometries";
  Statement stmt(db_, path_, "SELECT rows, cols, data FROM " + table + " WHERE pair_id = ?");
  stmt.BindInt64(1, static_cast<int64_t>(pair_id));
  if (!stmt.Step()) return std::nullopt;
  return ReadMatchesBlob(stmt, 0, path_, [&] { return table + " row of " + DescribePair(pair_id); });
}

std::optional<TwoViewGeometryRow> Database::ReadTwoViewGeometry(pair_t pair_id) const {
  Statement stmt(db_, path_,
                 "SELECT " + TwoViewColumns(two_view_cameras_) + " FROM two_view_geometries WHERE pair_id = ?");
  stmt.BindInt64(1, static_cast<int64_t>(pair_id));
  if (!stmt.Step()) return std::nullopt;
  const What what = [&] { return "two_view_geometries row of " + DescribePair(pair_id); };
  TwoViewGeometryRow row;
  row.pair_id = pair_id;
  row.inlier_matches = ReadMatchesBlob(stmt, 1, path_, what);
  row.config = static_cast<int>(stmt.Int64(4));
  const char* names[3] = {"F", "E", "H"};
  std::optional<Eigen::Matrix3d>* targets[3] = {&row.F, &row.E, &row.H};
  for (int k = 0; k < 3; ++k) {
    double v[9];
    if (ReadDoubles(stmt, 5 + k, 9, v, path_, [&] { return what() + " column " + names[k]; }) && !AllZero(v, 9)) {
      Eigen::Matrix3d m;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) m(r, c) = v[3 * r + c];
      *targets[k] = m;
    }
  }
  double q[4], t[3];
  const bool has_q = ReadDoubles(stmt, 8, 4, q, path_, [&] { return what() + " column qvec"; });
  const bool has_t = ReadDoubles(stmt, 9, 3, t, path_, [&] { return what() + " column tvec"; });
  // COLMAP < 4 writes an identity / all-zero pose when none was estimated; like 4.x's migration, read it as absent.
  const bool identity = has_q && q[0] == 1 && q[1] == 0 && q[2] == 0 && q[3] == 0 && has_t && AllZero(t, 3);
  if (has_q && has_t && !AllZero(q, 4) && !identity) {
    row.qvec = Eigen::Vector4d(q[0], q[1], q[2], q[3]);
    row.tvec = Eigen::Vector3d(t[0], t[1], t[2]);
  }
  if (two_view_cameras_) {
    std::optional<Camera>* cameras[2] = {&row.camera1, &row.camera2};
    for (int k = 0; k < 2; ++k) {
      size_t num_bytes = 0;
      const void* data = stmt.Blob(10 + k, &num_bytes);
      if (stmt.IsNull(10 + k)) continue;
      *cameras[k] = DecodeCameraBlob(data, num_bytes,
                                     "'" + path_ + "': " + what() + " column camera" + std::to_string(k + 1));
    }
  }
  return row;
}

Database::Transaction::Transaction(Database* db) : db_(db) { Exec(db_->db_, db_->path_, "BEGIN IMMEDIATE"); }

Database::Transaction::~Transaction() {
  if (!done_) sqlite3_exec(db_->db_, "ROLLBACK", nullptr, nullptr, nullptr);  // errors ignored: never throw here
}

void Database::Transaction::Commit() {
  if (done_) throw std::logic_error("'" + db_->path_ + "': transaction committed twice");
  Exec(db_->db_, db_->path_, "COMMIT");  // on failure (e.g. busy) the destructor rolls back
  done_ = true;
}

void Database::BackupTwoViewGeometries() {
  if (HasBackup()) return;
  ScopedTransaction transaction(db_, path_);
  // The backup keeps every column COLMAP's table has (camera1 / camera2 too, on COLMAP main).
  Exec(db_, path_, CreateTwoViewTableSql(kBackupTwoViewTable, two_view_cameras_));
  const std::string columns = TwoViewColumns(two_view_cameras_);
  Exec(db_, path_,
       std::string("INSERT INTO ") + kBackupTwoViewTable + " (" + columns + ") SELECT " + columns +
           " FROM two_view_geometries");
  transaction.Commit();
}

bool Database::HasBackup() const { return TableExists(db_, path_, kBackupTwoViewTable); }

int Database::RestoreTwoViewGeometries() {
  ScopedTransaction transaction(db_, path_);
  const bool has_backup = HasBackup();
  const bool has_pairs = TableExists(db_, path_, kMadsfmPairsTable);
  const bool has_written = TableExists(db_, path_, kWrittenPairsTable);
  int restored = 0;

  // Pairs whose two_view_geometries row madsfm wrote.
  std::string touched;
  if (has_pairs) touched = std::string("SELECT pair_id FROM ") + kMadsfmPairsTable;
  if (has_written) {
    touched += (touched.empty() ? "" : " UNION ") + std::string("SELECT pair_id FROM ") + kWrittenPairsTable;
  }
  if (has_written && !has_backup) {
    throw std::runtime_error("'" + path_ + "': madsfm wrote two-view geometries but the backup table " +
                             kBackupTwoViewTable + " is missing; nothing restored");
  }
  // Without a backup madsfm never wrote a two_view_geometries row (the backup precedes the first write).
  if (has_backup && !touched.empty()) {
    // A backup made before COLMAP added camera1 / camera2 (ALTER TABLE) holds rows whose cameras were NULL: restoring
    // the other columns leaves them NULL.
    const bool backup_cameras = TableColumns(db_, path_, kBackupTwoViewTable).count("camera1") != 0;
    if (backup_cameras && !two_view_cameras_) {
      throw std::runtime_error("'" + path_ + "': the backup table " + kBackupTwoViewTable +
                               " has camera1 / camera2 columns but two_view_geometries has not; nothing restored");
    }
    const std::string columns = TwoViewColumns(backup_cameras);
    Exec(db_, path_, "DELETE FROM two_view_geometries WHERE pair_id IN (" + touched + ")");
    Exec(db_, path_,
         "INSERT INTO two_view_geometries (" + columns + ") SELECT " + columns + " FROM " + kBackupTwoViewTable +
             " WHERE pair_id IN (" + touched + ")");
    restored = sqlite3_changes(db_);
  }
  if (TableExists(db_, path_, kCreatedMatchesTable)) {
    Exec(db_, path_,
         std::string("DELETE FROM matches WHERE pair_id IN (SELECT pair_id FROM ") + kCreatedMatchesTable + ")");
  }
  if (TableExists(db_, path_, kBackupCamerasTable)) {
    const std::string b = kBackupCamerasTable;
    Exec(db_, path_,
         "UPDATE cameras SET "
         "model = (SELECT model FROM " + b + " WHERE " + b + ".camera_id = cameras.camera_id), "
         "width = (SELECT width FROM " + b + " WHERE " + b + ".camera_id = cameras.camera_id), "
         "height = (SELECT height FROM " + b + " WHERE " + b + ".camera_id = cameras.camera_id), "
         "params = (SELECT params FROM " + b + " WHERE " + b + ".camera_id = cameras.camera_id), "
         "prior_focal_length = (SELECT prior_focal_length FROM " + b + " WHERE " + b +
         ".camera_id = cameras.camera_id) "
         "WHERE camera_id IN (SELECT camera_id FROM " + b + ")");
  }
  for (const char* table :
       {kBackupTwoViewTable, kBackupCamerasTable, kMadsfmPairsTable, kCreatedMatchesTable, kWrittenPairsTable}) {
    Exec(db_, path_, std::string("DROP TABLE IF EXISTS ") + table);
  }
  transaction.Commit();
  return restored;
}

void Database::CheckWritable(const TwoViewGeometryRow& row) const {
  image_t id1, id2;
  PairIdToImagePair(row.pair_id, &id1, &id2);
  if (id1 >= id2 || ImagePairToPairId(id1, id2) != row.pair_id) {
    throw std::invalid_argument("'" + path_ + "': invalid pair_id " + std::to_string(row.pair_id));
  }
  const auto fail = [&](const std::string& why) {
    throw std::invalid_argument("'" + path_ + "': two-view geometry of " + DescribePair(row.pair_id) + ": " + why);
  };
  if (row.qvec.has_value() != row.tvec.has_value()) fail("qvec and tvec must both be set or both be absent");
  const char* names[3] = {"F", "E", "H"};
  const std::optional<Eigen::Matrix3d>* matrices[3] = {&row.F, &row.E, &row.H};
  for (int k = 0; k < 3; ++k) {
    if (!matrices[k]->has_value()) continue;
    const Eigen::Matrix3d& m = **matrices[k];
    if (!AllFinite(m.data(), 9)) fail(std::string(names[k]) + " is not finite");
    if (AllZero(m.data(), 9)) fail(std::string(names[k]) + " is all zero (COLMAP reads that as not estimated)");
  }
  if (row.qvec.has_value()) {
    // COLMAP < 4 wrote identity / zero poses as "not estimated", and 4.x nulls them when it opens such a database:
    // a pose madsfm writes must be a real one.
    if (!AllFinite(row.qvec->data(), 4) || !AllFinite(row.tvec->data(), 3)) fail("the pose is not finite");
    if (std::abs(row.qvec->norm() - 1.0) > 1e-6) fail("qvec is not a unit quaternion");
    if (row.tvec->norm() == 0.0) fail("tvec is zero");
    if (!ConfigHasPose(row.config)) fail("config " + std::to_string(row.config) + " has no pose, but one is given");
  }
  if ((row.camera1.has_value() || row.camera2.has_value()) && !row.E.has_value()) {
    // COLMAP main decomposes E (not F) of pairs whose intrinsics were estimated.
    fail("camera1 / camera2 need E");
  }
  const std::optional<Camera>* cameras[2] = {&row.camera1, &row.camera2};
  const image_t ids[2] = {id1, id2};
  for (int k = 0; k < 2; ++k) {
    if (!cameras[k]->has_value()) continue;
    const Camera& c = **cameras[k];
    Statement stmt(db_, path_,
                   "SELECT images.camera_id, model, width, height, length(params) FROM images JOIN cameras ON "
                   "images.camera_id = cameras.camera_id WHERE image_id = ?");
    stmt.BindInt64(1, ids[k]);
    const std::string which = "camera" + std::to_string(k + 1) + " of " + DescribeImage(ids[k]);
    if (!stmt.Step()) fail(which + ": the image or its camera is not in the database");
    const int num_params = CameraModelNumParams(c.intrinsics.model_id);
    if (static_cast<camera_t>(stmt.Int64(0)) != c.camera_id || stmt.Int64(1) != c.intrinsics.model_id ||
        stmt.Int64(2) != c.intrinsics.width || stmt.Int64(3) != c.intrinsics.height ||
        stmt.Int64(4) != static_cast<int64_t>(c.intrinsics.params.size() * sizeof(double)) ||
        (num_params >= 0 && static_cast<int>(c.intrinsics.params.size()) != num_params)) {
      fail(which + " is camera_id " + std::to_string(c.camera_id) + " " + CameraModelName(c.intrinsics.model_id) +
           " " + std::to_string(c.intrinsics.width) + "x" + std::to_string(c.intrinsics.height) + " with " +
           std::to_string(c.intrinsics.params.size()) + " params, not the image's " +
           DescribeCamera(static_cast<camera_t>(stmt.Int64(0))) + " (" +
           CameraModelName(static_cast<int>(stmt.Int64(1))) + " " + std::to_string(stmt.Int64(2)) + "x" +
           std::to_string(stmt.Int64(3)) + ")");
    }
    if (!AllFinite(c.intrinsics.params.data(), static_cast<int>(c.intrinsics.params.size()))) {
      fail(which + " has non-finite params");
    }
  }
}

void Database::WriteTwoViewGeometry(const TwoViewGeometryRow& row) {
  CheckWritable(row);
  ScopedTransaction transaction(db_, path_);
  BackupTwoViewGeometries();  // no-op once the backup exists
  Exec(db_, path_,
       std::string("CREATE TABLE IF NOT EXISTS ") + kWrittenPairsTable + " (pair_id INTEGER PRIMARY KEY NOT NULL)");
  Exec(db_, path_,
       std::string("CREATE TABLE IF NOT EXISTS ") + kCreatedMatchesTable +
           " (pair_id INTEGER PRIMARY KEY NOT NULL)");
  {
    Statement stmt(db_, path_,
                   "INSERT OR REPLACE INTO two_view_geometries (" + TwoViewColumns(two_view_cameras_) +
                       ") VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?" + std::string(two_view_cameras_ ? ", ?, ?" : "") +
                       ")");
    stmt.BindInt64(1, static_cast<int64_t>(row.pair_id));
    stmt.BindInt64(2, static_cast<int64_t>(row.inlier_matches.size()));
    stmt.BindInt64(3, 2);
    BindMatchesBlob(&stmt, 4, row.inlier_matches);
    stmt.BindInt64(5, row.config);
    const std::optional<Eigen::Matrix3d>* matrices[3] = {&row.F, &row.E, &row.H};
    for (int k = 0; k < 3; ++k) {
      if (matrices[k]->has_value()) {
        const std::array<double, 9> v = RowMajor(**matrices[k]);
        stmt.BindBlob(6 + k, v.data(), sizeof(v));
      } else {
        stmt.BindNull(6 + k);
      }
    }
    if (row.qvec.has_value()) {
      const double q[4] = {(*row.qvec)(0), (*row.qvec)(1), (*row.qvec)(2), (*row.qvec)(3)};
      const double t[3] = {(*row.tvec)(0), (*row.tvec)(1), (*row.tvec)(2)};
      stmt.BindBlob(9, q, sizeof(q));
      stmt.BindBlob(10, t, sizeof(t));
    } else {
      stmt.BindNull(9);
      stmt.BindNull(10);
    }
    std::vector<unsigned char> camera_blobs[2];  // bound by copy, but kept until Run for clarity
    if (two_view_cameras_) {
      const std::optional<Camera>* cameras[2] = {&row.camera1, &row.camera2};
      for (int k = 0; k < 2; ++k) {
        if (cameras[k]->has_value()) {
          camera_blobs[k] = EncodeCameraBlob(**cameras[k]);
          stmt.BindBlob(11 + k, camera_blobs[k].data(), camera_blobs[k].size());
        } else {
          stmt.BindNull(11 + k);
        }
      }
    }
    stmt.Run();
  }
  {
    Statement stmt(db_, path_, std::string("INSERT OR IGNORE INTO ") + kWrittenPairsTable + " (pair_id) VALUES (?)");
    stmt.BindInt64(1, static_cast<int64_t>(row.pair_id));
    stmt.Run();
  }
  // COLMAP re-matches a pair that has a two_view_geometries row but no matches row: give it one.
  bool has_matches;
  {
    Statement stmt(db_, path_, "SELECT 1 FROM matches WHERE pair_id = ?");
    stmt.BindInt64(1, static_cast<int64_t>(row.pair_id));
    has_matches = stmt.Step();
  }
  if (!has_matches) {
    Statement insert(db_, path_, "INSERT INTO matches (pair_id, rows, cols, data) VALUES (?, ?, 2, ?)");
    insert.BindInt64(1, static_cast<int64_t>(row.pair_id));
    insert.BindInt64(2, static_cast<int64_t>(row.inlier_matches.size()));
    BindMatchesBlob(&insert, 3, row.inlier_matches);
    insert.Run();
    Statement track(db_, path_, std::string("INSERT OR IGNORE INTO ") + kCreatedMatchesTable + " (pair_id) VALUES (?)");
    track.BindInt64(1, static_cast<int64_t>(row.pair_id));
    track.Run();
  }
  transaction.Commit();
}

void Database::CreateMadsfmTables() {
  ScopedTransaction transaction(db_, path_);
  Exec(db_, path_,
       std::string("CREATE TABLE IF NOT EXISTS ") + kMadsfmPairsTable +
           " (pair_id INTEGER PRIMARY KEY NOT NULL, image_id1 INTEGER NOT NULL, image_id2 INTEGER NOT NULL, "
           "R BLOB NOT NULL, t BLOB NOT NULL, scale REAL, shift1 REAL, shift2 REAL, focal1 REAL, focal2 REAL, "
           "camera_mode INTEGER NOT NULL, method INTEGER NOT NULL, num_inliers_reproj1 INTEGER NOT NULL, "
           "num_inliers_reproj2 INTEGER NOT NULL, num_inliers_sampson INTEGER NOT NULL, "
           "num_inliers INTEGER NOT NULL, score REAL, options_fingerprint TEXT, status INTEGER NOT NULL, "
           "depth_observable INTEGER, sigma_scale REAL, sigma_shift1 REAL, sigma_shift2 REAL, sigma_focal1 REAL, "
           "sigma_focal2 REAL)");
  // Tables written by madsfm versions before these columns: add them (NULL: unknown).
  const std::set<std::string> columns = TableColumns(db_, path_, kMadsfmPairsTable);
  for (const char* c : {"depth_observable INTEGER", "sigma_scale REAL", "sigma_shift1 REAL", "sigma_shift2 REAL",
                        "sigma_focal1 REAL", "sigma_focal2 REAL"}) {
    const std::string name = std::string(c).substr(0, std::string(c).find(' '));
    if (!columns.count(name)) Exec(db_, path_, std::string("ALTER TABLE ") + kMadsfmPairsTable + " ADD COLUMN " + c);
  }
  transaction.Commit();
}

void Database::WriteMadsfmPair(const MadsfmPairRow& row) {
  image_t id1, id2;
  PairIdToImagePair(row.pair_id, &id1, &id2);
  ScopedTransaction transaction(db_, path_);
  CreateMadsfmTables();
  Statement stmt(db_, path_,
                 std::string("INSERT OR REPLACE INTO ") + kMadsfmPairsTable +
                     " (pair_id, image_id1, image_id2, R, t, scale, shift1, shift2, focal1, focal2, camera_mode, "
                     "method, num_inliers_reproj1, num_inliers_reproj2, num_inliers_sampson, num_inliers, score, "
                     "options_fingerprint, status, depth_observable, sigma_scale, sigma_shift1, sigma_shift2, "
                     "sigma_focal1, sigma_focal2) VALUES "
                     "(?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
  stmt.BindInt64(1, static_cast<int64_t>(row.pair_id));
  stmt.BindInt64(2, id1);
  stmt.BindInt64(3, id2);
  const std::array<double, 9> R = RowMajor(row.R);
  const double t[3] = {row.t(0), row.t(1), row.t(2)};
  stmt.BindBlob(4, R.data(), sizeof(R));
  stmt.BindBlob(5, t, sizeof(t));
  const double reals[5] = {row.scale, row.shift1, row.shift2, row.focal1, row.focal2};
  for (int k = 0; k < 5; ++k) stmt.BindDouble(6 + k, reals[k]);  // NaN is stored as NULL, read back as NaN
  stmt.BindInt64(11, row.camera_mode);
  stmt.BindInt64(12, row.method);
  stmt.BindInt64(13, row.num_inliers_reproj1);
  stmt.BindInt64(14, row.num_inliers_reproj2);
  stmt.BindInt64(15, row.num_inliers_sampson);
  stmt.BindInt64(16, row.num_inliers);
  stmt.BindDouble(17, row.score);
  stmt.BindText(18, row.options_fingerprint);
  stmt.BindInt64(19, row.status);
  if (row.depth_observable < 0) stmt.BindNull(20);
  else stmt.BindInt64(20, row.depth_observable);
  stmt.BindDouble(21, row.sigma_scale);
  stmt.BindDouble(22, row.sigma_shift1);
  stmt.BindDouble(23, row.sigma_shift2);
  stmt.BindDouble(24, row.sigma_focal1);
  stmt.BindDouble(25, row.sigma_focal2);
  stmt.Run();
  transaction.Commit();
}

namespace {

constexpr const char* kMadsfmPairColumns =
    "pair_id, R, t, scale, shift1, shift2, focal1, focal2, camera_mode, method, num_inliers_reproj1, "
    "num_inliers_reproj2, num_inliers_sampson, num_inliers, score, options_fingerprint, status";
// The columns added later, or NULLs in their place for a table written before them (a read-only database is not
// migrated).
std::string MadsfmPairSelect(sqlite3* db, const std::string& path) {
  const std::set<std::string> columns = TableColumns(db, path, kMadsfmPairsTable);
  const bool has = columns.count("depth_observable") > 0, has_focal = columns.count("sigma_focal1") > 0;
  return std::string("SELECT ") + kMadsfmPairColumns +
         (has ? ", depth_observable, sigma_scale, sigma_shift1, sigma_shift2" : ", NULL, NULL, NULL, NULL") +
         (has_focal ? ", sigma_focal1, sigma_focal2" : ", NULL, NULL") + " FROM " + kMadsfmPairsTable;
}

MadsfmPairRow ReadMadsfmPairRow(const Statement& stmt, const Database& db) {
  const std::string& path = db.path();
  MadsfmPairRow row;
  row.pair_id = static_cast<pair_t>(stmt.Int64(0));
  const What what = [&] { return std::string(kMadsfmPairsTable) + " row of " + db.DescribePair(row.pair_id); };
  double R[9], t[3];
  if (!ReadDoubles(stmt, 1, 9, R, path, [&] { return what() + " column R"; }) ||
      !ReadDoubles(stmt, 2, 3, t, path, [&] { return what() + " column t"; })) {
    throw std::runtime_error("'" + path + "': " + what() + " has no R or t");
  }
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) row.R(r, c) = R[3 * r + c];
  row.t = Eigen::Vector3d(t[0], t[1], t[2]);
  row.scale = stmt.Double(3);
  row.shift1 = stmt.Double(4);
  row.shift2 = stmt.Double(5);
  row.focal1 = stmt.Double(6);
  row.focal2 = stmt.Double(7);
  row.camera_mode = static_cast<int>(stmt.Int64(8));
  row.method = static_cast<int>(stmt.Int64(9));
  row.num_inliers_reproj1 = static_cast<int>(stmt.Int64(10));
  row.num_inliers_reproj2 = static_cast<int>(stmt.Int64(11));
  row.num_inliers_sampson = static_cast<int>(stmt.Int64(12));
  row.num_inliers = static_cast<int>(stmt.Int64(13));
  row.score = stmt.Double(14);
  row.options_fingerprint = stmt.Text(15);
  row.status = static_cast<int>(stmt.Int64(16));
  row.depth_observable = stmt.IsNull(17) ? -1 : static_cast<int>(stmt.Int64(17));
  row.sigma_scale = stmt.Double(18);
  row.sigma_shift1 = stmt.Double(19);
  row.sigma_shift2 = stmt.Double(20);
  row.sigma_focal1 = stmt.Double(21);
  row.sigma_focal2 = stmt.Double(22);
  return row;
}

}  // namespace

std::optional<MadsfmPairRow> Database::ReadMadsfmPair(pair_t pair_id) const {
  if (!TableExists(db_, path_, kMadsfmPairsTable)) return std::nullopt;
  Statement stmt(db_, path_, MadsfmPairSelect(db_, path_) + " WHERE pair_id = ?");
  stmt.BindInt64(1, static_cast<int64_t>(pair_id));
  if (!stmt.Step()) return std::nullopt;
  return ReadMadsfmPairRow(stmt, *this);
}

std::vector<MadsfmPairRow> Database::ReadMadsfmPairs() const {
  std::vector<MadsfmPairRow> rows;
  if (!TableExists(db_, path_, kMadsfmPairsTable)) return rows;
  Statement stmt(db_, path_, MadsfmPairSelect(db_, path_) + " ORDER BY pair_id");
  while (stmt.Step()) rows.push_back(ReadMadsfmPairRow(stmt, *this));
  return rows;
}

void Database::UpdateCamera(const Camera& camera) {
  ScopedTransaction transaction(db_, path_);
  const std::string what = DescribeCamera(camera.camera_id);
  int stored_model;
  {
    Statement stmt(db_, path_, "SELECT model FROM cameras WHERE camera_id = ?");
    stmt.BindInt64(1, camera.camera_id);
    if (!stmt.Step()) throw std::runtime_error("'" + path_ + "': UpdateCamera: " + what);
    stored_model = static_cast<int>(stmt.Int64(0));
  }
  const int num_params = CameraModelNumParams(stored_model);
  if (stored_model != camera.intrinsics.model_id ||
      (num_params >= 0 && static_cast<int>(camera.intrinsics.params.size()) != num_params)) {
    throw std::invalid_argument("'" + path_ + "': UpdateCamera: " + what + " is " + CameraModelName(stored_model) +
                                " in the database; got model " + CameraModelName(camera.intrinsics.model_id) +
                                " with " + std::to_string(camera.intrinsics.params.size()) + " params");
  }
  Exec(db_, path_,
       std::string("CREATE TABLE IF NOT EXISTS ") + kBackupCamerasTable +
           " (camera_id INTEGER PRIMARY KEY NOT NULL, model INTEGER NOT NULL, width INTEGER NOT NULL, "
           "height INTEGER NOT NULL, params BLOB, prior_focal_length INTEGER NOT NULL)");
  {
    // The original row, once (later updates keep the first backup).
    Statement stmt(db_, path_,
                   std::string("INSERT OR IGNORE INTO ") + kBackupCamerasTable + " (" + kCameraColumns + ") SELECT " +
                       kCameraColumns + " FROM cameras WHERE camera_id = ?");
    stmt.BindInt64(1, camera.camera_id);
    stmt.Run();
  }
  {
    Statement stmt(db_, path_, "UPDATE cameras SET params = ?, prior_focal_length = ? WHERE camera_id = ?");
    stmt.BindBlob(1, camera.intrinsics.params.data(), camera.intrinsics.params.size() * sizeof(double));
    stmt.BindInt64(2, camera.prior_focal_length ? 1 : 0);
    stmt.BindInt64(3, camera.camera_id);
    stmt.Run();
  }
  transaction.Commit();
}

std::vector<std::string> Database::ListTables() const {
  std::vector<std::string> tables;
  sqlite3_stmt* st = nullptr;
  if (sqlite3_prepare_v2(db_, "SELECT name FROM sqlite_master WHERE type = 'table'", -1, &st, nullptr) != SQLITE_OK) {
    throw std::runtime_error("'" + path_ + "': cannot list tables: " + sqlite3_errmsg(db_));
  }
  while (sqlite3_step(st) == SQLITE_ROW) tables.emplace_back(reinterpret_cast<const char*>(sqlite3_column_text(st, 0)));
  sqlite3_finalize(st);
  return tables;
}

}  // namespace madsfm::colmap
