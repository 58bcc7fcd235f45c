#include "colmap_ext/pipeline/two_view_estimator.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>

#include "colmap_ext/database/database.h"
#include "colmap_ext/pipeline/focal_estimator.h"
#include "madsfm/estimators/relpose_problem.h"
#include "madsfm/geometry/pose_error.h"
#include "madsfm/io/depth_map_io.h"
#include "madsfm/io/npy.h"
#include "madsfm/synthetic/two_view_scene.h"
#include "colmap_ext/synthetic/synthetic_project.h"
#include "testing/colmap_database_builder.h"
#include "testing/temp_dir.h"

namespace madsfm {
namespace {

namespace fs = std::filesystem;

// A synthetic COLMAP project (colmap_ext/synthetic): `num_pairs` independent pairs (images 2k+1, 2k+2), one
// SIMPLE_PINHOLE camera per pair (with `calibrated` the true focal and a prior, else COLMAP's 1.2 max(W, H) guess),
// 300 matches with 30% outliers, and depth sidecars <name>.npy.
struct Project {
  std::shared_ptr<testing::TempDir> scratch;  // removed with the last copy of the project
  std::string dir, db, depths;
  std::vector<SyntheticPair> pairs;
};

Project MakeProject(const std::string& name, int num_pairs, bool calibrated,
                    colmap::ColmapRelease release = colmap::ColmapRelease::k3_8, double outlier_ratio = 0.3) {
  Project p;
  p.scratch = std::make_shared<testing::TempDir>("tve_" + name);
  p.dir = p.scratch->Sub("project");
  colmap::SyntheticProjectOptions o;
  o.output_path = p.dir;
  o.preset = "indoor_shared_focal";
  o.num_pairs = num_pairs;
  o.min_num_matches = o.max_num_matches = 300;
  o.outlier_ratio = outlier_ratio;
  o.calibrated = calibrated;
  o.seed = 7;
  o.keep_pairs = true;
  o.colmap_release = release;
  colmap::SyntheticProject sp = colmap::WriteSyntheticProject(o);
  p.db = sp.database_path;
  p.depths = sp.depth_path;
  p.pairs = std::move(sp.pairs);
  return p;
}

TwoViewEstimatorOptions Options(const Project& p, int threads = 2) {
  TwoViewEstimatorOptions o;
  o.database_path = p.db;
  o.depth_path = p.depths;
  o.num_threads = threads;
  o.progress = false;
  return o;
}

// Options with an empty depth folder: every pair runs the point method.
TwoViewEstimatorOptions OptionsWithoutDepth(const Project& p) {
  TwoViewEstimatorOptions o = Options(p);
  o.depth_path = p.dir + "/empty_depths";
  fs::create_directories(o.depth_path);
  return o;
}

TEST(TwoViewEstimator, EstimatesEveryPairAndWritesColmapRows) {
  const Project p = MakeProject("estimate", 6, false);
  const TwoViewEstimatorSummary s = RunTwoViewEstimatorImpl(Options(p));
  EXPECT_EQ(s.num_pairs, 6);
  EXPECT_EQ(s.num_estimated, 6);
  EXPECT_EQ(s.num_point_fallback, 0);
  EXPECT_EQ(s.num_images_with_depth, 12);
  EXPECT_EQ(testing::IntegrityCheck(p.db), "ok");
  auto db = colmap::Database::Open(p.db, true);
  int accurate = 0, observable = 0;
  for (int k = 0; k < 6; ++k) {
    const colmap::pair_t id = colmap::ImagePairToPairId(2 * k + 1, 2 * k + 2);
    const auto row = db->ReadMadsfmPair(id);
    ASSERT_TRUE(row.has_value());
    EXPECT_EQ(row->camera_mode, static_cast<int>(CameraMode::kSharedFocal));
    const auto geometry = db->ReadTwoViewGeometry(id);
    ASSERT_TRUE(geometry.has_value());
    EXPECT_EQ(geometry->config, colmap::kUncalibrated);
    EXPECT_EQ(static_cast<int>(geometry->inlier_matches.size()), row->num_inliers_sampson);
    const Eigen::Matrix4d& T = *p.pairs[k].pair.T_0to1;
    const double rot = RotationErrorDeg(row->R, T.topLeftCorner<3, 3>());
    const double focal = std::abs(row->focal1 / p.pairs[k].focal0 - 1.0);
    accurate += rot < 1.0 && focal < 0.05;
    // The inliers are (mostly) the true inliers. (The generator keeps the 30% outlier ratio, but a pair whose views
    // overlap little gets fewer inliers than 70% of the 300 requested, so compare with its own count.)
    const double true_inliers = p.pairs[k].num_inliers;
    EXPECT_NEAR(static_cast<double>(geometry->inlier_matches.size()), true_inliers, std::max(5.0, 0.05 * true_inliers));
    // The estimator's word on the depth corrections is stored with them.
    EXPECT_TRUE(row->depth_observable == 0 || row->depth_observable == 1);
    EXPECT_TRUE(std::isfinite(row->sigma_scale) && row->sigma_scale >= 0);
    observable += row->depth_observable == 1;
  }
  EXPECT_GE(accurate, 5);
  EXPECT_GE(observable, 4) << "baselines of 5-30% of the depth: most pairs determine scale and shifts";
}

// On a database with COLMAP main's camera1 / camera2 columns (here a 3.8 database main has opened, which adds them
// with ALTER TABLE), the estimated focals go there in COLMAP's camera blob, next to E, F and the pose that COLMAP 4's
// global mapper keeps; schema and user_version stay as they were.
TEST(TwoViewEstimator, WritesEstimatedCamerasWhereTheSchemaHasThem) {
  const Project p = MakeProject("cameras", 3, false);
  testing::ExecSql(p.db, "ALTER TABLE two_view_geometries ADD COLUMN camera1 BLOB; "
                         "ALTER TABLE two_view_geometries ADD COLUMN camera2 BLOB; PRAGMA user_version = 4020000;");
  const std::string schema_before = testing::DumpTable(p.db, "sqlite_master");
  const TwoViewEstimatorSummary s = RunTwoViewEstimatorImpl(Options(p));
  EXPECT_EQ(s.num_estimated, 3);
  auto db = colmap::Database::Open(p.db, true);
  ASSERT_TRUE(db->has_two_view_cameras());
  EXPECT_EQ(db->user_version(), 4020000);
  const auto cameras = db->ReadCameras();
  for (int k = 0; k < 3; ++k) {
    const colmap::pair_t id = colmap::ImagePairToPairId(2 * k + 1, 2 * k + 2);
    const auto row = db->ReadMadsfmPair(id);
    const auto geometry = db->ReadTwoViewGeometry(id);
    ASSERT_TRUE(row.has_value() && geometry.has_value());
    EXPECT_EQ(geometry->config, colmap::kUncalibrated);
    ASSERT_TRUE(geometry->camera1.has_value() && geometry->camera2.has_value());
    ASSERT_TRUE(geometry->E.has_value() && geometry->F.has_value() && geometry->qvec.has_value());
    const colmap::Camera& stored = cameras[k];  // one camera per pair, ids 1..3
    for (const colmap::Camera* c : {&*geometry->camera1, &*geometry->camera2}) {
      EXPECT_EQ(c->camera_id, stored.camera_id);
      EXPECT_EQ(c->intrinsics.model_id, stored.intrinsics.model_id);
      EXPECT_EQ(c->intrinsics.width, stored.intrinsics.width);
      EXPECT_EQ(c->intrinsics.params.size(), stored.intrinsics.params.size());
      EXPECT_EQ(c->intrinsics.PrincipalX(), stored.intrinsics.PrincipalX());
    }
    EXPECT_DOUBLE_EQ(geometry->camera1->intrinsics.FocalX(), row->focal1);
    EXPECT_DOUBLE_EQ(geometry->camera2->intrinsics.FocalX(), row->focal2);
    EXPECT_LT(std::abs(geometry->camera1->intrinsics.FocalX() / p.pairs[k].focal0 - 1.0), 0.05);
    // cam2_from_cam1 with unit translation, the rotation madsfm estimated.
    const Eigen::Quaterniond q((*geometry->qvec)(0), (*geometry->qvec)(1), (*geometry->qvec)(2), (*geometry->qvec)(3));
    EXPECT_LT((q.toRotationMatrix() - row->R).norm(), 1e-9);
    EXPECT_NEAR(geometry->tvec->norm(), 1.0, 1e-12);
    EXPECT_LT((*geometry->tvec - row->t.normalized()).norm(), 1e-9);
    // ... and against the ground truth X2 = R X1 + t of the synthetic pair (image 1 = the smaller id): the stored
    // qvec / tvec are cam2_from_cam1, not its inverse.
    const Eigen::Matrix4d& T = *p.pairs[k].pair.T_0to1;
    EXPECT_LT(RotationErrorDeg(q.toRotationMatrix(), T.topLeftCorner<3, 3>()), 2.0);
    const Eigen::Vector3d t_true = T.topRightCorner<3, 1>().normalized();
    EXPECT_GT(geometry->tvec->dot(t_true), std::cos(5.0 * M_PI / 180.0));
  }
  EXPECT_NE(testing::DumpTable(p.db, "sqlite_master").find("madsfm"), std::string::npos);
  db.reset();
  // Restore gives back the original rows (no geometries before) and the schema as it was.
  colmap::Database::Open(p.db)->RestoreTwoViewGeometries();
  EXPECT_EQ(testing::DumpTable(p.db, "sqlite_master"), schema_before);
  EXPECT_EQ(colmap::Database::Open(p.db, true)->user_version(), 4020000);
}

// The whole estimator on a database of every COLMAP release (DatabaseBuilder's schemas, with the rigs and frames
// 3.12+ have): every pair estimated, camera1 / camera2 only where the schema has them, the schema and user_version
// untouched, and restore gives back the database as it was.
class TwoViewEstimatorOnRelease : public ::testing::TestWithParam<colmap::ColmapRelease> {};

TEST_P(TwoViewEstimatorOnRelease, EstimatesWritesAndRestores) {
  const colmap::ColmapRelease release = GetParam();
  const Project p = MakeProject("release_" + colmap::ColmapReleaseName(release), 3, false, release);
  const std::string schema_before = testing::DumpTable(p.db, "sqlite_master");
  const std::string tvg_before = testing::DumpTable(p.db, "two_view_geometries");
  const std::string frames_before = release >= colmap::ColmapRelease::k3_12 ? testing::DumpTable(p.db, "frames") : "";
  const TwoViewEstimatorSummary s = RunTwoViewEstimatorImpl(Options(p));
  EXPECT_EQ(s.num_estimated, 3);
  {
    auto db = colmap::Database::Open(p.db, true);
    EXPECT_EQ(db->user_version(), colmap::ColmapReleaseUserVersion(release));
    EXPECT_EQ(db->has_two_view_cameras(), release == colmap::ColmapRelease::kMain);
    for (int k = 0; k < 3; ++k) {
      const auto g = db->ReadTwoViewGeometry(colmap::ImagePairToPairId(2 * k + 1, 2 * k + 2));
      ASSERT_TRUE(g.has_value());
      EXPECT_TRUE(g->qvec.has_value() && g->E.has_value() && g->F.has_value());
      EXPECT_EQ(g->camera1.has_value(), release == colmap::ColmapRelease::kMain);
    }
    if (release >= colmap::ColmapRelease::k3_12) {
      EXPECT_EQ(testing::DumpTable(p.db, "frames"), frames_before);
    }
  }
  colmap::Database::Open(p.db)->RestoreTwoViewGeometries();
  EXPECT_EQ(testing::DumpTable(p.db, "sqlite_master"), schema_before);
  EXPECT_EQ(testing::DumpTable(p.db, "two_view_geometries"), tvg_before);
  EXPECT_EQ(colmap::Database::Open(p.db, true)->user_version(), colmap::ColmapReleaseUserVersion(release));
}

INSTANTIATE_TEST_SUITE_P(Releases, TwoViewEstimatorOnRelease, ::testing::ValuesIn(colmap::AllColmapReleases()),
                         [](const ::testing::TestParamInfo<colmap::ColmapRelease>& info) {
                           std::string name = "Colmap" + colmap::ColmapReleaseName(info.param);
                           for (char& c : name) {
                             if (c == '.') c = '_';
                           }
                           return name;
                         });

TEST(TwoViewEstimator, ResumesAndIsDeterministicAcrossThreadCounts) {
  const Project a = MakeProject("det_a", 5, true);
  const Project b = MakeProject("det_b", 5, true);
  RunTwoViewEstimatorImpl(Options(a, 1));
  RunTwoViewEstimatorImpl(Options(b, 2));
  EXPECT_EQ(testing::DumpTable(a.db, "two_view_geometries"), testing::DumpTable(b.db, "two_view_geometries"));
  // The rows are identical but for the depth folder named in the options fingerprint.
  std::string rows_b = testing::DumpTable(b.db, "madsfm_two_view_geometries");
  for (size_t at; (at = rows_b.find(b.dir)) != std::string::npos;) rows_b.replace(at, b.dir.size(), a.dir);
  EXPECT_EQ(testing::DumpTable(a.db, "madsfm_two_view_geometries"), rows_b);
  // A second run with the same options skips every pair and changes nothing.
  const std::string before = testing::DumpTable(a.db, "two_view_geometries");
  const TwoViewEstimatorSummary again = RunTwoViewEstimatorImpl(Options(a, 2));
  EXPECT_EQ(again.num_skipped_done, 5);
  EXPECT_EQ(again.num_estimated, 0);
  EXPECT_EQ(testing::DumpTable(a.db, "two_view_geometries"), before);
  // Calibrated cameras (focal priors) are estimated in calibrated mode with E.
  auto db = colmap::Database::Open(a.db, true);
  const auto geometry = db->ReadTwoViewGeometry(colmap::ImagePairToPairId(1, 2));
  ASSERT_TRUE(geometry.has_value());
  EXPECT_EQ(geometry->config, colmap::kCalibrated);
  EXPECT_TRUE(geometry->E.has_value());
}

TEST(TwoViewEstimator, RestorePutsColmapRowsBack) {
  const Project p = MakeProject("restore", 3, false);
  // COLMAP's matcher wrote a geometry for pair (1, 2) before (config 3, three inlier matches).
  testing::ExecSql(p.db, "INSERT INTO two_view_geometries(pair_id, rows, cols, data, config) VALUES(" +
                             std::to_string(colmap::ImagePairToPairId(1, 2)) +
                             ", 3, 2, x'000000000000000001000000010000000200000002000000', 3)");
  const std::string tvg_before = testing::DumpTable(p.db, "two_view_geometries");
  const std::string cams_before = testing::DumpTable(p.db, "cameras");
  RunTwoViewEstimatorImpl(Options(p));
  FocalEstimatorOptions fo;
  fo.database_path = p.db;
  RunFocalEstimatorImpl(fo);
  EXPECT_NE(testing::DumpTable(p.db, "two_view_geometries"), tvg_before);
  EXPECT_NE(testing::DumpTable(p.db, "cameras"), cams_before);
  auto db = colmap::Database::Open(p.db);
  db->RestoreTwoViewGeometries();
  db.reset();
  EXPECT_EQ(testing::DumpTable(p.db, "two_view_geometries"), tvg_before);
  EXPECT_EQ(testing::DumpTable(p.db, "cameras"), cams_before);
  EXPECT_EQ(testing::IntegrityCheck(p.db), "ok");
}

TEST(TwoViewEstimator, FocalEstimatorRecoversTheFocalLengths) {
  const Project p = MakeProject("focal", 6, false);
  RunTwoViewEstimatorImpl(Options(p));
  FocalEstimatorOptions fo;
  fo.database_path = p.db;
  const auto changes = RunFocalEstimatorImpl(fo);
  ASSERT_EQ(changes.size(), 6u);
  int good = 0;
  for (size_t k = 0; k < changes.size(); ++k) {
    EXPECT_TRUE(changes[k].updated);
    EXPECT_EQ(changes[k].num_samples, 1);
    EXPECT_FALSE(changes[k].trusted);
    good += std::abs(changes[k].new_focal / p.pairs[k].focal0 - 1.0) < 0.03;
  }
  EXPECT_GE(good, 5);
  // One pair per camera is not enough evidence for a prior (min_prior_pairs = 5): the estimates are initial values
  // only, which COLMAP refines.
  auto db = colmap::Database::Open(p.db, true);
  for (const auto& cam : db->ReadCameras()) EXPECT_FALSE(cam.prior_focal_length);
}

// One camera shared by six pairs whose true focal lengths differ (fields of view drawn in [50, 100] deg): the six
// estimates disagree, so the aggregate is only an initial value; with a tolerance that accepts every estimate the
// same evidence becomes a prior. Cameras without pairs are left as they are.
TEST(TwoViewEstimator, FocalBecomesAPriorOnlyWhenEnoughPairsAgree) {
  const Project p = MakeProject("focal_trust", 6, false);
  std::vector<double> focals;
  for (const auto& pair : p.pairs) focals.push_back(pair.focal0);
  std::sort(focals.begin(), focals.end());
  int near_median = 0;
  for (double f : focals) near_median += std::abs(f / focals[3] - 1.0) <= 0.03;
  ASSERT_LT(near_median, 5) << "the six true focals must disagree for this test";
  testing::ExecSql(p.db, "UPDATE images SET camera_id = 1");
  RunTwoViewEstimatorImpl(Options(p));
  const std::string before = testing::DumpTable(p.db, "cameras");
  FocalEstimatorOptions fo;
  fo.database_path = p.db;
  auto changes = RunFocalEstimatorImpl(fo);
  ASSERT_EQ(changes.size(), 6u);  // one camera per pair in the project; only camera 1 is used now
  EXPECT_EQ(changes[0].num_samples, 6);
  EXPECT_LT(changes[0].num_agreeing, 5);
  EXPECT_TRUE(changes[0].updated);
  EXPECT_FALSE(changes[0].trusted);
  for (size_t k = 1; k < changes.size(); ++k) {
    EXPECT_EQ(changes[k].num_samples, 0);
    EXPECT_FALSE(changes[k].updated);
  }
  {
    auto db = colmap::Database::Open(p.db, true);
    EXPECT_FALSE(db->ReadCameras()[0].prior_focal_length);
  }
  // Every estimate within the tolerance, but none precise enough: still only an initial value.
  fo.prior_agreement = 10.0;
  fo.prior_max_pair_sigma = 1e-6;
  changes = RunFocalEstimatorImpl(fo);
  EXPECT_EQ(changes[0].num_agreeing, 0);
  EXPECT_FALSE(changes[0].trusted);
  fo.prior_max_pair_sigma = 1.0;  // every estimate "agrees"
  changes = RunFocalEstimatorImpl(fo);
  EXPECT_EQ(changes[0].num_agreeing, 6);
  EXPECT_TRUE(changes[0].trusted);
  auto db = colmap::Database::Open(p.db, true);
  // The pairs' focal standard deviations are stored (shared focal: the same for both images), small but not zero
  // on these wide-baseline pairs.
  for (const colmap::MadsfmPairRow& row : db->ReadMadsfmPairs()) {
    EXPECT_GT(row.sigma_focal1, 0.0);
    EXPECT_LT(row.sigma_focal1, 0.05);
    EXPECT_EQ(row.sigma_focal1, row.sigma_focal2);
  }
  const auto cameras = db->ReadCameras();
  EXPECT_TRUE(cameras[0].prior_focal_length);
  for (size_t k = 1; k < cameras.size(); ++k) EXPECT_FALSE(cameras[k].prior_focal_length);
  EXPECT_NE(testing::DumpTable(p.db, "cameras"), before);
}

// Metric depth (sensor depth, metric depth models): the sidecars hold the true depth times one scale per image (1.0
// for the first image of a pair, 1.5 for the second), no shift. With estimate_shift = 0 the stored shifts are exactly
// 0, the scale is the ratio of the two images' scales (1 / 1.5: the corrected depth of the second view is scale x its
// prior, in the first view's units), the pose and focal are accurate, the pairs say their scale is determined, and a
// run with shifts (another options fingerprint) estimates every pair again.
TEST(TwoViewEstimator, MetricDepthWithoutShifts) {
  const Project p = MakeProject("metric", 6, false);
  auto db = colmap::Database::Open(p.db, true);
  std::map<colmap::image_t, std::string> names;
  for (const auto& image : db->ReadImages()) names[image.image_id] = image.name;
  db.reset();
  for (int k = 0; k < 6; ++k) {
    for (int view = 0; view < 2; ++view) {
      const DepthMap& truth = view == 0 ? p.pairs[k].true_depth_map0 : p.pairs[k].true_depth_map1;
      std::vector<double> metric(truth.data.size());
      for (size_t i = 0; i < metric.size(); ++i) {
        metric[i] = truth.data[i] > 0 ? (view == 0 ? 1.0 : 1.5) * truth.data[i] : std::nan("");
      }
      const std::string path = p.depths + "/" + names.at(2 * k + 1 + view) + ".npy";
      ASSERT_TRUE(fs::exists(path)) << path;
      WriteNpy(path, {static_cast<size_t>(truth.height), static_cast<size_t>(truth.width)}, metric.data());
    }
  }
  TwoViewEstimatorOptions o = Options(p);
  o.estimator.estimate_shift = false;
  ASSERT_EQ(RunTwoViewEstimatorImpl(o).num_estimated, 6);
  db = colmap::Database::Open(p.db, true);
  int accurate = 0, observable = 0;
  std::string fingerprint;
  for (int k = 0; k < 6; ++k) {
    const auto row = db->ReadMadsfmPair(colmap::ImagePairToPairId(2 * k + 1, 2 * k + 2));
    ASSERT_TRUE(row.has_value());
    EXPECT_EQ(row->shift1, 0.0);
    EXPECT_EQ(row->shift2, 0.0);
    const Eigen::Matrix4d& T = *p.pairs[k].pair.T_0to1;
    const double rot = RotationErrorDeg(row->R, T.topLeftCorner<3, 3>());
    const double focal = std::abs(row->focal1 / p.pairs[k].focal0 - 1.0);
    std::printf("pair %d: rot %.3f deg, focal %.3f%%, scale %.4f\n", k, rot, 100 * focal, row->scale);
    accurate += rot < 0.5 && focal < 0.02 && std::abs(row->scale * 1.5 - 1.0) < 0.02;
    fingerprint = row->options_fingerprint;
    // Determined without shifts: the scale's sigma decides (the shifts' are NULL), so seed_model can use the pair.
    EXPECT_TRUE(std::isnan(row->sigma_shift1) && std::isnan(row->sigma_shift2));
    observable += row->depth_observable == 1;
  }
  EXPECT_GE(accurate, 5);
  EXPECT_GE(observable, 5) << "baselines of 5-30% of the depth determine the scale";
  db.reset();
  o.estimator.estimate_shift = true;
  const TwoViewEstimatorSummary again = RunTwoViewEstimatorImpl(o);
  EXPECT_EQ(again.num_estimated, 6);
  EXPECT_EQ(again.num_skipped_done, 0);
  db = colmap::Database::Open(p.db, true);
  EXPECT_NE(db->ReadMadsfmPair(colmap::ImagePairToPairId(1, 2))->options_fingerprint, fingerprint);
}

TEST(TwoViewEstimator, ImagesWithoutDepthFallBackToPoints) {
  const Project p = MakeProject("nodepth", 3, true);
  const TwoViewEstimatorOptions o = OptionsWithoutDepth(p);
  const TwoViewEstimatorSummary s = RunTwoViewEstimatorImpl(o);
  EXPECT_EQ(s.num_estimated, 3);
  EXPECT_EQ(s.num_point_fallback, 3);
  EXPECT_EQ(s.num_images_with_depth, 0);
}

// A point-only pair whose COLMAP verification found fewer than min_num_inliers inliers (a row with 0 or 10 rows) is not
// searched: its row stays COLMAP's, and madsfm records it as failed. A pair without a COLMAP row (verification never
// ran) is estimated, and with depth priors every pair is.
TEST(TwoViewEstimator, PointOnlyPairsColmapRejectedAreNotSearched) {
  const Project p = MakeProject("not_verified", 3, false);
  const auto id12 = colmap::ImagePairToPairId(1, 2), id34 = colmap::ImagePairToPairId(3, 4),
             id56 = colmap::ImagePairToPairId(5, 6);
  testing::ExecSql(p.db, "DELETE FROM two_view_geometries");
  testing::ExecSql(p.db, "INSERT INTO two_view_geometries (pair_id, rows, cols, data, config) VALUES (" +
                             std::to_string(id12) + ", 0, 2, NULL, 0)");
  testing::ExecSql(p.db, "INSERT INTO two_view_geometries (pair_id, rows, cols, data, config) SELECT pair_id, 10, 2, "
                         "substr(data, 1, 80), 3 FROM matches WHERE pair_id = " + std::to_string(id34));
  const TwoViewEstimatorOptions o = OptionsWithoutDepth(p);
  const TwoViewEstimatorSummary s = RunTwoViewEstimatorImpl(o);
  EXPECT_EQ(s.num_not_verified, 2);
  EXPECT_EQ(s.num_estimated, 1);
  EXPECT_EQ(s.num_point_fallback, 1);
  EXPECT_EQ(s.num_failed, 0);
  {
    auto db = colmap::Database::Open(p.db, true);
    EXPECT_EQ(db->ReadMadsfmPair(id12)->status, 1);
    EXPECT_EQ(db->ReadMadsfmPair(id34)->status, 1);
    EXPECT_EQ(db->ReadMadsfmPair(id56)->status, 0);
    EXPECT_EQ(db->ReadTwoViewGeometry(id12)->inlier_matches.size(), 0u);
    EXPECT_EQ(db->ReadTwoViewGeometry(id34)->inlier_matches.size(), 10u);
    EXPECT_GE(db->ReadTwoViewGeometry(id56)->inlier_matches.size(), 150u);
  }
  // A rerun counts them as done.
  EXPECT_EQ(RunTwoViewEstimatorImpl(o).num_skipped_done, 3);
  // With depth priors (another fingerprint) all three pairs are estimated.
  const TwoViewEstimatorSummary with_depth = RunTwoViewEstimatorImpl(Options(p));
  EXPECT_EQ(with_depth.num_not_verified, 0);
  EXPECT_EQ(with_depth.num_estimated, 3);
  EXPECT_EQ(with_depth.num_point_fallback, 0);
}

// COLMAP's verified inlier matches guide the sampling: with 70% outliers among the raw matches and a verification
// that kept the true inliers (plus a few outliers), the search needs far fewer iterations and is as accurate.
TEST(TwoViewEstimator, ColmapsVerifiedMatchesGuideTheSampling) {
  const Project p = MakeProject("guided", 6, false, colmap::ColmapRelease::k3_8, 0.7);
  // COLMAP's rows, as its matcher writes them (a hex blob of uint32 index pairs, little-endian).
  testing::ExecSql(p.db, "DELETE FROM two_view_geometries");
  for (int k = 0; k < 6; ++k) {
    const std::vector<uint8_t>& is_inlier = p.pairs[k].is_inlier;
    std::string hex;
    int rows = 0, outliers = 0;
    char byte[3];
    for (uint32_t i = 0; i < is_inlier.size(); ++i) {
      if (!is_inlier[i] && outliers++ % 20 != 0) continue;
      for (int twice = 0; twice < 2; ++twice) {
        for (int b = 0; b < 4; ++b) {
          std::snprintf(byte, sizeof(byte), "%02X", (i >> (8 * b)) & 0xFF);
          hex += byte;
        }
      }
      ++rows;
    }
    testing::ExecSql(p.db, "INSERT INTO two_view_geometries (pair_id, rows, cols, data, config) VALUES (" +
                               std::to_string(colmap::ImagePairToPairId(2 * k + 1, 2 * k + 2)) + ", " +
                               std::to_string(rows) + ", 2, X'" + hex + "', 3)");
  }
  auto run = [&](double fraction, int* accurate) {
    const testing::TempDir copy("tve_guided_copy");
    const std::string db_path = copy.Sub("database.db");
    fs::copy_file(p.db, db_path);
    TwoViewEstimatorOptions o = Options(p);
    o.database_path = db_path;
    o.estimator.guided_sampling_fraction = fraction;
    const TwoViewEstimatorSummary s = RunTwoViewEstimatorImpl(o);
    EXPECT_EQ(s.num_estimated, 6);
    auto db = colmap::Database::Open(db_path, true);
    *accurate = 0;
    for (int k = 0; k < 6; ++k) {
      const auto row = db->ReadMadsfmPair(colmap::ImagePairToPairId(2 * k + 1, 2 * k + 2));
      const double rot = RotationErrorDeg(row->R, p.pairs[k].pair.T_0to1->topLeftCorner<3, 3>());
      *accurate += rot < 1.0 && std::abs(row->focal1 / p.pairs[k].focal0 - 1.0) < 0.05;
    }
    return s.num_iterations;
  };
  int accurate_uniform = 0, accurate_guided = 0;
  const int64_t uniform = run(0.0, &accurate_uniform);
  const int64_t guided = run(0.9, &accurate_guided);
  std::printf("70%% outliers, 6 pairs: %lld iterations uniform (%d accurate), %lld guided (%d accurate)\n",
              static_cast<long long>(uniform), accurate_uniform, static_cast<long long>(guided), accurate_guided);
  EXPECT_LT(2 * guided, uniform);
  EXPECT_GE(accurate_guided, accurate_uniform);
  EXPECT_GE(accurate_guided, 5);
}

// Without depth evidence (every pair point-only) focal_estimator keeps COLMAP's cameras as they are.
TEST(TwoViewEstimator, FocalEstimatorKeepsColmapsFocalWithoutDepthEvidence) {
  const Project p = MakeProject("nodepth_focal", 3, false);
  const TwoViewEstimatorOptions o = OptionsWithoutDepth(p);
  const TwoViewEstimatorSummary s = RunTwoViewEstimatorImpl(o);
  ASSERT_EQ(s.num_point_fallback, 3);
  const std::string before = testing::DumpTable(p.db, "cameras");
  FocalEstimatorOptions fo;
  fo.database_path = p.db;
  for (const FocalChange& c : RunFocalEstimatorImpl(fo)) {
    EXPECT_EQ(c.num_samples, 0);
    EXPECT_FALSE(c.updated);
  }
  EXPECT_EQ(testing::DumpTable(p.db, "cameras"), before);
}

TEST(TwoViewEstimator, BadInputGivesClearErrorsAndLeavesTheDatabaseUnchanged) {
  const Project p = MakeProject("bad", 2, true);
  const std::string before = testing::DumpTable(p.db, "two_view_geometries");
  // A corrupt depth file names the file.
  { std::ofstream(p.depths + "/pair0_a.png.npy") << "not an npy file"; }
  try {
    RunTwoViewEstimatorImpl(Options(p));
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("pair0_a.png.npy"), std::string::npos) << e.what();
  }
  EXPECT_EQ(testing::DumpTable(p.db, "two_view_geometries"), before);
  // A missing database names the path.
  TwoViewEstimatorOptions o = Options(p);
  o.database_path = p.dir + "/missing.db";
  try {
    RunTwoViewEstimatorImpl(o);
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("missing.db"), std::string::npos) << e.what();
  }
  // An unsupported camera model (FOV, id 7) names the camera; nothing is written.
  const Project q = MakeProject("badcam", 1, true);
  testing::ExecSql(q.db, "UPDATE cameras SET model = 7, params = x'" + std::string(80, '0') + "' WHERE camera_id = 1");
  const std::string q_before = testing::DumpTable(q.db, "two_view_geometries");
  try {
    RunTwoViewEstimatorImpl(Options(q));
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("camera_id 1 (used by 'pair0_a.png', 'pair0_b.png')"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("FOV"), std::string::npos) << e.what();
  }
  EXPECT_EQ(testing::DumpTable(q.db, "two_view_geometries"), q_before);
}

}  // namespace
}  // namespace madsfm
