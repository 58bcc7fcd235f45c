// Our thin SQLite layer over a COLMAP database (docs: ../shared/docs/colmap.md). Reads cameras, images,
// keypoints and matches of COLMAP 3.8 ... 4.x databases (schema detected from the tables), writes two-view
// geometries back in the schema it came in, keeps COLMAP's original rows in a backup table first, and
// stores madsfm's own per-pair results in its own table. Every write happens inside a transaction.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "colmap_ext/camera/camera_models.h"

struct sqlite3;

namespace madsfm::colmap {

using image_t = uint32_t;
using camera_t = uint32_t;
using pair_t = uint64_t;

// pair_id = 2147483647 * min(id1, id2) + max(id1, id2); the smaller id is "image 1".
pair_t ImagePairToPairId(image_t id1, image_t id2);
void PairIdToImagePair(pair_t pair_id, image_t* id1, image_t* id2);

enum class SchemaVersion {
  kColmap38,  // 3.8 / 3.9: images.prior_* columns, no rigs/frames, descriptors without type
  kColmap310, // 3.10 / 3.11: no images.prior_*, pose_priors(image_id, ...)
  kColmap312, // 3.12 / 3.13: rigs, rig_sensors, frames, frame_data
  kColmap4,   // 4.x: descriptors.type, redesigned pose_priors
};
std::string SchemaVersionName(SchemaVersion v);

struct Camera {
  camera_t camera_id = 0;
  CameraIntrinsics intrinsics;
  bool prior_focal_length = false;
};

struct Image {
  image_t image_id = 0;
  std::string name;
  camera_t camera_id = 0;
};

// COLMAP TwoViewGeometry::ConfigurationType values.
enum TwoViewConfig : int { kUndefined = 0, kDegenerate = 1, kCalibrated = 2, kUncalibrated = 3, kPlanar = 4 };

struct TwoViewGeometryRow {
  pair_t pair_id = 0;
  std::vector<std::array<uint32_t, 2>> inlier_matches;  // column 0 indexes the smaller image id
  int config = kUndefined;
  std::optional<Eigen::Matrix3d> F, E, H;               // written as row-major float64 (NULL when absent)
  std::optional<Eigen::Vector4d> qvec;                  // (w, x, y, z) of cam2_from_cam1 (x2 = R x1 + t)
  std::optional<Eigen::Vector3d> tvec;                  // its translation (madsfm writes it with unit length)
  // Intrinsics the two-view solver estimated for image 1 (smaller id) / image 2: the image's camera (same id, model,
  // size) with the estimated focal. Stored in the camera1 / camera2 columns where the schema has them (COLMAP main
  // after 4.1.1, docs/formats.md); elsewhere not stored (and read back as absent).
  std::optional<Camera> camera1, camera2;
};

// True for the configs COLMAP gives a usable relative pose: CALIBRATED, UNCALIBRATED, PLANAR, PANORAMIC,
// PLANAR_OR_PANORAMIC, CALIBRATED_RIG (not UNDEFINED, DEGENERATE, WATERMARK, MULTIPLE).
bool ConfigHasPose(int config);

// COLMAP's binary encoding of a Camera in two_view_geometries.camera1 / camera2 (little-endian: u32 camera_id,
// i32 model id, u64 width, u64 height, u8 prior_focal_length, u64 number of params, f64 params).
std::vector<unsigned char> EncodeCameraBlob(const Camera& camera);
// Inverse of EncodeCameraBlob; throws std::runtime_error mentioning `what` when the size does not match.
Camera DecodeCameraBlob(const void* data, size_t num_bytes, const std::string& what);

// madsfm's own per-pair result, table madsfm_two_view_geometries.
struct MadsfmPairRow {
  pair_t pair_id = 0;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // cam2_from_cam1 (smaller id = image 1)
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  double scale = 1, shift1 = 0, shift2 = 0, focal1 = 0, focal2 = 0;
  int camera_mode = 0;  // CameraMode as int
  int method = 0;       // 0 hybrid, 1 points (fallback)
  int num_inliers_reproj1 = 0, num_inliers_reproj2 = 0, num_inliers_sampson = 0, num_inliers = 0;
  double score = 0;
  std::string options_fingerprint;
  int status = 0;       // 0 ok, 1 failed (no model), 2 skipped (too few matches)
  // Whether the pair determines scale and shifts (HybridEstimate::depth_observable: 1 yes, 0 no, -1 unknown: a row
  // written before madsfm stored it), and their standard deviations (shifts relative to the median prior of their
  // image, scale relative to itself; NaN when not fitted).
  int depth_observable = -1;
  double sigma_scale = std::numeric_limits<double>::quiet_NaN();
  double sigma_shift1 = std::numeric_limits<double>::quiet_NaN();
  double sigma_shift2 = std::numeric_limits<double>::quiet_NaN();
  // Focal modes: relative standard deviations of focal1 / focal2 with pose, scale and shifts free
  // (HybridEstimate::sigma_focal0/1); NaN when calibrated, unknown or written before madsfm stored them.
  double sigma_focal1 = std::numeric_limits<double>::quiet_NaN();
  double sigma_focal2 = std::numeric_limits<double>::quiet_NaN();
};

// Thread safety: the connection is opened in SQLite's serialized mode and every call prepares its own statements, so
// several threads may read through one Database at once. Writes (and Transactions) belong to one thread.
// Every write method is atomic on its own: it opens BEGIN IMMEDIATE ... COMMIT, or a savepoint when the caller already
// holds a Transaction (then nothing is durable before the caller's Commit()).
class Database {
 public:
  // Opens an existing database. Throws std::runtime_error naming the file when it does not exist, is not an
  // SQLite database, lacks COLMAP's tables (unknown schema), or cannot be opened for writing (read_only=false).
  // A busy database (another writer) is waited for up to busy_timeout_ms, then an error.
  static std::unique_ptr<Database> Open(const std::string& path, bool read_only = false, int busy_timeout_ms = 5000);
  ~Database();

  const std::string& path() const { return path_; }
  SchemaVersion schema() const { return schema_; }
  // Whether two_view_geometries has COLMAP main's camera1 / camera2 columns.
  bool has_two_view_cameras() const { return two_view_cameras_; }
  // PRAGMA user_version as found (madsfm never changes it).
  int user_version() const { return user_version_; }

  // How errors name images and cameras, in the user's terms: "'img_0003.png' (image_id 4)",
  // "camera_id 2 (of 'a.jpg', 'b.jpg')", "pair 8589934595 ('a.jpg' (image_id 2), 'b.jpg' (image_id 3))".
  // Ids missing from the images / cameras table are said to be missing. Meant for error paths (they query).
  std::string DescribeImage(image_t image_id) const;
  std::string DescribeCamera(camera_t camera_id) const;
  std::string DescribePair(pair_t pair_id) const;

  // All cameras, by id. params must be float64 x CameraModelNumParams(model) (error naming the camera_id otherwise);
  // cameras of unknown model ids are returned as stored (callers decide).
  std::vector<Camera> ReadCameras() const;
  // All images (id, name, camera id), by id.
  std::vector<Image> ReadImages() const;
  // x, y of every keypoint (COLMAP convention, pixel centres at +0.5). Throws naming the image when the blob
  // size does not match rows x cols or cols is not 2, 4 or 6. An image without a keypoints row has none.
  std::vector<Eigen::Vector2d> ReadKeypoints(image_t image_id) const;
  // All pairs with a matches row and rows > 0, with their number of matches, sorted by pair id.
  std::vector<std::pair<pair_t, int>> ReadMatchedPairs() const;
  // uint32 N x 2 matches of a pair (empty without a row); throws naming the pair when the blob size is wrong.
  std::vector<std::array<uint32_t, 2>> ReadMatches(pair_t pair_id) const;
  // The two_view_geometries row of a pair (nullopt without one). NULL or empty blobs are absent, and so are the
  // placeholders COLMAP < 4 writes when nothing was estimated (all-zero F/E/H, zero or identity-with-zero-t pose), as
  // 4.x's migration does. camera1 / camera2 are read where the schema has them. Wrong blob sizes throw naming the
  // pair.
  std::optional<TwoViewGeometryRow> ReadTwoViewGeometry(pair_t pair_id) const;
  // COLMAP's own verified inlier matches of a pair: the two_view_geometries row as COLMAP wrote it (from the backup
  // once madsfm has written rows), nullopt without a row. COLMAP's matchers write a row for every matched pair, with
  // 0 rows when geometric verification failed. Wrong blob sizes throw naming the pair.
  std::optional<std::vector<std::array<uint32_t, 2>>> ReadColmapInlierMatches(pair_t pair_id) const;

  // RAII transaction: BEGIN IMMEDIATE on construction, COMMIT on Commit(), ROLLBACK if destroyed uncommitted (the
  // destructor never throws). Waits up to the busy timeout for another writer, then throws. Not nestable.
  class Transaction {
   public:
    explicit Transaction(Database* db);
    ~Transaction();
    void Commit();
   private:
    Database* db_;
    bool done_ = false;
  };

  // Copies COLMAP's two_view_geometries rows into madsfm_backup_two_view_geometries once (no-op if the backup
  // exists). WriteTwoViewGeometry calls it before its first write, so calling it explicitly is optional.
  void BackupTwoViewGeometries();
  bool HasBackup() const;
  // Undoes everything madsfm wrote, in one transaction: the two_view_geometries rows of pairs madsfm wrote (tracked,
  // plus the pairs of madsfm_two_view_geometries) are deleted and their backed-up originals re-inserted byte for
  // byte; matches rows madsfm created are deleted; cameras changed by UpdateCamera get their original rows back;
  // madsfm's tables are dropped. Returns the number of two_view_geometries rows re-inserted (0 if nothing to undo).
  int RestoreTwoViewGeometries();

  // INSERT OR REPLACE of the two_view_geometries row (NULL rules of 4.x respected: absent F/E/H/pose are NULL;
  // F/E/H 72-byte row-major float64, qvec 4 and tvec 3 float64, data uint32 N x 2, cols = 2), and a matches row is
  // created from the inlier matches if the pair has none (COLMAP re-matches pairs with only one of the two rows);
  // such rows are tracked for RestoreTwoViewGeometries. Backs up COLMAP's rows first (once). camera1 / camera2 are
  // written where the schema has those columns (NULL when absent) and dropped where it has not; the schema and
  // PRAGMA user_version are never changed.
  // Never writes what COLMAP would take for a placeholder or could not use: throws std::invalid_argument naming the
  // pair when pair_id is not ImagePairToPairId's, exactly one of qvec / tvec is set, the pose is not finite, qvec is
  // not a unit quaternion or tvec is zero, a pose comes with a config without one (ConfigHasPose), F / E / H is all
  // zero or not finite, camera1 / camera2 come without E, or a camera does not match its image's camera (id, model,
  // size, number of params; error naming the image).
  void WriteTwoViewGeometry(const TwoViewGeometryRow& row);

  // Table madsfm_two_view_geometries: one row per pair, R (row-major) and t as float64 blobs, every other field of
  // MadsfmPairRow in its own column (NaN reals read back as NaN).
  void CreateMadsfmTables();  // idempotent
  void WriteMadsfmPair(const MadsfmPairRow& row);  // INSERT OR REPLACE; creates the table when missing
  std::optional<MadsfmPairRow> ReadMadsfmPair(pair_t pair_id) const;  // nullopt without row (or table)
  std::vector<MadsfmPairRow> ReadMadsfmPairs() const;                 // by pair id

  // Updates params and prior_focal_length of a camera, after saving its original row (once) in
  // madsfm_backup_cameras. Throws when the camera does not exist, or when camera.intrinsics' model differs from the
  // stored one or has the wrong number of params.
  void UpdateCamera(const Camera& camera);

  // Names of all tables in the database.
  std::vector<std::string> ListTables() const;

  sqlite3* handle() const { return db_; }

 private:
  Database() = default;
  void CheckWritable(const TwoViewGeometryRow& row) const;  // the checks of WriteTwoViewGeometry
  std::string path_;
  sqlite3* db_ = nullptr;
  SchemaVersion schema_ = SchemaVersion::kColmap38;
  bool two_view_cameras_ = false;
  int user_version_ = 0;
};

}  // namespace madsfm::colmap
