// Creating an empty COLMAP database with the schema of one COLMAP release (docs/formats.md, "COLMAP database
// schemas"), for importing matches from other matchers (as hloc does), the synthetic projects and tests. The
// statements are madsfm's own restatement of the tables, columns, indexes and `PRAGMA user_version` each release
// creates (read from COLMAP's source at the tags listed below); 3.8 is also checked against `colmap database_creator`.
#pragma once

#include <string>
#include <vector>

namespace madsfm::colmap {

// The releases whose schema madsfm writes; each stands for the tags that create the same tables.
enum class ColmapRelease {
  k3_8,   // 3.8: images.prior_* columns, user_version 3800
  k3_9,   // 3.9, 3.9.1: same tables as 3.8, user_version 3900
  k3_10,  // 3.10: images without prior_*, pose_priors(image_id, position, coordinate_system)
  k3_11,  // 3.11.0, 3.11.1: pose_priors.position_covariance
  k3_12,  // 3.12.0 ... 3.12.6: rigs, rig_sensors, frames, frame_data
  k3_13,  // 3.13.0: same tables as 3.12 (user_version still 3900)
  k4_0,   // 4.0.0 ... 4.0.4: redesigned pose_priors, descriptors.type, user_version = 4000000 + 100 * patch
  k4_1,   // 4.1.0, 4.1.1: same tables as 4.0
  kMain,  // main after 4.1.1 (4.2.0.dev0, 2026-08): two_view_geometries.camera1 / camera2
};

// Every release above, oldest first.
std::vector<ColmapRelease> AllColmapReleases();
// "3.8", ..., "4.1", "main".
std::string ColmapReleaseName(ColmapRelease release);
// Inverse of ColmapReleaseName; throws std::invalid_argument naming `option` and listing the releases.
ColmapRelease ParseColmapRelease(const std::string& name, const std::string& option = "--colmap_version");
// The PRAGMA user_version COLMAP's newest tag of the release writes into a database it creates (3800, 3900,
// 4000400 for 4.0.4, 4010100 for 4.1.1, 4020000 for main).
int ColmapReleaseUserVersion(ColmapRelease release);

// The CREATE TABLE / CREATE UNIQUE INDEX statements of the release and its PRAGMA user_version.
std::string ColmapSchemaSql(ColmapRelease release);
// COLMAP 3.8's (kept for callers that want exactly `colmap database_creator` 3.8).
std::string Colmap38SchemaSql();

// Creates `path` with the release's schema; throws std::runtime_error naming the file if it exists or cannot be
// created.
void CreateColmapDatabase(const std::string& path, ColmapRelease release);
void CreateColmap38Database(const std::string& path);

}  // namespace madsfm::colmap
