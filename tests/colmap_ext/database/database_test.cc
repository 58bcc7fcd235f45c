// madsfm's SQLite layer over COLMAP databases: schema detection (a database made by Debian's `colmap` 3.8 binary and
// synthetic 3.8 / 3.10 / 3.11 / 3.12 / 4.1.1 schemas), exact read-back of everything populated with raw SQL, two-view
// geometry writes (blob sizes, NULL rules, the matches row COLMAP needs), backup/restore to the original bytes,
// madsfm's own tables, transactions, and the errors of bad inputs.
#include "colmap_ext/database/database.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <Eigen/Geometry>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <stdexcept>
#include <thread>

#include "colmap_ext/database/database_builder.h"
#include "colmap_ext/database/database_schema.h"

namespace madsfm::colmap {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------------------------
// Test helpers: temp dirs, raw SQL, schemas, population.

class TempDir {
 public:
  TempDir() {
    std::string pattern = (fs::path(::testing::TempDir()) / "madsfm_db_test_XXXXXX").string();
    char* dir = ::mkdtemp(pattern.data());
    if (dir == nullptr) throw std::runtime_error("mkdtemp failed");
    path_ = dir;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string File(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

// A raw sqlite3 connection for setting up and inspecting databases behind the layer's back.
class RawDb {
 public:
  explicit RawDb(const std::string& path) {
    if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) != SQLITE_OK) {
      throw std::runtime_error("cannot open " + path);
    }
  }
  ~RawDb() { sqlite3_close_v2(db_); }
  void Exec(const std::string& sql) {
    char* error = nullptr;
    if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &error) != SQLITE_OK) {
      const std::string message = error ? error : "?";
      sqlite3_free(error);
      throw std::runtime_error(sql + ": " + message);
    }
  }
  // Runs sql with ? parameters: each argument an int64, a double, a string (text) or a blob (std::vector<char>).
  struct Value {
    enum Kind { kInt, kReal, kText, kBlob, kNull } kind = kNull;
    int64_t i = 0;
    double d = 0;
    std::string s;
    Value(int64_t v) : kind(kInt), i(v) {}                    // NOLINT
    Value(int v) : kind(kInt), i(v) {}                        // NOLINT
    Value(double v) : kind(kReal), d(v) {}                    // NOLINT
    Value(const char* v) : kind(kText), s(v) {}               // NOLINT
    static Value Blob(const void* data, size_t n) {
      Value v(0);
      v.kind = kBlob;
      v.s.assign(static_cast<const char*>(data), n);
      return v;
    }
    static Value Null() {
      Value v(0);
      v.kind = kNull;
      return v;
    }
  };
  void Run(const std::string& sql, const std::vector<Value>& values) {
    sqlite3_stmt* stmt = nullptr;
    if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &stmt, nullptr) != SQLITE_OK) {
      throw std::runtime_error(sql + ": " + sqlite3_errmsg(db_));
    }
    for (size_t k = 0; k < values.size(); ++k) {
      const Value& v = values[k];
      const int i = static_cast<int>(k) + 1;
      switch (v.kind) {
        case Value::kInt: sqlite3_bind_int64(stmt, i, v.i); break;
        case Value::kReal: sqlite3_bind_double(stmt, i, v.d); break;
        case Value::kText: sqlite3_bind_text(stmt, i, v.s.c_str(), -1, SQLITE_TRANSIENT); break;
        case Value::kBlob:
          if (v.s.empty()) {
            sqlite3_bind_zeroblob(stmt, i, 0);
          } else {
            sqlite3_bind_blob(stmt, i, v.s.data(), static_cast<int>(v.s.size()), SQLITE_TRANSIENT);
          }
          break;
        case Value::kNull: sqlite3_bind_null(stmt, i); break;
      }
    }
    const int rc = sqlite3_step(stmt);
    sqlite3_finalize(stmt);
    if (rc != SQLITE_DONE && rc != SQLITE_ROW) throw std::runtime_error(sql + ": " + sqlite3_errmsg(db_));
  }
  // Every cell of a query as "type:bytes" (exact: blobs byte for byte, reals bit for bit).
  std::vector<std::vector<std::string>> Snapshot(const std::string& sql) {
    sqlite3_stmt* stmt = nullptr;
    if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &stmt, nullptr) != SQLITE_OK) {
      throw std::runtime_error(sql + ": " + sqlite3_errmsg(db_));
    }
    std::vector<std::vector<std::string>> rows;
    while (sqlite3_step(stmt) == SQLITE_ROW) {
      std::vector<std::string> row;
      for (int c = 0; c < sqlite3_column_count(stmt); ++c) {
        const int type = sqlite3_column_type(stmt, c);
        std::string cell = std::to_string(type) + ":";
        if (type == SQLITE_INTEGER) {
          cell += std::to_string(sqlite3_column_int64(stmt, c));
        } else if (type == SQLITE_FLOAT) {
          const double d = sqlite3_column_double(stmt, c);
          cell.append(reinterpret_cast<const char*>(&d), sizeof(d));
        } else if (type != SQLITE_NULL) {
          const void* data = sqlite3_column_blob(stmt, c);
          cell.append(static_cast<const char*>(data), sqlite3_column_bytes(stmt, c));
        }
        row.push_back(cell);
      }
      rows.push_back(row);
    }
    sqlite3_finalize(stmt);
    return rows;
  }
  std::string QueryText(const std::string& sql) {
    const auto rows = Snapshot(sql);
    if (rows.empty() || rows[0].empty()) return "<no row>";
    return rows[0][0].substr(rows[0][0].find(':') + 1);
  }
  int64_t QueryInt(const std::string& sql) { return std::stoll(QueryText(sql)); }
  sqlite3* handle() { return db_; }

 private:
  sqlite3* db_ = nullptr;
};

template <typename T>
RawDb::Value BlobOf(const std::vector<T>& v) {
  return RawDb::Value::Blob(v.data(), v.size() * sizeof(T));
}

bool HaveColmap() { return std::system("command -v colmap > /dev/null 2>&1") == 0; }

void CreateWithColmap(const std::string& path) {
  const std::string cmd = "colmap database_creator --database_path '" + path + "' > '" + path + ".log' 2>&1";
  if (std::system(cmd.c_str()) != 0) throw std::runtime_error("colmap database_creator failed: " + cmd);
}

// Databases of every COLMAP release come from DatabaseBuilder (its schemas restate each release's CREATE statements,
// docs/formats.md); two more are what COLMAP leaves when it opens an older database.
enum class Migration {
  kNone,
  k38OpenedBy311,   // 3.11 adds pose_priors (with position_covariance), keeps images.prior_*, user_version 3900
  k38OpenedByMain,  // main adds rigs/frames, the 4.x pose_priors, descriptors.type, camera1/camera2 (ALTER TABLE)
};

struct SchemaCase {
  std::string label;
  ColmapRelease release;
  Migration migration;
  SchemaVersion expected;
  bool cameras;  // two_view_geometries has camera1 / camera2
  int user_version;
};

void CreateSynthetic(const std::string& path, const SchemaCase& c) {
  { DatabaseBuilder builder(path, c.release); }
  RawDb db(path);
  switch (c.migration) {
    case Migration::kNone:
      break;
    case Migration::k38OpenedBy311:
      db.Exec("CREATE TABLE pose_priors (image_id INTEGER PRIMARY KEY NOT NULL, position BLOB, coordinate_system "
              "INTEGER NOT NULL, position_covariance BLOB, FOREIGN KEY(image_id) REFERENCES images(image_id) ON "
              "DELETE CASCADE); PRAGMA user_version = 3900;");
      break;
    case Migration::k38OpenedByMain:
      db.Exec(R"SQL(
CREATE TABLE rigs (rig_id INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, ref_sensor_id INTEGER NOT NULL, ref_sensor_type INTEGER NOT NULL);
CREATE TABLE rig_sensors (rig_id INTEGER NOT NULL, sensor_id INTEGER NOT NULL, sensor_type INTEGER NOT NULL, sensor_from_rig BLOB, FOREIGN KEY(rig_id) REFERENCES rigs(rig_id) ON DELETE CASCADE);
CREATE TABLE frames (frame_id INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, rig_id INTEGER NOT NULL, FOREIGN KEY(rig_id) REFERENCES rigs(rig_id) ON DELETE CASCADE);
CREATE TABLE frame_data (frame_id INTEGER NOT NULL, data_id INTEGER NOT NULL, sensor_id INTEGER NOT NULL, sensor_type INTEGER NOT NULL, FOREIGN KEY(frame_id) REFERENCES frames(frame_id) ON DELETE CASCADE);
CREATE TABLE pose_priors (pose_prior_id INTEGER PRIMARY KEY NOT NULL, corr_data_id INTEGER NOT NULL, corr_sensor_id INTEGER NOT NULL, corr_sensor_type INTEGER NOT NULL, position BLOB, position_covariance BLOB, gravity BLOB, coordinate_system INTEGER NOT NULL);
ALTER TABLE descriptors ADD COLUMN type INTEGER NOT NULL DEFAULT 0;
ALTER TABLE two_view_geometries ADD COLUMN camera1 BLOB;
ALTER TABLE two_view_geometries ADD COLUMN camera2 BLOB;
PRAGMA user_version = 4020000;
)SQL");
      break;
  }
}

std::vector<SchemaCase> AllSchemaCases() {
  std::vector<SchemaCase> cases;
  for (ColmapRelease r : AllColmapReleases()) {
    SchemaCase c{ColmapReleaseName(r), r, Migration::kNone, SchemaVersion::kColmap4, r == ColmapRelease::kMain,
                 ColmapReleaseUserVersion(r)};
    if (r == ColmapRelease::k3_8 || r == ColmapRelease::k3_9) c.expected = SchemaVersion::kColmap38;
    if (r == ColmapRelease::k3_10 || r == ColmapRelease::k3_11) c.expected = SchemaVersion::kColmap310;
    if (r == ColmapRelease::k3_12 || r == ColmapRelease::k3_13) c.expected = SchemaVersion::kColmap312;
    cases.push_back(c);
  }
  cases.push_back({"3.8 opened by 3.11", ColmapRelease::k3_8, Migration::k38OpenedBy311, SchemaVersion::kColmap310,
                   false, 3900});
  cases.push_back({"3.8 opened by main", ColmapRelease::k3_8, Migration::k38OpenedByMain, SchemaVersion::kColmap4,
                   true, 4020000});
  return cases;
}

bool HasCameraColumns(RawDb* db) {
  return db->QueryInt("SELECT count(*) FROM pragma_table_info('two_view_geometries') WHERE name IN "
                      "('camera1', 'camera2')") == 2;
}

// What Populate() wrote, for exact comparison.
struct Expected {
  std::vector<Camera> cameras;
  std::vector<Image> images;
  std::map<image_t, std::vector<Eigen::Vector2d>> keypoints;  // images without a row are absent
  std::map<pair_t, std::vector<std::array<uint32_t, 2>>> matches;
  std::map<pair_t, TwoViewGeometryRow> two_view;  // as madsfm should read them back
};

Camera MakeCamera(camera_t id, int model, int w, int h, std::vector<double> params, bool prior) {
  Camera c;
  c.camera_id = id;
  c.intrinsics.model_id = model;
  c.intrinsics.width = w;
  c.intrinsics.height = h;
  c.intrinsics.params = std::move(params);
  c.prior_focal_length = prior;
  return c;
}

std::vector<double> RowMajor(const Eigen::Matrix3d& m) {
  std::vector<double> v;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) v.push_back(m(r, c));
  return v;
}

std::vector<std::array<uint32_t, 2>> RandomMatches(std::mt19937* rng, int n, uint32_t n1, uint32_t n2) {
  std::vector<std::array<uint32_t, 2>> m(n);
  for (auto& a : m) a = {static_cast<uint32_t>((*rng)() % n1), static_cast<uint32_t>((*rng)() % n2)};
  return m;
}

// Fills cameras, images, keypoints, matches and COLMAP-3.8-style two_view_geometries rows with raw SQL, using only
// columns every schema has. exotic_cameras adds cameras of a 4.x-only model (11) and an unknown model id (99).
Expected Populate(const std::string& path, bool exotic_cameras) {
  Expected e;
  std::mt19937 rng(1234);
  RawDb db(path);
  db.Exec("BEGIN");

  e.cameras.push_back(MakeCamera(1, 2, 640, 480, {600, 320, 240, 0.01}, false));
  e.cameras.push_back(MakeCamera(2, 1, 1024, 768, {800, 810, 512.5, 383.5}, true));
  e.cameras.push_back(MakeCamera(3, 4, 1920, 1080, {1500, 1490, 960, 540, -0.1, 0.01, 0.001, -0.0005}, true));
  if (exotic_cameras) {
    std::vector<double> params16(16);
    for (int i = 0; i < 16; ++i) params16[i] = 0.5 * i + 1;
    e.cameras.push_back(MakeCamera(4, 11, 1280, 1024, params16, false));
    e.cameras.push_back(MakeCamera(5, 99, 100, 100, {1, 2, 3}, false));
  }
  for (const Camera& c : e.cameras) {
    db.Run("INSERT INTO cameras (camera_id, model, width, height, params, prior_focal_length) VALUES (?,?,?,?,?,?)",
           {static_cast<int64_t>(c.camera_id), c.intrinsics.model_id, c.intrinsics.width, c.intrinsics.height,
            BlobOf(c.intrinsics.params), c.prior_focal_length ? 1 : 0});
  }

  const std::vector<std::pair<std::string, camera_t>> images = {
      {"a/img1.jpg", 1}, {"img2.png", 2}, {"b/c/img3.jpg", 3}, {"img4.jpg", 1}, {"img5.jpg", 2}};
  for (size_t i = 0; i < images.size(); ++i) {
    Image image;
    image.image_id = static_cast<image_t>(i + 1);
    image.name = images[i].first;
    image.camera_id = images[i].second;
    e.images.push_back(image);
    db.Run("INSERT INTO images (image_id, name, camera_id) VALUES (?,?,?)",
           {static_cast<int64_t>(image.image_id), image.name.c_str(), static_cast<int64_t>(image.camera_id)});
  }

  // Keypoints with 6 (SIFT affine), 4 and 2 columns; image 5 has no keypoints row.
  const std::vector<std::pair<int, int>> kp_shape = {{500, 6}, {300, 4}, {200, 2}, {250, 6}};
  std::uniform_real_distribution<float> coord(0.0f, 1000.0f);
  for (size_t i = 0; i < kp_shape.size(); ++i) {
    const image_t id = static_cast<image_t>(i + 1);
    const int rows = kp_shape[i].first, cols = kp_shape[i].second;
    std::vector<float> data(static_cast<size_t>(rows * cols));
    for (float& v : data) v = coord(rng);
    db.Run("INSERT INTO keypoints (image_id, rows, cols, data) VALUES (?,?,?,?)",
           {static_cast<int64_t>(id), rows, cols, BlobOf(data)});
    auto& kp = e.keypoints[id];
    for (int r = 0; r < rows; ++r) kp.emplace_back(data[r * cols], data[r * cols + 1]);
  }

  // Matches: (1,2), (1,3), (2,3), (2,4) with rows; (3,4) with rows = 0 (empty blob, as COLMAP writes it).
  const struct {
    image_t a, b;
    int n;
  } kMatches[] = {{1, 2, 120}, {1, 3, 80}, {2, 3, 60}, {2, 4, 50}, {3, 4, 0}};
  for (const auto& m : kMatches) {
    const pair_t pair_id = ImagePairToPairId(m.a, m.b);
    const auto matches = RandomMatches(&rng, m.n, 200, 200);
    db.Run("INSERT INTO matches (pair_id, rows, cols, data) VALUES (?,?,?,?)",
           {static_cast<int64_t>(pair_id), m.n, 2, BlobOf(matches)});
    e.matches[pair_id] = matches;
  }

  // Original two-view geometries, written the way COLMAP 3.8 writes them: all five blobs, zero E/H and identity pose
  // when not estimated (read back as absent), NULL blobs when there are no inliers.
  {
    TwoViewGeometryRow row;
    row.pair_id = ImagePairToPairId(1, 2);
    row.inlier_matches.assign(e.matches[row.pair_id].begin(), e.matches[row.pair_id].begin() + 100);
    row.config = kCalibrated;
    row.F = Eigen::Matrix3d::Random();
    row.E = Eigen::Matrix3d::Random();
    row.H = Eigen::Matrix3d::Random();
    row.qvec = Eigen::Vector4d(0.9, 0.1, -0.3, 0.2).normalized();
    row.tvec = Eigen::Vector3d(0.3, -0.1, 0.95);
    db.Run("INSERT INTO two_view_geometries (pair_id, rows, cols, data, config, F, E, H, qvec, tvec) VALUES "
           "(?,?,?,?,?,?,?,?,?,?)",
           {static_cast<int64_t>(row.pair_id), 100, 2, BlobOf(row.inlier_matches), row.config, BlobOf(RowMajor(*row.F)),
            BlobOf(RowMajor(*row.E)), BlobOf(RowMajor(*row.H)),
            BlobOf(std::vector<double>(row.qvec->data(), row.qvec->data() + 4)),
            BlobOf(std::vector<double>(row.tvec->data(), row.tvec->data() + 3))});
    if (HasCameraColumns(&db)) {
      // COLMAP main's solver estimated image 1's focal (its camera with another focal); image 2's not (NULL).
      Camera camera1 = e.cameras[0];
      camera1.intrinsics.SetFocal(655.5);
      row.camera1 = camera1;
      const std::vector<unsigned char> blob = EncodeCameraBlob(camera1);
      db.Run("UPDATE two_view_geometries SET camera1 = ?, camera2 = NULL WHERE pair_id = ?",
             {RawDb::Value::Blob(blob.data(), blob.size()), static_cast<int64_t>(row.pair_id)});
    }
    e.two_view[row.pair_id] = row;
  }
  {
    TwoViewGeometryRow row;
    row.pair_id = ImagePairToPairId(1, 3);
    row.inlier_matches.assign(e.matches[row.pair_id].begin(), e.matches[row.pair_id].begin() + 40);
    row.config = kUncalibrated;
    row.F = Eigen::Matrix3d::Random();
    db.Run("INSERT INTO two_view_geometries (pair_id, rows, cols, data, config, F, E, H, qvec, tvec) VALUES "
           "(?,?,?,?,?,?,?,?,?,?)",
           {static_cast<int64_t>(row.pair_id), 40, 2, BlobOf(row.inlier_matches), row.config, BlobOf(RowMajor(*row.F)),
            BlobOf(std::vector<double>(9, 0.0)), BlobOf(std::vector<double>(9, 0.0)),
            BlobOf(std::vector<double>{1, 0, 0, 0}), BlobOf(std::vector<double>(3, 0.0))});
    e.two_view[row.pair_id] = row;
  }
  {
    TwoViewGeometryRow row;
    row.pair_id = ImagePairToPairId(3, 4);
    row.config = kDegenerate;
    db.Run("INSERT INTO two_view_geometries (pair_id, rows, cols, data, config, F, E, H, qvec, tvec) VALUES "
           "(?,?,?,NULL,?,NULL,NULL,NULL,NULL,NULL)",
           {static_cast<int64_t>(row.pair_id), 0, 2, row.config});
    e.two_view[row.pair_id] = row;
  }
  db.Exec("COMMIT");
  return e;
}

void ExpectSameRow(const TwoViewGeometryRow& a, const TwoViewGeometryRow& b) {
  EXPECT_EQ(a.pair_id, b.pair_id);
  EXPECT_EQ(a.inlier_matches, b.inlier_matches);
  EXPECT_EQ(a.config, b.config);
  const std::optional<Eigen::Matrix3d>* ma[3] = {&a.F, &a.E, &a.H};
  const std::optional<Eigen::Matrix3d>* mb[3] = {&b.F, &b.E, &b.H};
  for (int k = 0; k < 3; ++k) {
    ASSERT_EQ(ma[k]->has_value(), mb[k]->has_value()) << "matrix " << k;
    if (ma[k]->has_value()) {
      EXPECT_EQ(**ma[k], **mb[k]) << "matrix " << k;  // exact: bytes round trip
    }
  }
  ASSERT_EQ(a.qvec.has_value(), b.qvec.has_value());
  ASSERT_EQ(a.tvec.has_value(), b.tvec.has_value());
  if (a.qvec) {
    EXPECT_EQ(*a.qvec, *b.qvec);
    EXPECT_EQ(*a.tvec, *b.tvec);
  }
  const std::optional<Camera>* ca[2] = {&a.camera1, &a.camera2};
  const std::optional<Camera>* cb[2] = {&b.camera1, &b.camera2};
  for (int k = 0; k < 2; ++k) {
    ASSERT_EQ(ca[k]->has_value(), cb[k]->has_value()) << "camera" << k + 1;
    if (!ca[k]->has_value()) continue;
    const Camera &x = **ca[k], &y = **cb[k];
    EXPECT_EQ(x.camera_id, y.camera_id);
    EXPECT_EQ(x.intrinsics.model_id, y.intrinsics.model_id);
    EXPECT_EQ(x.intrinsics.width, y.intrinsics.width);
    EXPECT_EQ(x.intrinsics.height, y.intrinsics.height);
    EXPECT_EQ(x.intrinsics.params, y.intrinsics.params);
    EXPECT_EQ(x.prior_focal_length, y.prior_focal_length);
  }
}

// What a schema without camera1 / camera2 keeps of a row.
TwoViewGeometryRow WithoutCameras(TwoViewGeometryRow row) {
  row.camera1.reset();
  row.camera2.reset();
  return row;
}

void ExpectReadsEverything(const Database& db, const Expected& e) {
  const std::vector<Camera> cameras = db.ReadCameras();
  ASSERT_EQ(cameras.size(), e.cameras.size());
  for (size_t i = 0; i < cameras.size(); ++i) {
    EXPECT_EQ(cameras[i].camera_id, e.cameras[i].camera_id);
    EXPECT_EQ(cameras[i].intrinsics.model_id, e.cameras[i].intrinsics.model_id);
    EXPECT_EQ(cameras[i].intrinsics.width, e.cameras[i].intrinsics.width);
    EXPECT_EQ(cameras[i].intrinsics.height, e.cameras[i].intrinsics.height);
    EXPECT_EQ(cameras[i].intrinsics.params, e.cameras[i].intrinsics.params);
    EXPECT_EQ(cameras[i].prior_focal_length, e.cameras[i].prior_focal_length);
  }
  const std::vector<Image> images = db.ReadImages();
  ASSERT_EQ(images.size(), e.images.size());
  for (size_t i = 0; i < images.size(); ++i) {
    EXPECT_EQ(images[i].image_id, e.images[i].image_id);
    EXPECT_EQ(images[i].name, e.images[i].name);
    EXPECT_EQ(images[i].camera_id, e.images[i].camera_id);
  }
  for (const Image& image : e.images) {
    const auto it = e.keypoints.find(image.image_id);
    const std::vector<Eigen::Vector2d> kp = db.ReadKeypoints(image.image_id);
    if (it == e.keypoints.end()) {
      EXPECT_TRUE(kp.empty());
    } else {
      EXPECT_EQ(kp, it->second) << "image " << image.image_id;
    }
  }
  std::vector<std::pair<pair_t, int>> expected_pairs;
  for (const auto& [pair_id, m] : e.matches) {
    if (!m.empty()) expected_pairs.emplace_back(pair_id, static_cast<int>(m.size()));
  }
  EXPECT_EQ(db.ReadMatchedPairs(), expected_pairs);  // sorted by pair id, rows > 0 only
  for (const auto& [pair_id, m] : e.matches) EXPECT_EQ(db.ReadMatches(pair_id), m);
  EXPECT_TRUE(db.ReadMatches(ImagePairToPairId(4, 5)).empty());
  for (const auto& [pair_id, row] : e.two_view) {
    const std::optional<TwoViewGeometryRow> read = db.ReadTwoViewGeometry(pair_id);
    ASSERT_TRUE(read.has_value());
    ExpectSameRow(*read, row);
    EXPECT_EQ(db.ReadColmapInlierMatches(pair_id), std::optional(row.inlier_matches));
  }
  EXPECT_FALSE(db.ReadTwoViewGeometry(ImagePairToPairId(2, 3)).has_value());
  EXPECT_FALSE(db.ReadColmapInlierMatches(ImagePairToPairId(2, 3)).has_value());
}

std::string IntegrityCheck(const std::string& path) { return RawDb(path).QueryText("PRAGMA integrity_check"); }

// Everything COLMAP owns, exactly.
std::vector<std::vector<std::vector<std::string>>> SnapshotColmapTables(const std::string& path) {
  RawDb db(path);
  return {db.Snapshot("SELECT * FROM cameras ORDER BY camera_id"),
          db.Snapshot("SELECT * FROM images ORDER BY image_id"),
          db.Snapshot("SELECT * FROM keypoints ORDER BY image_id"),
          db.Snapshot("SELECT * FROM matches ORDER BY pair_id"),
          db.Snapshot("SELECT * FROM two_view_geometries ORDER BY pair_id"),
          db.Snapshot("SELECT type, name, tbl_name, sql FROM sqlite_master WHERE name NOT LIKE 'madsfm%' "
                      "ORDER BY name"),
          db.Snapshot("PRAGMA user_version")};
}

std::set<std::string> MadsfmTables(const std::string& path) {
  std::set<std::string> names;
  for (const auto& row : RawDb(path).Snapshot("SELECT name FROM sqlite_master WHERE name LIKE 'madsfm%'")) {
    names.insert(row[0].substr(row[0].find(':') + 1));
  }
  return names;
}

// The geometries madsfm writes in the scenario tests.
std::vector<TwoViewGeometryRow> NewGeometries(const Expected& e) {
  std::vector<TwoViewGeometryRow> rows;
  {
    TwoViewGeometryRow row;  // replaces COLMAP's (1, 2): full pose and both focals estimated
    row.pair_id = ImagePairToPairId(1, 2);
    const auto& m = e.matches.at(row.pair_id);
    row.inlier_matches.assign(m.begin() + 10, m.begin() + 110);
    row.config = kUncalibrated;
    row.E = Eigen::Matrix3d::Random();
    row.F = Eigen::Matrix3d::Random();
    row.qvec = Eigen::Vector4d(0.8, -0.2, 0.1, 0.3).normalized();
    row.tvec = Eigen::Vector3d(-0.5, 0.2, 0.8).normalized();
    Camera camera1 = e.cameras[0], camera2 = e.cameras[1];  // images 1 and 2
    camera1.intrinsics.SetFocal(612.25);
    camera2.intrinsics.SetFocal(790.5);
    row.camera1 = camera1;
    row.camera2 = camera2;
    rows.push_back(row);
  }
  {
    TwoViewGeometryRow row;  // new row for (2, 3): F only (matches row exists)
    row.pair_id = ImagePairToPairId(2, 3);
    const auto& m = e.matches.at(row.pair_id);
    row.inlier_matches.assign(m.begin(), m.begin() + 30);
    row.config = kUncalibrated;
    row.F = Eigen::Matrix3d::Random();
    rows.push_back(row);
  }
  {
    TwoViewGeometryRow row;  // (1, 4): neither a matches nor a two_view_geometries row before
    row.pair_id = ImagePairToPairId(4, 1);
    row.inlier_matches = {{0, 1}, {5, 7}, {9, 2}, {10, 11}, {499, 249}};
    row.config = kCalibrated;
    row.E = Eigen::Matrix3d::Random();
    row.qvec = Eigen::Vector4d(1, 0, 0, 0.1).normalized();
    row.tvec = Eigen::Vector3d(1, 0, 0);
    rows.push_back(row);
  }
  {
    TwoViewGeometryRow row;  // replaces COLMAP's degenerate (3, 4), whose matches row has rows = 0
    row.pair_id = ImagePairToPairId(3, 4);
    row.config = kDegenerate;
    rows.push_back(row);
  }
  return rows;
}

MadsfmPairRow MakeMadsfmRow(pair_t pair_id, double seed) {
  MadsfmPairRow row;
  row.pair_id = pair_id;
  row.R = Eigen::AngleAxisd(0.1 * seed, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  row.t = Eigen::Vector3d(0.1, -0.2, 0.9) * seed;
  row.scale = 1.25 * seed;
  row.shift1 = -0.125;
  row.shift2 = 0.5 + seed;
  row.focal1 = 812.75;
  row.focal2 = std::numeric_limits<double>::quiet_NaN();  // e.g. not estimated
  row.camera_mode = 2;
  row.method = 1;
  row.num_inliers_reproj1 = 101;
  row.num_inliers_reproj2 = 99;
  row.num_inliers_sampson = 130;
  row.num_inliers = 140;
  row.score = 17.5 * seed;
  row.options_fingerprint = "reproj=8;epi=2;seed=" + std::to_string(seed);
  row.status = 0;
  row.depth_observable = seed > 1 ? 1 : 0;
  row.sigma_scale = 0.0625 * seed;
  row.sigma_shift1 = 0.25;
  row.sigma_shift2 = std::numeric_limits<double>::quiet_NaN();  // not fitted
  row.sigma_focal1 = 0.00390625 * seed;
  row.sigma_focal2 = std::numeric_limits<double>::quiet_NaN();  // calibrated in this view
  return row;
}

// NaN (stored as NULL) reads back as NaN; anything else exactly.
void ExpectSameOrBothNan(double a, double b) {
  EXPECT_EQ(std::isnan(a), std::isnan(b));
  if (!std::isnan(a)) {
    EXPECT_EQ(a, b);
  }
}

void ExpectSameMadsfmRow(const MadsfmPairRow& a, const MadsfmPairRow& b) {
  EXPECT_EQ(a.pair_id, b.pair_id);
  EXPECT_EQ(a.R, b.R);
  EXPECT_EQ(a.t, b.t);
  EXPECT_EQ(a.scale, b.scale);
  EXPECT_EQ(a.shift1, b.shift1);
  EXPECT_EQ(a.shift2, b.shift2);
  EXPECT_EQ(a.focal1, b.focal1);
  ExpectSameOrBothNan(a.focal2, b.focal2);
  EXPECT_EQ(a.camera_mode, b.camera_mode);
  EXPECT_EQ(a.method, b.method);
  EXPECT_EQ(a.num_inliers_reproj1, b.num_inliers_reproj1);
  EXPECT_EQ(a.num_inliers_reproj2, b.num_inliers_reproj2);
  EXPECT_EQ(a.num_inliers_sampson, b.num_inliers_sampson);
  EXPECT_EQ(a.num_inliers, b.num_inliers);
  EXPECT_EQ(a.score, b.score);
  EXPECT_EQ(a.options_fingerprint, b.options_fingerprint);
  EXPECT_EQ(a.status, b.status);
  EXPECT_EQ(a.depth_observable, b.depth_observable);
  EXPECT_EQ(a.sigma_scale, b.sigma_scale);
  EXPECT_EQ(a.sigma_shift1, b.sigma_shift1);
  ExpectSameOrBothNan(a.sigma_shift2, b.sigma_shift2);
  ExpectSameOrBothNan(a.sigma_focal1, b.sigma_focal1);
  ExpectSameOrBothNan(a.sigma_focal2, b.sigma_focal2);
}

// The whole write / read-back / backup / restore scenario on one populated database.
void RunWriteRestoreScenario(const std::string& path, const Expected& e) {
  const auto original = SnapshotColmapTables(path);
  const std::vector<TwoViewGeometryRow> rows = NewGeometries(e);
  const pair_t p14 = ImagePairToPairId(1, 4);
  const std::string matches_12_before = RawDb(path).QueryText("SELECT hex(data) FROM matches WHERE pair_id = " +
                                                              std::to_string(ImagePairToPairId(1, 2)));
  {
    auto db = Database::Open(path);
    EXPECT_FALSE(db->HasBackup());
    {
      Database::Transaction transaction(db.get());
      db->BackupTwoViewGeometries();
      for (const auto& row : rows) db->WriteTwoViewGeometry(row);
      db->WriteMadsfmPair(MakeMadsfmRow(rows[0].pair_id, 1));
      db->WriteMadsfmPair(MakeMadsfmRow(rows[1].pair_id, 2));
      transaction.Commit();
    }
    EXPECT_TRUE(db->HasBackup());
    for (const auto& row : rows) {
      const auto read = db->ReadTwoViewGeometry(row.pair_id);
      ASSERT_TRUE(read.has_value());
      ExpectSameRow(*read, db->has_two_view_cameras() ? row : WithoutCameras(row));
    }
    // COLMAP's own inlier counts come from the backup now: madsfm's rows do not change them.
    for (const auto& row : rows) {
      const auto it = e.two_view.find(row.pair_id);
      if (it == e.two_view.end()) {
        EXPECT_FALSE(db->ReadColmapInlierMatches(row.pair_id).has_value()) << row.pair_id;
      } else {
        EXPECT_EQ(db->ReadColmapInlierMatches(row.pair_id), std::optional(it->second.inlier_matches)) << row.pair_id;
      }
    }
    // A pair with a geometry but no matches row got one, holding the inlier matches.
    EXPECT_EQ(db->ReadMatches(p14), rows[2].inlier_matches);
    // Existing matches rows are left alone (also the one with rows = 0).
    EXPECT_EQ(db->ReadMatches(ImagePairToPairId(3, 4)).size(), 0u);

    // Camera updates keep the first original row.
    Camera camera = e.cameras[0];
    camera.intrinsics.params[0] = 777;
    camera.prior_focal_length = true;
    db->UpdateCamera(camera);
    camera.intrinsics.params[0] = 778;
    db->UpdateCamera(camera);
    Camera camera3 = e.cameras[2];
    camera3.intrinsics.SetFocal(1234);
    db->UpdateCamera(camera3);
    const auto cameras = db->ReadCameras();
    EXPECT_EQ(cameras[0].intrinsics.params[0], 778);
    EXPECT_TRUE(cameras[0].prior_focal_length);
    EXPECT_EQ(cameras[2].intrinsics.params, camera3.intrinsics.params);
  }
  EXPECT_EQ(IntegrityCheck(path), "ok");
  {
    // While madsfm's rows are in, COLMAP's schema (tables, columns, indexes) and user_version are as they were.
    const auto written = SnapshotColmapTables(path);
    EXPECT_EQ(written[5], original[5]) << "schema changed";
    EXPECT_EQ(written[6], original[6]) << "user_version changed";
  }
  {
    // Blob sizes and NULLs as COLMAP expects them.
    RawDb raw(path);
    const std::string where = " FROM two_view_geometries WHERE pair_id = ";
    const std::string p12 = std::to_string(rows[0].pair_id), p23 = std::to_string(rows[1].pair_id);
    EXPECT_EQ(raw.QueryText("SELECT length(F) || ',' || length(E) || ',' || typeof(H) || ',' || length(qvec) || ',' "
                            "|| length(tvec) || ',' || rows || ',' || cols || ',' || length(data)" + where + p12),
              "72,72,null,32,24,100,2,800");
    EXPECT_EQ(raw.QueryText("SELECT length(F) || ',' || typeof(E) || ',' || typeof(H) || ',' || typeof(qvec) || ',' "
                            "|| typeof(tvec) || ',' || config" + where + p23),
              "72,null,null,null,null,3");
    EXPECT_EQ(raw.QueryText("SELECT rows || ',' || cols || ',' || length(data) FROM matches WHERE pair_id = " +
                            std::to_string(p14)),
              "5,2,40");
    EXPECT_EQ(raw.QueryText("SELECT hex(data) FROM matches WHERE pair_id = " + std::to_string(rows[0].pair_id)),
              matches_12_before);
    // Row-major F: element (0, 1) is the second double.
    const auto cell = raw.Snapshot("SELECT F" + where + p12)[0][0];
    double f01;
    std::memcpy(&f01, cell.data() + cell.find(':') + 1 + sizeof(double), sizeof(double));
    EXPECT_EQ(f01, (*rows[0].F)(0, 1));
    EXPECT_EQ(raw.QueryInt("SELECT count(*) FROM madsfm_created_matches"), 1);
    if (HasCameraColumns(&raw)) {
      // COLMAP's camera blob, decoded by hand: u32 camera_id, i32 model, u64 width, u64 height, u8 prior, u64 n,
      // n x f64 (PINHOLE: 33 + 4 x 8 bytes). Pairs written without cameras have NULL.
      const std::string cell = raw.Snapshot("SELECT camera2" + where + p12)[0][0];
      const std::string blob = cell.substr(cell.find(':') + 1);
      ASSERT_EQ(blob.size(), 65u);
      uint32_t camera_id;
      int32_t model;
      uint64_t width, height, n;
      double params[4];
      std::memcpy(&camera_id, blob.data(), 4);
      std::memcpy(&model, blob.data() + 4, 4);
      std::memcpy(&width, blob.data() + 8, 8);
      std::memcpy(&height, blob.data() + 16, 8);
      std::memcpy(&n, blob.data() + 25, 8);
      std::memcpy(params, blob.data() + 33, 32);
      EXPECT_EQ(camera_id, 2u);
      EXPECT_EQ(model, 1);  // PINHOLE
      EXPECT_EQ(width, 1024u);
      EXPECT_EQ(height, 768u);
      EXPECT_EQ(blob[24], 1);  // camera 2 has a focal prior in the cameras table; the blob keeps the flag
      EXPECT_EQ(n, 4u);
      EXPECT_EQ(params[0], 790.5);  // fx
      EXPECT_EQ(params[1], 790.5 * (810.0 / 800.0));  // fy: SetFocal keeps the camera's aspect ratio
      EXPECT_EQ(params[2], 512.5);
      EXPECT_EQ(params[3], 383.5);
      EXPECT_EQ(raw.QueryText("SELECT typeof(camera1) || ',' || typeof(camera2)" + where + p23), "null,null");
    } else {
      EXPECT_FALSE(Database::Open(path, true)->has_two_view_cameras());
    }
  }
  {
    // madsfm's own rows, read-only.
    auto db = Database::Open(path, /*read_only=*/true);
    const auto madsfm_rows = db->ReadMadsfmPairs();
    ASSERT_EQ(madsfm_rows.size(), 2u);
    ExpectSameMadsfmRow(madsfm_rows[0], MakeMadsfmRow(rows[0].pair_id, 1));
    ExpectSameMadsfmRow(madsfm_rows[1], MakeMadsfmRow(rows[1].pair_id, 2));
  }
  {
    auto db = Database::Open(path);
    // (1, 2) and (3, 4) had original rows; (2, 3) and (1, 4) did not.
    EXPECT_EQ(db->RestoreTwoViewGeometries(), 2);
    EXPECT_FALSE(db->HasBackup());
    EXPECT_EQ(db->RestoreTwoViewGeometries(), 0);  // idempotent
  }
  EXPECT_EQ(SnapshotColmapTables(path), original) << "restore must give back COLMAP's tables byte for byte";
  EXPECT_TRUE(MadsfmTables(path).empty());
  EXPECT_EQ(IntegrityCheck(path), "ok");
}

// ---------------------------------------------------------------------------------------------------------------
// Pair ids.

TEST(PairIds, KnownValueAndRoundTrip) {
  EXPECT_EQ(ImagePairToPairId(1, 2), 2147483649ull);
  EXPECT_EQ(ImagePairToPairId(2, 1), 2147483649ull);
  std::mt19937 rng(7);
  for (int i = 0; i < 10000; ++i) {
    const image_t a = static_cast<image_t>(rng() % 2147483646u) + 1;
    const image_t b = static_cast<image_t>(rng() % 2147483646u) + 1;
    image_t id1, id2;
    PairIdToImagePair(ImagePairToPairId(a, b), &id1, &id2);
    EXPECT_EQ(id1, std::min(a, b));
    EXPECT_EQ(id2, std::max(a, b));
  }
  image_t id1, id2;
  PairIdToImagePair(ImagePairToPairId(2147483645, 2147483646), &id1, &id2);
  EXPECT_EQ(id1, 2147483645u);
  EXPECT_EQ(id2, 2147483646u);
}

// ---------------------------------------------------------------------------------------------------------------
// A database made by COLMAP 3.8 itself.

class Colmap38Database : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!HaveColmap()) GTEST_SKIP() << "the `colmap` binary is not installed: skipping tests on a COLMAP-made database";
    path_ = dir_.File("colmap.db");
    CreateWithColmap(path_);
  }
  TempDir dir_;
  std::string path_;
};

TEST_F(Colmap38Database, DetectsSchema) {
  auto db = Database::Open(path_);
  EXPECT_EQ(db->schema(), SchemaVersion::kColmap38);
  EXPECT_EQ(SchemaVersionName(db->schema()), "COLMAP 3.8/3.9");
  EXPECT_EQ(db->path(), path_);
  EXPECT_TRUE(db->ReadCameras().empty());
  EXPECT_TRUE(db->ReadMatchedPairs().empty());
}

// DatabaseBuilder's 3.8 schema is the one `colmap database_creator` 3.8 makes: same tables, columns (type, NOT NULL,
// default, primary key), indexes, foreign keys and user_version (the CREATE text differs only in white space).
TEST_F(Colmap38Database, BuilderSchemaEqualsDatabaseCreator) {
  const std::string ours = dir_.File("builder.db");
  { DatabaseBuilder builder(ours, ColmapRelease::k3_8); }
  const auto describe = [](const std::string& path) {
    RawDb db(path);
    std::vector<std::vector<std::vector<std::string>>> out;
    out.push_back(db.Snapshot("SELECT type, name, tbl_name FROM sqlite_master ORDER BY name"));
    for (const auto& row : out[0]) {
      const std::string name = row[1].substr(row[1].find(':') + 1);
      if (row[0].find("table") == std::string::npos) continue;
      out.push_back(db.Snapshot("PRAGMA table_info('" + name + "')"));
      out.push_back(db.Snapshot("PRAGMA index_list('" + name + "')"));
      out.push_back(db.Snapshot("PRAGMA foreign_key_list('" + name + "')"));
    }
    out.push_back(db.Snapshot("PRAGMA user_version"));
    return out;
  };
  EXPECT_EQ(describe(ours), describe(path_));
  EXPECT_EQ(RawDb(path_).QueryInt("PRAGMA user_version"), ColmapReleaseUserVersion(ColmapRelease::k3_8));
}

TEST_F(Colmap38Database, ReadsEverythingBackExactly) {
  const Expected e = Populate(path_, /*exotic_cameras=*/true);
  auto db = Database::Open(path_, /*read_only=*/true);
  EXPECT_EQ(db->schema(), SchemaVersion::kColmap38);
  ExpectReadsEverything(*db, e);
}

// two_view_estimator asks for COLMAP's own verification result of a pair (its inlier matches guide the sampling);
// once madsfm has written the pair, the answer comes from the backup, not from madsfm's row.
TEST_F(Colmap38Database, ColmapInlierMatchesComeFromTheBackup) {
  const Expected e = Populate(path_, /*exotic_cameras=*/false);
  const pair_t p13 = ImagePairToPairId(1, 3), p34 = ImagePairToPairId(3, 4), p23 = ImagePairToPairId(2, 3);
  auto db = Database::Open(path_);
  const auto colmap13 = db->ReadColmapInlierMatches(p13);
  ASSERT_TRUE(colmap13.has_value());
  EXPECT_EQ(colmap13->size(), 40u);
  EXPECT_EQ(db->ReadColmapInlierMatches(p34)->size(), 0u);  // verification failed: a row with 0 rows
  EXPECT_FALSE(db->ReadColmapInlierMatches(p23).has_value());  // no row at all
  TwoViewGeometryRow row;
  row.pair_id = p13;
  row.inlier_matches.assign(e.matches.at(p13).begin(), e.matches.at(p13).begin() + 5);
  row.config = kCalibrated;
  row.E = Eigen::Matrix3d::Identity();
  {
    Database::Transaction transaction(db.get());
    db->WriteTwoViewGeometry(row);
    transaction.Commit();
  }
  EXPECT_EQ(db->ReadTwoViewGeometry(p13)->inlier_matches.size(), 5u);
  EXPECT_EQ(db->ReadColmapInlierMatches(p13), colmap13);
}

TEST_F(Colmap38Database, WriteBackupRestoreRoundTrip) {
  const Expected e = Populate(path_, /*exotic_cameras=*/true);
  RunWriteRestoreScenario(path_, e);
}

// COLMAP itself reads what madsfm wrote: `colmap database_merger` reads every camera, image, keypoint, match and
// two-view geometry through COLMAP's own Database class (which checks the blob sizes) and writes them into a new
// database; the geometries read back from that copy must equal what madsfm wrote.
TEST_F(Colmap38Database, ColmapReadsWhatMadsfmWrote) {
  const Expected e = Populate(path_, /*exotic_cameras=*/false);  // 3.8 aborts on camera models it does not know
  // COLMAP 3.8 also aborts on an image without a keypoints row ("Keypoint format not supported"): give image 5 an
  // empty one, as feature extraction would.
  RawDb(path_).Exec("INSERT INTO keypoints (image_id, rows, cols, data) VALUES (5, 0, 6, zeroblob(0))");
  const std::vector<TwoViewGeometryRow> rows = NewGeometries(e);
  {
    auto db = Database::Open(path_);
    Database::Transaction transaction(db.get());
    for (const auto& row : rows) db->WriteTwoViewGeometry(row);
    transaction.Commit();
  }
  const std::string empty = dir_.File("empty.db"), merged = dir_.File("merged.db");
  CreateWithColmap(empty);
  const std::string cmd = "colmap database_merger --database_path1 '" + path_ + "' --database_path2 '" + empty +
                          "' --merged_database_path '" + merged + "' > '" + merged + ".log' 2>&1";
  if (std::system(cmd.c_str()) != 0) {
    std::ifstream log(merged + ".log");
    FAIL() << cmd << " failed:\n" << std::string(std::istreambuf_iterator<char>(log), {});
  }
  auto db = Database::Open(merged, /*read_only=*/true);
  const auto images = db->ReadImages();
  ASSERT_EQ(images.size(), e.images.size());
  for (size_t i = 0; i < images.size(); ++i) {
    ASSERT_EQ(images[i].image_id, e.images[i].image_id);  // ids kept, so pair ids are comparable
    ASSERT_EQ(images[i].name, e.images[i].name);
  }
  for (const auto& row : rows) {
    const auto read = db->ReadTwoViewGeometry(row.pair_id);
    if (row.inlier_matches.empty()) {
      // COLMAP reads geometries "WHERE rows > 0" in bulk (3.8 database.cc), so the merger does not copy them.
      EXPECT_FALSE(read.has_value()) << row.pair_id;
      continue;
    }
    ASSERT_TRUE(read.has_value()) << row.pair_id;
    // COLMAP writes absent matrices as zeros, which read back as absent; 3.8 has no camera1 / camera2.
    ExpectSameRow(*read, WithoutCameras(row));
    EXPECT_EQ(db->ReadMatches(row.pair_id).size(),
              e.matches.count(row.pair_id) ? e.matches.at(row.pair_id).size() : row.inlier_matches.size());
  }
  EXPECT_EQ(IntegrityCheck(merged), "ok");
}

// ---------------------------------------------------------------------------------------------------------------
// Synthetic schemas of every supported version.

class SyntheticSchemaTest : public ::testing::TestWithParam<SchemaCase> {};

TEST_P(SyntheticSchemaTest, DetectsReadsWritesRestores) {
  TempDir dir;
  const std::string path = dir.File("synthetic.db");
  CreateSynthetic(path, GetParam());
  {
    RawDb raw(path);
    EXPECT_EQ(raw.QueryInt("PRAGMA user_version"), GetParam().user_version);
    EXPECT_EQ(HasCameraColumns(&raw), GetParam().cameras);
  }
  const Expected e = Populate(path, /*exotic_cameras=*/true);
  {
    auto db = Database::Open(path, /*read_only=*/true);
    EXPECT_EQ(db->schema(), GetParam().expected) << GetParam().label;
    EXPECT_EQ(db->has_two_view_cameras(), GetParam().cameras);
    EXPECT_EQ(db->user_version(), GetParam().user_version);
    ExpectReadsEverything(*db, e);
  }
  // Also checks that the schema and user_version are exactly as before, after writing and after restoring.
  RunWriteRestoreScenario(path, e);
}

INSTANTIATE_TEST_SUITE_P(Versions, SyntheticSchemaTest, ::testing::ValuesIn(AllSchemaCases()),
                         [](const ::testing::TestParamInfo<SchemaCase>& info) {
                           std::string name = "Colmap" + info.param.label;
                           for (char& c : name) {
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           }
                           return name;
                         });

// The schemas themselves: the tables, columns and indexes each release has, and what madsfm writes there.
TEST(ColmapSchemas, TablesColumnsAndIndexesPerRelease) {
  const auto columns = [](RawDb* db, const std::string& table) {
    std::string out;
    for (const auto& row : db->Snapshot("SELECT name FROM pragma_table_info('" + table + "') ORDER BY cid")) {
      out += (out.empty() ? "" : ",") + row[0].substr(row[0].find(':') + 1);
    }
    return out;
  };
  const auto names = [](RawDb* db, const std::string& type) {
    std::string out;
    for (const auto& row : db->Snapshot("SELECT name FROM sqlite_master WHERE type = '" + type +
                                        "' AND name NOT LIKE 'sqlite_%' ORDER BY name")) {
      out += (out.empty() ? "" : ",") + row[0].substr(row[0].find(':') + 1);
    }
    return out;
  };
  TempDir dir;
  std::map<std::string, std::string> seen;
  for (ColmapRelease release : AllColmapReleases()) {
    const std::string name = ColmapReleaseName(release);
    const std::string path = dir.File(name + ".db");
    CreateColmapDatabase(path, release);
    RawDb db(path);
    const bool rigs = release >= ColmapRelease::k3_12, v4 = release >= ColmapRelease::k4_0;
    EXPECT_EQ(names(&db, "table"),
              std::string("cameras,descriptors,") + (rigs ? "frame_data,frames," : "") + "images,keypoints,matches," +
                  (release >= ColmapRelease::k3_10 ? "pose_priors," : "") + (rigs ? "rig_sensors,rigs," : "") +
                  "two_view_geometries")
        << name;
    EXPECT_EQ(names(&db, "index"), std::string(rigs ? "frame_sensor_assignment," : "") + "index_name" +
                                       (v4 ? ",pose_prior_data_assignment" : "") +
                                       (rigs ? ",rig_ref_sensor_assignment,rig_sensor_assignment" : ""))
        << name;
    EXPECT_EQ(columns(&db, "images"), release >= ColmapRelease::k3_10
                                          ? "image_id,name,camera_id"
                                          : "image_id,name,camera_id,prior_qw,prior_qx,prior_qy,prior_qz,prior_tx,"
                                            "prior_ty,prior_tz")
        << name;
    EXPECT_EQ(columns(&db, "descriptors"), v4 ? "image_id,type,rows,cols,data" : "image_id,rows,cols,data") << name;
    EXPECT_EQ(columns(&db, "two_view_geometries"),
              std::string("pair_id,rows,cols,data,config,F,E,H,qvec,tvec") +
                  (release == ColmapRelease::kMain ? ",camera1,camera2" : ""))
        << name;
    if (release >= ColmapRelease::k3_10) {
      EXPECT_EQ(columns(&db, "pose_priors"),
                v4 ? "pose_prior_id,corr_data_id,corr_sensor_id,corr_sensor_type,position,position_covariance,gravity,"
                     "coordinate_system"
                   : release == ColmapRelease::k3_10 ? "image_id,position,coordinate_system"
                                                     : "image_id,position,coordinate_system,position_covariance")
          << name;
    }
    EXPECT_EQ(db.QueryInt("PRAGMA user_version"), ColmapReleaseUserVersion(release)) << name;
    EXPECT_EQ(IntegrityCheck(path), "ok");
  }
  EXPECT_EQ(ColmapReleaseUserVersion(ColmapRelease::k3_8), 3800);
  EXPECT_EQ(ColmapReleaseUserVersion(ColmapRelease::k3_13), 3900);
  EXPECT_EQ(ColmapReleaseUserVersion(ColmapRelease::k4_1), 4010100);
  for (ColmapRelease release : AllColmapReleases()) EXPECT_EQ(ParseColmapRelease(ColmapReleaseName(release)), release);
  EXPECT_THROW(ParseColmapRelease("4.2"), std::invalid_argument);
  // The 3.8 schema is still the one of `colmap database_creator` 3.8 (checked against the binary below).
  EXPECT_EQ(Colmap38SchemaSql(), ColmapSchemaSql(ColmapRelease::k3_8));
}

// From 3.12 on the builder makes the rig and frame COLMAP's feature extractor makes for every single camera / image.
TEST(ColmapSchemas, BuilderWritesTrivialRigsAndFramesFrom312) {
  TempDir dir;
  for (ColmapRelease release : {ColmapRelease::k3_11, ColmapRelease::k3_12, ColmapRelease::kMain}) {
    const std::string path = dir.File(ColmapReleaseName(release) + ".db");
    {
      DatabaseBuilder builder(path, release);
      const uint32_t c1 = builder.AddCamera(0, 640, 480, {500, 320, 240}, false);
      const uint32_t c2 = builder.AddCamera(1, 800, 600, {700, 710, 400, 300}, true);
      builder.AddImage("a.jpg", c1);
      builder.AddImage("b.jpg", c2);
      builder.AddImage("c.jpg", c2);
    }
    RawDb raw(path);
    if (release < ColmapRelease::k3_12) {
      EXPECT_EQ(raw.QueryInt("SELECT count(*) FROM sqlite_master WHERE name = 'rigs'"), 0);
      continue;
    }
    EXPECT_EQ(raw.QueryText("SELECT group_concat(rig_id || ':' || ref_sensor_id || ':' || ref_sensor_type, ' ') "
                            "FROM rigs"),
              "1:1:0 2:2:0");
    EXPECT_EQ(raw.QueryText("SELECT group_concat(frame_id || ':' || rig_id, ' ') FROM frames"), "1:1 2:2 3:2");
    EXPECT_EQ(raw.QueryText("SELECT group_concat(frame_id || ':' || data_id || ':' || sensor_id || ':' || sensor_type, "
                            "' ') FROM frame_data"),
              "1:1:1:0 2:2:2:0 3:3:2:0");
    auto db = Database::Open(path, true);
    EXPECT_EQ(db->ReadImages().size(), 3u);
    EXPECT_EQ(db->ReadCameras().size(), 2u);
  }
}

// What COLMAP 4.x does to a database of user_version <= 3130000 when it opens it (PostMigrateTables, re-implemented
// here from its description in docs/formats.md): identity-with-zero-t or all-zero poses and all-zero F/E/H become
// NULL. Everything madsfm wrote into a 3.8 database survives it, so the global mapper sees madsfm's poses.
TEST(ColmapSchemas, MadsfmRowsSurviveColmap4Migration) {
  TempDir dir;
  const std::string path = dir.File("old.db");
  CreateColmapDatabase(path, ColmapRelease::k3_8);
  const Expected e = Populate(path, /*exotic_cameras=*/false);
  const std::vector<TwoViewGeometryRow> rows = NewGeometries(e);
  {
    auto db = Database::Open(path);
    for (const auto& row : rows) db->WriteTwoViewGeometry(row);
  }
  RawDb raw(path);
  ASSERT_LE(raw.QueryInt("PRAGMA user_version"), 3130000);
  const auto doubles = [&](const std::string& column, pair_t pair_id) {
    const auto cell = raw.Snapshot("SELECT " + column + " FROM two_view_geometries WHERE pair_id = " +
                                   std::to_string(pair_id))[0][0];
    const std::string bytes = cell.substr(cell.find(':') + 1);
    std::vector<double> v(bytes.size() / sizeof(double));
    if (!v.empty()) std::memcpy(v.data(), bytes.data(), bytes.size());
    return v;  // empty for NULL
  };
  int poses = 0;
  for (const auto& row : rows) {
    const std::vector<double> q = doubles("qvec", row.pair_id), t = doubles("tvec", row.pair_id);
    ASSERT_EQ(q.empty(), t.empty());
    if (!q.empty()) {
      ++poses;
      const bool identity = q == std::vector<double>{1, 0, 0, 0} && t == std::vector<double>(3, 0.0);
      const bool zero = q == std::vector<double>(4, 0.0);
      EXPECT_FALSE(identity || zero) << "COLMAP 4 would drop the pose of pair " << row.pair_id;
      EXPECT_TRUE(ConfigHasPose(row.config));
    }
    for (const char* m : {"F", "E", "H"}) {
      const std::vector<double> v = doubles(m, row.pair_id);
      if (!v.empty()) {
        EXPECT_NE(v, std::vector<double>(9, 0.0)) << "COLMAP 4 would drop " << m << " of pair " << row.pair_id;
      }
    }
  }
  EXPECT_EQ(poses, 2);
}

// COLMAP's camera blob (two_view_geometries.camera1 / camera2) round trip and its size checks.
TEST(ColmapSchemas, CameraBlob) {
  Camera camera = MakeCamera(7, 4, 1920, 1080, {1500, 1490, 960, 540, -0.1, 0.01, 0.001, -0.0005}, true);
  const std::vector<unsigned char> blob = EncodeCameraBlob(camera);
  ASSERT_EQ(blob.size(), 33u + 8 * 8);
  EXPECT_EQ(blob[0], 7);  // little-endian camera_id
  EXPECT_EQ(blob[4], 4);  // OPENCV
  EXPECT_EQ(blob[8], 1920 & 0xff);
  EXPECT_EQ(blob[9], 1920 >> 8);
  EXPECT_EQ(blob[24], 1);
  EXPECT_EQ(blob[25], 8);
  const Camera back = DecodeCameraBlob(blob.data(), blob.size(), "test");
  EXPECT_EQ(back.camera_id, 7u);
  EXPECT_EQ(back.intrinsics.model_id, 4);
  EXPECT_EQ(back.intrinsics.width, 1920);
  EXPECT_EQ(back.intrinsics.height, 1080);
  EXPECT_EQ(back.intrinsics.params, camera.intrinsics.params);
  EXPECT_TRUE(back.prior_focal_length);
  EXPECT_THROW(DecodeCameraBlob(blob.data(), blob.size() - 1, "test"), std::runtime_error);
  EXPECT_THROW(DecodeCameraBlob(blob.data(), 20, "test"), std::runtime_error);
  std::vector<unsigned char> huge = blob;
  huge[32] = 0x7f;  // a corrupt parameter count must not allocate
  EXPECT_THROW(DecodeCameraBlob(huge.data(), huge.size(), "test"), std::runtime_error);
}

// ---------------------------------------------------------------------------------------------------------------
// Bad inputs and failure modes.

// Runs f, expects a std::runtime_error whose message contains every one of needles.
template <typename F>
void ExpectErrorContaining(F&& f, const std::vector<std::string>& needles) {
  try {
    f();
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& error) {
    const std::string message = error.what();
    for (const std::string& needle : needles) {
      EXPECT_NE(message.find(needle), std::string::npos) << "'" << needle << "' not in: " << message;
    }
    std::printf("[ message  ] %s\n", message.c_str());
  }
}

class SyntheticDatabase : public ::testing::Test {
 protected:
  // A populated synthetic 3.8 database (does not need the colmap binary).
  std::string MakeDb(const std::string& name) {
    const std::string path = dir_.File(name);
    { DatabaseBuilder builder(path, ColmapRelease::k3_8); }
    expected_ = Populate(path, /*exotic_cameras=*/false);
    return path;
  }
  TempDir dir_;
  Expected expected_;
};

TEST_F(SyntheticDatabase, MissingFile) {
  const std::string path = dir_.File("missing.db");
  ExpectErrorContaining([&] { Database::Open(path); }, {"missing.db", "does not exist"});
  EXPECT_FALSE(fs::exists(path)) << "Open must not create a database";
}

TEST_F(SyntheticDatabase, TextFile) {
  const std::string path = dir_.File("x.db");
  std::ofstream(path) << "this is a text file, long enough to fill a database header\n";
  ExpectErrorContaining([&] { Database::Open(path); }, {"'" + path + "' is not a SQLite database"});
  const std::string empty = dir_.File("empty.db");
  std::ofstream(empty).flush();
  ExpectErrorContaining([&] { Database::Open(empty, true); }, {"empty.db", "not a SQLite database"});
}

TEST_F(SyntheticDatabase, SqliteWithoutColmapTables) {
  const std::string path = dir_.File("other.db");
  RawDb(path).Exec("CREATE TABLE cameras (x INTEGER); CREATE TABLE foo (y TEXT)");
  ExpectErrorContaining([&] { Database::Open(path); },
                        {"other.db", "unknown schema", "images", "keypoints", "matches", "two_view_geometries"});
}

TEST_F(SyntheticDatabase, ReadOnlyFileOpenedForWriting) {
  const std::string path = MakeDb("readonly.db");
  ASSERT_EQ(::chmod(path.c_str(), 0444), 0);
  ExpectErrorContaining([&] { Database::Open(path, /*read_only=*/false); }, {"readonly.db", "read-only"});
  // Reading is fine, and writing through a read-only handle fails with the file name.
  auto db = Database::Open(path, /*read_only=*/true);
  EXPECT_EQ(db->ReadImages().size(), 5u);
  TwoViewGeometryRow row;
  row.pair_id = ImagePairToPairId(1, 2);
  ExpectErrorContaining([&] { db->WriteTwoViewGeometry(row); }, {"readonly.db", "readonly"});
}

TEST_F(SyntheticDatabase, KeypointBlobSizeMismatch) {
  const std::string path = MakeDb("kp.db");
  RawDb(path).Exec("UPDATE keypoints SET rows = rows + 1 WHERE image_id = 3");
  RawDb(path).Exec("UPDATE keypoints SET cols = 3, rows = 1000 WHERE image_id = 2");
  auto db = Database::Open(path, true);
  ExpectErrorContaining([&] { db->ReadKeypoints(3); },
                        {"kp.db", "keypoints of 'b/c/img3.jpg' (image_id 3): blob has 1600 bytes, expected 1608"});
  ExpectErrorContaining([&] { db->ReadKeypoints(2); }, {"kp.db", "'img2.png' (image_id 2)", "cols = 3"});
  EXPECT_EQ(db->ReadKeypoints(1).size(), 500u);  // the others still read
}

TEST_F(SyntheticDatabase, MatchesBlobSizeMismatch) {
  const std::string path = MakeDb("matches.db");
  const pair_t pair_id = ImagePairToPairId(2, 3);
  RawDb(path).Exec("UPDATE matches SET rows = 61 WHERE pair_id = " + std::to_string(pair_id));
  auto db = Database::Open(path, true);
  ExpectErrorContaining([&] { db->ReadMatches(pair_id); },
                        {"matches.db", "matches of pair " + std::to_string(pair_id) +
                                           " ('img2.png' (image_id 2), 'b/c/img3.jpg' (image_id 3))"});
  // Inlier matches of a geometry likewise, and an F blob of float32 (36 bytes).
  const pair_t p12 = ImagePairToPairId(1, 2);
  RawDb(path).Exec("UPDATE two_view_geometries SET F = zeroblob(36) WHERE pair_id = " + std::to_string(p12));
  ExpectErrorContaining([&] { db->ReadTwoViewGeometry(p12); },
                        {"matches.db", "('a/img1.jpg' (image_id 1), 'img2.png' (image_id 2))", "F", "36 bytes"});
  // An image id the images table does not have is said to be missing.
  EXPECT_EQ(db->DescribeImage(77), "image_id 77 (not in the images table)");
  EXPECT_EQ(db->DescribeCamera(1), "camera_id 1 (used by 'a/img1.jpg', 'img4.jpg')");
  EXPECT_EQ(db->DescribeCamera(9), "camera_id 9 (not in the cameras table)");
}

TEST_F(SyntheticDatabase, CameraParamsOfTheWrongLength) {
  const std::string path = MakeDb("cameras.db");
  RawDb raw(path);
  const std::vector<double> params = {800, 810, 512};  // PINHOLE needs 4
  raw.Run("UPDATE cameras SET params = ? WHERE camera_id = 2", {BlobOf(params)});
  auto db = Database::Open(path, true);
  ExpectErrorContaining([&] { db->ReadCameras(); },
                        {"cameras.db", "params of camera_id 2 (used by 'img2.png', 'img5.jpg') have 3 values",
                         "PINHOLE"});
}

TEST_F(SyntheticDatabase, CameraOfInvalidSize) {
  const std::vector<std::string> sizes = {"width = 0", "height = -480", "width = 4294967296"};
  for (size_t k = 0; k < sizes.size(); ++k) {
    const std::string name = "camera_size_" + std::to_string(k) + ".db";
    const std::string path = MakeDb(name);
    RawDb(path).Exec("UPDATE cameras SET " + sizes[k] + " WHERE camera_id = 2");
    auto db = Database::Open(path, true);
    ExpectErrorContaining([&] { db->ReadCameras(); },
                          {name, "camera_id 2 (used by 'img2.png', 'img5.jpg') has an invalid size"});
  }
}

TEST_F(SyntheticDatabase, InvalidWrites) {
  const std::string path = MakeDb("writes.db");
  auto db = Database::Open(path);
  TwoViewGeometryRow row;
  row.pair_id = ImagePairToPairId(1, 2);
  row.qvec = Eigen::Vector4d(1, 0, 0, 0);  // without tvec
  EXPECT_THROW(db->WriteTwoViewGeometry(row), std::invalid_argument);
  row.qvec.reset();
  row.pair_id = 2147483647ull * 5 + 3;  // "image 1" = 5 > "image 2" = 3: not a pair id ImagePairToPairId makes
  EXPECT_THROW(db->WriteTwoViewGeometry(row), std::invalid_argument);
  Camera camera = expected_.cameras[1];
  camera.intrinsics.params.pop_back();
  EXPECT_THROW(db->UpdateCamera(camera), std::invalid_argument);
  camera = expected_.cameras[1];
  camera.camera_id = 42;
  ExpectErrorContaining([&] { db->UpdateCamera(camera); }, {"writes.db", "camera_id 42 (not in the cameras table)"});
  EXPECT_EQ(IntegrityCheck(path), "ok");
}

// Runs f, expects a std::invalid_argument whose message contains every one of needles.
template <typename F>
void ExpectInvalidArgument(F&& f, const std::vector<std::string>& needles) {
  try {
    f();
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& error) {
    const std::string message = error.what();
    for (const std::string& needle : needles) {
      EXPECT_NE(message.find(needle), std::string::npos) << "'" << needle << "' not in: " << message;
    }
    std::printf("[ message  ] %s\n", message.c_str());
  }
}

// madsfm never writes a pose COLMAP would take for "not estimated" (and 4.x would set to NULL), a pose on a pair
// whose config says it has none, placeholder matrices, or cameras that are not the images' cameras. Nothing of a
// rejected write reaches the database.
TEST(WriteChecks, NoPlaceholderPosesOrForeignCameras) {
  TempDir dir;
  const std::string path = dir.File("main.db");
  CreateColmapDatabase(path, ColmapRelease::kMain);
  const Expected e = Populate(path, /*exotic_cameras=*/false);
  const auto before = SnapshotColmapTables(path);
  auto db = Database::Open(path);
  ASSERT_TRUE(db->has_two_view_cameras());
  TwoViewGeometryRow good;
  good.pair_id = ImagePairToPairId(2, 3);
  good.inlier_matches = {{0, 1}, {2, 3}};
  good.config = kUncalibrated;
  good.F = Eigen::Matrix3d::Random();
  good.E = Eigen::Matrix3d::Random();
  good.qvec = Eigen::Vector4d(1, 0, 0, 0);  // a pure translation: identity rotation is fine with t != 0
  good.tvec = Eigen::Vector3d(0, 0, 1);
  good.camera1 = e.cameras[1];  // image 2 uses camera 2
  good.camera2 = e.cameras[2];  // image 3 uses camera 3
  const std::string pair = "pair " + std::to_string(good.pair_id) + " ('img2.png' (image_id 2), 'b/c/img3.jpg'";
  struct Case {
    std::string label;
    std::function<void(TwoViewGeometryRow*)> change;
    std::string fragment;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Case> cases = {
      {"identity, zero t", [](TwoViewGeometryRow* r) { r->tvec = Eigen::Vector3d::Zero(); }, "tvec is zero"},
      {"zero q", [](TwoViewGeometryRow* r) { r->qvec = Eigen::Vector4d::Zero(); }, "not a unit quaternion"},
      {"non-unit q", [](TwoViewGeometryRow* r) { r->qvec = Eigen::Vector4d(1, 1, 0, 0); }, "not a unit quaternion"},
      {"nan t", [nan](TwoViewGeometryRow* r) { r->tvec = Eigen::Vector3d(nan, 0, 1); }, "not finite"},
      {"qvec only", [](TwoViewGeometryRow* r) { r->tvec.reset(); }, "both be set"},
      {"degenerate", [](TwoViewGeometryRow* r) { r->config = kDegenerate; }, "config 1 has no pose"},
      {"undefined", [](TwoViewGeometryRow* r) { r->config = kUndefined; }, "config 0 has no pose"},
      {"zero F", [](TwoViewGeometryRow* r) { r->F = Eigen::Matrix3d::Zero(); }, "F is all zero"},
      {"inf E", [](TwoViewGeometryRow* r) { (*r->E)(1, 1) = INFINITY; }, "E is not finite"},
      {"cameras without E", [](TwoViewGeometryRow* r) { r->E.reset(); }, "need E"},
      {"camera of another image", [&](TwoViewGeometryRow* r) { r->camera1 = e.cameras[0]; },
       "camera1 of 'img2.png' (image_id 2) is camera_id 1"},
      {"camera of the wrong size", [&](TwoViewGeometryRow* r) { r->camera2->intrinsics.width = 1000; },
       "camera2 of 'b/c/img3.jpg' (image_id 3)"},
      {"camera with NaN focal", [nan](TwoViewGeometryRow* r) { r->camera2->intrinsics.params[0] = nan; },
       "non-finite params"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.label);
    TwoViewGeometryRow row = good;
    c.change(&row);
    ExpectInvalidArgument([&] { db->WriteTwoViewGeometry(row); }, {"main.db", pair, c.fragment});
  }
  EXPECT_EQ(SnapshotColmapTables(path), before);
  EXPECT_TRUE(MadsfmTables(path).empty()) << "a rejected write must not even create the backup";
  db->WriteTwoViewGeometry(good);  // the unchanged row is fine
  ExpectSameRow(*db->ReadTwoViewGeometry(good.pair_id), good);
  // A pair without a pose (e.g. degenerate) is written with NULL qvec / tvec, never a placeholder.
  TwoViewGeometryRow degenerate;
  degenerate.pair_id = ImagePairToPairId(1, 4);
  degenerate.config = kDegenerate;
  db->WriteTwoViewGeometry(degenerate);
  EXPECT_EQ(RawDb(path).QueryText("SELECT typeof(qvec) || typeof(tvec) || typeof(F) || typeof(camera1) FROM "
                                  "two_view_geometries WHERE pair_id = " + std::to_string(degenerate.pair_id)),
            "nullnullnullnull");
}

TEST_F(SyntheticDatabase, TransactionWithoutCommitRollsBack) {
  const std::string path = MakeDb("tx.db");
  const pair_t p14 = ImagePairToPairId(1, 4);
  TwoViewGeometryRow row;
  row.pair_id = p14;
  row.inlier_matches = {{1, 2}, {3, 4}};
  row.config = kUncalibrated;
  row.F = Eigen::Matrix3d::Identity();
  {
    auto db = Database::Open(path);
    {
      Database::Transaction transaction(db.get());
      db->WriteTwoViewGeometry(row);
      db->WriteMadsfmPair(MakeMadsfmRow(p14, 1));
      Camera camera = expected_.cameras[0];
      camera.intrinsics.params[0] = 1;
      db->UpdateCamera(camera);
      EXPECT_TRUE(db->ReadTwoViewGeometry(p14).has_value());  // visible inside the transaction
    }  // destroyed without Commit
    EXPECT_FALSE(db->ReadTwoViewGeometry(p14).has_value());
    EXPECT_TRUE(db->ReadMatches(p14).empty());
    EXPECT_FALSE(db->ReadMadsfmPair(p14).has_value());
    EXPECT_EQ(db->ReadCameras()[0].intrinsics.params, expected_.cameras[0].intrinsics.params);
    EXPECT_FALSE(db->HasBackup());
    // An exception leaving the scope rolls back too.
    try {
      Database::Transaction transaction(db.get());
      db->WriteTwoViewGeometry(row);
      throw std::runtime_error("abort");
    } catch (const std::runtime_error&) {
    }
    EXPECT_FALSE(db->ReadTwoViewGeometry(p14).has_value());
    // Committed: present, also for a new connection.
    {
      Database::Transaction transaction(db.get());
      db->WriteTwoViewGeometry(row);
      transaction.Commit();
    }
  }
  EXPECT_TRUE(Database::Open(path, true)->ReadTwoViewGeometry(p14).has_value());
  EXPECT_TRUE(MadsfmTables(path).count("madsfm_backup_two_view_geometries"));
  EXPECT_EQ(IntegrityCheck(path), "ok");
}

TEST_F(SyntheticDatabase, BusyDatabaseTimesOut) {
  const std::string path = MakeDb("busy.db");
  RawDb other(path);
  other.Exec("BEGIN IMMEDIATE");  // another writer holds the lock
  auto db = Database::Open(path, false, /*busy_timeout_ms=*/200);
  const auto start = std::chrono::steady_clock::now();
  ExpectErrorContaining([&] { Database::Transaction transaction(db.get()); }, {"busy.db", "locked"});
  const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_GE(waited, 0.15);
  EXPECT_EQ(db->ReadImages().size(), 5u);  // reading is not blocked
  other.Exec("COMMIT");
  Database::Transaction transaction(db.get());  // now it works
  transaction.Commit();
}

// ---------------------------------------------------------------------------------------------------------------
// madsfm's own table and camera updates.

TEST_F(SyntheticDatabase, MadsfmPairsReplaceAndReadBack) {
  const std::string path = MakeDb("madsfm.db");
  auto db = Database::Open(path);
  EXPECT_FALSE(db->ReadMadsfmPair(ImagePairToPairId(1, 2)).has_value());  // no table yet
  EXPECT_TRUE(db->ReadMadsfmPairs().empty());
  db->CreateMadsfmTables();
  db->CreateMadsfmTables();  // idempotent
  db->WriteMadsfmPair(MakeMadsfmRow(ImagePairToPairId(2, 3), 1));
  db->WriteMadsfmPair(MakeMadsfmRow(ImagePairToPairId(1, 2), 2));
  MadsfmPairRow failed = MakeMadsfmRow(ImagePairToPairId(2, 3), 3);
  failed.status = 1;
  db->WriteMadsfmPair(failed);  // replaces
  const auto rows = db->ReadMadsfmPairs();
  ASSERT_EQ(rows.size(), 2u);
  ExpectSameMadsfmRow(rows[0], MakeMadsfmRow(ImagePairToPairId(1, 2), 2));
  ExpectSameMadsfmRow(rows[1], failed);
  ExpectSameMadsfmRow(*db->ReadMadsfmPair(ImagePairToPairId(2, 3)), failed);
  EXPECT_FALSE(db->ReadMadsfmPair(ImagePairToPairId(3, 4)).has_value());
  // Restoring with only madsfm rows written (no two_view_geometries writes) changes nothing of COLMAP's.
  const auto before = SnapshotColmapTables(path);
  EXPECT_EQ(db->RestoreTwoViewGeometries(), 0);
  EXPECT_EQ(SnapshotColmapTables(path), before);
  EXPECT_TRUE(MadsfmTables(path).empty());
}

// A madsfm table written before the depth-observability columns: read as unknown (-1, NaN) read-only, and given the
// columns (old rows NULL) by the first write.
TEST_F(SyntheticDatabase, MadsfmTableWithoutObservabilityColumnsIsReadAndMigrated) {
  const std::string path = MakeDb("madsfm_old_table.db");
  {
    auto db = Database::Open(path);
    db->WriteMadsfmPair(MakeMadsfmRow(ImagePairToPairId(1, 2), 2));
  }
  {  // drop the four columns (SQLite >= 3.35)
    sqlite3* raw = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &raw), SQLITE_OK);
    for (const char* c :
         {"depth_observable", "sigma_scale", "sigma_shift1", "sigma_shift2", "sigma_focal1", "sigma_focal2"}) {
      ASSERT_EQ(sqlite3_exec(raw, (std::string("ALTER TABLE madsfm_two_view_geometries DROP COLUMN ") + c).c_str(),
                             nullptr, nullptr, nullptr),
                SQLITE_OK)
          << sqlite3_errmsg(raw);
    }
    sqlite3_close(raw);
  }
  {
    auto db = Database::Open(path, /*read_only=*/true);
    const auto row = db->ReadMadsfmPair(ImagePairToPairId(1, 2));
    ASSERT_TRUE(row.has_value());
    EXPECT_EQ(row->depth_observable, -1);
    EXPECT_TRUE(std::isnan(row->sigma_scale));
    EXPECT_TRUE(std::isnan(row->sigma_focal1));
    EXPECT_EQ(row->num_inliers, 140);
  }
  auto db = Database::Open(path);
  db->WriteMadsfmPair(MakeMadsfmRow(ImagePairToPairId(2, 3), 3));
  const auto rows = db->ReadMadsfmPairs();
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].depth_observable, -1);  // the old row
  ExpectSameMadsfmRow(rows[1], MakeMadsfmRow(ImagePairToPairId(2, 3), 3));
}

// A madsfm table of madsfm-5 (observability columns, no focal standard deviations): those read as NaN, the rest as
// stored; the first write adds the columns.
TEST_F(SyntheticDatabase, MadsfmTableWithoutFocalSigmaColumnsIsReadAndMigrated) {
  const std::string path = MakeDb("madsfm_table_v5.db");
  {
    auto db = Database::Open(path);
    db->WriteMadsfmPair(MakeMadsfmRow(ImagePairToPairId(1, 2), 2));
  }
  {
    RawDb raw(path);
    for (const char* c : {"sigma_focal1", "sigma_focal2"}) {
      raw.Exec(std::string("ALTER TABLE madsfm_two_view_geometries DROP COLUMN ") + c);
    }
  }
  {
    auto db = Database::Open(path, /*read_only=*/true);
    const auto row = db->ReadMadsfmPair(ImagePairToPairId(1, 2));
    ASSERT_TRUE(row.has_value());
    EXPECT_EQ(row->depth_observable, 1);
    EXPECT_EQ(row->sigma_scale, 0.125);
    EXPECT_TRUE(std::isnan(row->sigma_focal1));
    EXPECT_TRUE(std::isnan(row->sigma_focal2));
  }
  auto db = Database::Open(path);
  db->WriteMadsfmPair(MakeMadsfmRow(ImagePairToPairId(2, 3), 3));
  const auto rows = db->ReadMadsfmPairs();
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_TRUE(std::isnan(rows[0].sigma_focal1));  // the old row
  ExpectSameMadsfmRow(rows[1], MakeMadsfmRow(ImagePairToPairId(2, 3), 3));
}

TEST_F(SyntheticDatabase, ConcurrentReadersShareOneConnection) {
  const std::string path = MakeDb("threads.db");
  auto db = Database::Open(path, /*read_only=*/true);
  const int kThreads = 4, kRounds = 50;
  std::vector<int> mismatches(kThreads, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      for (int round = 0; round < kRounds; ++round) {
        for (const auto& [image_id, kp] : expected_.keypoints) mismatches[t] += db->ReadKeypoints(image_id) != kp;
        for (const auto& [pair_id, m] : expected_.matches) mismatches[t] += db->ReadMatches(pair_id) != m;
      }
    });
  }
  for (auto& thread : threads) thread.join();
  int total = 0;
  for (int m : mismatches) total += m;
  std::printf("[ rates    ] %d threads x %d rounds of all keypoints + matches through one connection: %d mismatches\n",
              kThreads, kRounds, total);
  EXPECT_EQ(total, 0);
}

}  // namespace
}  // namespace madsfm::colmap
