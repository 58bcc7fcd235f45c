#include "colmap_ext/shard/shard_file.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include "testing/colmap_database_builder.h"
#include "testing/error_of.h"
#include "testing/temp_dir.h"

namespace madsfm::colmap {
namespace {

namespace fs = std::filesystem;
using testing::ErrorOf;

// A path in this process's scratch folder (removed at exit).
std::string TempPath(const std::string& name) {
  static const testing::TempDir scratch("shard_file_test");
  const std::string p = scratch.Sub(name);
  fs::remove(p);
  fs::remove(p + ".tmp");
  return p;
}

ShardInfo SomeInfo() {
  ShardInfo i;
  i.database_path = "/data/db.db";
  i.database_fingerprint = "0123456789abcdef0123456789abcdef";
  i.options_fingerprint = "madsfm-1;mode=auto;seed=3";
  i.split_fingerprint = "fedcba9876543210fedcba9876543210";
  i.num_shards = 4;
  i.shard_index = 2;
  i.num_split_pairs = 123456789012LL;
  i.min_num_matches = 15;
  i.pair_list_path = "/data/pairs.txt";
  i.pair_list_fingerprint = "00ff";
  i.madsfm_version = "9.9.9";
  return i;
}

ShardResult SomeResult(pair_t pair_id, bool with_geometry, bool calibrated) {
  ShardResult r;
  if (with_geometry) {
    TwoViewGeometryRow g;
    g.pair_id = pair_id;
    g.inlier_matches = {{1, 2}, {3, 4}, {4294967295u, 0}};
    g.config = calibrated ? kCalibrated : kUncalibrated;
    g.F = Eigen::Matrix3d::Random();
    if (calibrated) g.E = Eigen::Matrix3d::Random();
    if (!calibrated) {  // estimated focal of image 2 only (COLMAP main's camera2 column)
      g.E = Eigen::Matrix3d::Random();
      Camera camera;
      camera.camera_id = static_cast<camera_t>(pair_id % 1000 + 1);
      camera.intrinsics.model_id = 2;
      camera.intrinsics.width = 640;
      camera.intrinsics.height = 480;
      camera.intrinsics.params = {611.25, 320, 240, -0.0125};
      g.camera2 = camera;
    }
    g.qvec = Eigen::Vector4d(0.5, 0.5, -0.5, 0.5);
    g.tvec = Eigen::Vector3d(1e-300, -0.0, 3.0);
    r.geometry = g;
  }
  r.madsfm.pair_id = pair_id;
  r.madsfm.R = Eigen::Matrix3d::Random();
  r.madsfm.t = Eigen::Vector3d::Random();
  r.madsfm.scale = 0.1 + pair_id % 7;
  r.madsfm.shift1 = -0.25;
  r.madsfm.shift2 = std::numeric_limits<double>::quiet_NaN();
  r.madsfm.focal1 = 1234.5;
  r.madsfm.focal2 = std::numeric_limits<double>::infinity();
  r.madsfm.camera_mode = 2;
  r.madsfm.method = 1;
  r.madsfm.num_inliers_reproj1 = 10;
  r.madsfm.num_inliers_reproj2 = 11;
  r.madsfm.num_inliers_sampson = 12;
  r.madsfm.num_inliers = 12;
  r.madsfm.score = 3.25;
  r.madsfm.status = with_geometry ? 0 : 1;
  r.madsfm.options_fingerprint = SomeInfo().options_fingerprint;
  r.madsfm.depth_observable = with_geometry ? 1 : 0;
  r.madsfm.sigma_scale = 0.03125;
  r.madsfm.sigma_shift1 = std::numeric_limits<double>::quiet_NaN();
  r.madsfm.sigma_shift2 = 0.5;
  r.madsfm.sigma_focal1 = 0.0078125;
  r.madsfm.sigma_focal2 = std::numeric_limits<double>::quiet_NaN();
  return r;
}

bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

void ExpectSameResult(const ShardResult& a, const ShardResult& b) {
  ASSERT_EQ(a.geometry.has_value(), b.geometry.has_value());
  if (a.geometry) {
    const TwoViewGeometryRow &x = *a.geometry, &y = *b.geometry;
    EXPECT_EQ(x.pair_id, y.pair_id);
    EXPECT_EQ(x.inlier_matches, y.inlier_matches);
    EXPECT_EQ(x.config, y.config);
    ASSERT_EQ(x.F.has_value(), y.F.has_value());
    ASSERT_EQ(x.E.has_value(), y.E.has_value());
    ASSERT_EQ(x.H.has_value(), y.H.has_value());
    if (x.F) {
      EXPECT_EQ(*x.F, *y.F);
    }
    if (x.E) {
      EXPECT_EQ(*x.E, *y.E);
    }
    if (x.H) {
      EXPECT_EQ(*x.H, *y.H);
    }
    ASSERT_EQ(x.qvec.has_value(), y.qvec.has_value());
    ASSERT_EQ(x.tvec.has_value(), y.tvec.has_value());
    if (x.qvec) {
      EXPECT_EQ(*x.qvec, *y.qvec);
    }
    if (x.tvec) {
      for (int i = 0; i < 3; ++i) EXPECT_TRUE(SameBits((*x.tvec)(i), (*y.tvec)(i)));
    }
    ASSERT_EQ(x.camera1.has_value(), y.camera1.has_value());
    ASSERT_EQ(x.camera2.has_value(), y.camera2.has_value());
    if (x.camera2) {
      EXPECT_EQ(x.camera2->camera_id, y.camera2->camera_id);
      EXPECT_EQ(x.camera2->intrinsics.model_id, y.camera2->intrinsics.model_id);
      EXPECT_EQ(x.camera2->intrinsics.width, y.camera2->intrinsics.width);
      EXPECT_EQ(x.camera2->intrinsics.height, y.camera2->intrinsics.height);
      EXPECT_EQ(x.camera2->intrinsics.params, y.camera2->intrinsics.params);
    }
  }
  const MadsfmPairRow &m = a.madsfm, &n = b.madsfm;
  EXPECT_EQ(m.pair_id, n.pair_id);
  EXPECT_EQ(m.R, n.R);
  EXPECT_EQ(m.t, n.t);
  for (auto [u, v] : {std::pair{m.scale, n.scale}, {m.shift1, n.shift1}, {m.shift2, n.shift2},
                      {m.focal1, n.focal1}, {m.focal2, n.focal2}, {m.score, n.score}, {m.sigma_scale, n.sigma_scale},
                      {m.sigma_shift1, n.sigma_shift1}, {m.sigma_shift2, n.sigma_shift2},
                      {m.sigma_focal1, n.sigma_focal1}, {m.sigma_focal2, n.sigma_focal2}}) {
    EXPECT_TRUE(SameBits(u, v)) << u << " vs " << v;
  }
  EXPECT_EQ(m.camera_mode, n.camera_mode);
  EXPECT_EQ(m.method, n.method);
  EXPECT_EQ(m.num_inliers_reproj1, n.num_inliers_reproj1);
  EXPECT_EQ(m.num_inliers_reproj2, n.num_inliers_reproj2);
  EXPECT_EQ(m.num_inliers_sampson, n.num_inliers_sampson);
  EXPECT_EQ(m.num_inliers, n.num_inliers);
  EXPECT_EQ(m.status, n.status);
  EXPECT_EQ(m.depth_observable, n.depth_observable);
  EXPECT_EQ(m.options_fingerprint, n.options_fingerprint);
}

TEST(ShardFile, InfoAssignedPairsAndResultsRoundTripBitExactly) {
  const std::string path = TempPath("roundtrip.sqlite");
  const std::vector<pair_t> assigned = {ImagePairToPairId(1, 2), ImagePairToPairId(1, 3), ImagePairToPairId(5, 9)};
  std::vector<ShardResult> written = {SomeResult(assigned[0], true, true), SomeResult(assigned[1], false, false),
                                      SomeResult(assigned[2], true, false)};
  {
    auto shard = ShardFile::Create(path, SomeInfo(), assigned);
    shard->Begin();
    for (const auto& r : written) shard->WriteResult(r);
    shard->Commit();
  }
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  const auto shard = ShardFile::Open(path, /*read_only=*/true);
  const ShardInfo &a = shard->info(), b = SomeInfo();
  EXPECT_EQ(a.database_path, b.database_path);
  EXPECT_EQ(a.database_fingerprint, b.database_fingerprint);
  EXPECT_EQ(a.options_fingerprint, b.options_fingerprint);
  EXPECT_EQ(a.split_fingerprint, b.split_fingerprint);
  EXPECT_EQ(a.num_shards, b.num_shards);
  EXPECT_EQ(a.shard_index, b.shard_index);
  EXPECT_EQ(a.num_split_pairs, b.num_split_pairs);
  EXPECT_EQ(a.min_num_matches, b.min_num_matches);
  EXPECT_EQ(a.pair_list_path, b.pair_list_path);
  EXPECT_EQ(a.pair_list_fingerprint, b.pair_list_fingerprint);
  EXPECT_EQ(a.madsfm_version, b.madsfm_version);
  EXPECT_EQ(shard->AssignedPairs(), assigned);
  EXPECT_EQ(shard->ResultPairs(), assigned);
  size_t k = 0;
  shard->ForEachResult([&](const ShardResult& r) {
    ASSERT_LT(k, written.size());
    ExpectSameResult(r, written[k++]);
  });
  EXPECT_EQ(k, written.size());
}

TEST(ShardFile, UncommittedBatchIsRolledBack) {
  const std::string path = TempPath("rollback.sqlite");
  {
    auto shard = ShardFile::Create(path, SomeInfo(), {ImagePairToPairId(1, 2), ImagePairToPairId(3, 4)});
    shard->Begin();
    shard->WriteResult(SomeResult(ImagePairToPairId(1, 2), true, true));
    shard->Commit();
    shard->Begin();
    shard->WriteResult(SomeResult(ImagePairToPairId(3, 4), true, true));
    // Destroyed without Commit(), as a killed task leaves it.
  }
  EXPECT_EQ(ShardFile::Open(path, true)->ResultPairs(), std::vector<pair_t>{ImagePairToPairId(1, 2)});
  EXPECT_EQ(testing::IntegrityCheck(path), "ok");
}

TEST(ShardFile, ReadOnlyOpenRecoversFromATaskKilledInsideABatch) {
  const std::string path = TempPath("killed.sqlite");
  const pair_t a = ImagePairToPairId(1, 2), b = ImagePairToPairId(3, 4);
  {
    auto shard = ShardFile::Create(path, SomeInfo(), {a, b});
    shard->Begin();
    shard->WriteResult(SomeResult(a, true, true));
    shard->Commit();
  }
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    auto shard = ShardFile::Open(path, false);
    shard->Begin();
    shard->WriteResult(SomeResult(b, true, true));
    ::raise(SIGKILL);  // dies inside the transaction: a hot journal stays behind
    _exit(1);
  }
  ASSERT_GT(pid, 0);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status));
  ASSERT_TRUE(fs::exists(path + "-journal") && fs::file_size(path + "-journal") > 0);
  // merge_shards opens read-only: the interrupted batch is rolled back, the committed one is there.
  EXPECT_EQ(ShardFile::Open(path, /*read_only=*/true)->ResultPairs(), std::vector<pair_t>{a});
  EXPECT_EQ(testing::IntegrityCheck(path), "ok");
}

TEST(ShardFile, WritingOutsideABatchIsAProgrammingError) {
  auto shard = ShardFile::Create(TempPath("nobatch.sqlite"), SomeInfo(), {});
  EXPECT_THROW(shard->WriteResult(SomeResult(ImagePairToPairId(1, 2), true, true)), std::logic_error);
}

TEST(ShardFile, RefusesToOverwriteAnExistingFile) {
  const std::string path = TempPath("exists.sqlite");
  ShardFile::Create(path, SomeInfo(), {ImagePairToPairId(1, 2)});
  const std::string e = ErrorOf([&] { ShardFile::Create(path, SomeInfo(), {}); });
  EXPECT_NE(e.find("'" + path + "' already exists"), std::string::npos) << e;
  EXPECT_EQ(ShardFile::Open(path, true)->AssignedPairs().size(), 1u);
}

TEST(ShardFile, OpenNamesTheFileWhenItIsNotAShard) {
  const std::string missing = TempPath("missing.sqlite");
  EXPECT_NE(ErrorOf([&] { ShardFile::Open(missing, true); }).find("'" + missing + "' does not exist"),
            std::string::npos);

  const std::string text = TempPath("text.sqlite");
  std::ofstream(text) << "not a database at all, just some text that is long enough to be a header....";
  const std::string e1 = ErrorOf([&] { ShardFile::Open(text, true); });
  EXPECT_NE(e1.find(text), std::string::npos) << e1;

  const std::string colmap_db = TempPath("colmap.db");
  testing::ColmapDatabaseBuilder builder(colmap_db);
  const std::string e2 = ErrorOf([&] { ShardFile::Open(colmap_db, true); });
  EXPECT_NE(e2.find("'" + colmap_db + "' is not a madsfm shard file"), std::string::npos) << e2;
}

TEST(ShardFile, OpenRejectsAnotherFormatAndBadInfo) {
  const std::string path = TempPath("format.sqlite");
  ShardFile::Create(path, SomeInfo(), {});
  testing::ExecSql(path, "UPDATE madsfm_shard_info SET value = 'madsfm-shard-99' WHERE key = 'format'");
  EXPECT_NE(ErrorOf([&] { ShardFile::Open(path, true); }).find("has format 'madsfm-shard-99'"), std::string::npos);

  const std::string index = TempPath("index.sqlite");
  ShardFile::Create(index, SomeInfo(), {});
  testing::ExecSql(index, "UPDATE madsfm_shard_info SET value = '7' WHERE key = 'shard_index'");
  EXPECT_NE(ErrorOf([&] { ShardFile::Open(index, true); }).find("shard_index 7 is not in [0, num_shards = 4)"),
            std::string::npos);

  const std::string missing_key = TempPath("key.sqlite");
  ShardFile::Create(missing_key, SomeInfo(), {});
  testing::ExecSql(missing_key, "DELETE FROM madsfm_shard_info WHERE key = 'options_fingerprint'");
  EXPECT_NE(ErrorOf([&] { ShardFile::Open(missing_key, true); }).find("lacks the info key 'options_fingerprint'"),
            std::string::npos);
}

// Shards written before the focal standard deviations were stored end after the depth sigmas, and those written
// before the depth observability end after the status: read as unknown (-1, NaN); a partial trailing section or an
// out-of-range flag is an error naming the file.
TEST(ShardFile, ResultsWithoutTheFocalSigmasReadAsUnknown) {
  const std::string path = TempPath("old_focal_blob.sqlite");
  const pair_t p = ImagePairToPairId(1, 2);
  {
    auto shard = ShardFile::Create(path, SomeInfo(), {p});
    shard->Begin();
    shard->WriteResult(SomeResult(p, true, true));
    shard->Commit();
  }
  testing::ExecSql(path, "UPDATE madsfm_shard_results SET madsfm = substr(madsfm, 1, length(madsfm) - 16)");
  int n = 0;
  ShardFile::Open(path, true)->ForEachResult([&](const ShardResult& r) {
    ++n;
    EXPECT_EQ(r.madsfm.depth_observable, 1);
    EXPECT_EQ(r.madsfm.sigma_scale, 0.03125);
    EXPECT_TRUE(std::isnan(r.madsfm.sigma_focal1));
    EXPECT_TRUE(std::isnan(r.madsfm.sigma_focal2));
  });
  EXPECT_EQ(n, 1);
  testing::ExecSql(path, "UPDATE madsfm_shard_results SET madsfm = madsfm || x'0000000000000000'");
  const std::string e = ErrorOf([&] { ShardFile::Open(path, true)->ForEachResult([](const ShardResult&) {}); });
  EXPECT_NE(e.find("shard file '" + path + "'"), std::string::npos) << e;
}

TEST(ShardFile, ResultsWithoutTheObservabilitySectionReadAsUnknown) {
  const std::string path = TempPath("old_blob.sqlite");
  const pair_t p = ImagePairToPairId(1, 2);
  {
    auto shard = ShardFile::Create(path, SomeInfo(), {p});
    shard->Begin();
    shard->WriteResult(SomeResult(p, true, true));
    shard->Commit();
  }
  testing::ExecSql(path, "UPDATE madsfm_shard_results SET madsfm = substr(madsfm, 1, length(madsfm) - 44)");
  int n = 0;
  ShardFile::Open(path, true)->ForEachResult([&](const ShardResult& r) {
    ++n;
    EXPECT_EQ(r.madsfm.depth_observable, -1);
    EXPECT_TRUE(std::isnan(r.madsfm.sigma_scale));
    EXPECT_EQ(r.madsfm.num_inliers, 12);
  });
  EXPECT_EQ(n, 1);
  testing::ExecSql(path, "UPDATE madsfm_shard_results SET madsfm = madsfm || x'07000000'");
  const std::string e = ErrorOf([&] { ShardFile::Open(path, true)->ForEachResult([](const ShardResult&) {}); });
  EXPECT_NE(e.find("shard file '" + path + "'"), std::string::npos) << e;
}

TEST(ShardFile, MalformedResultBlobsAreReportedWithFileAndPair) {
  const std::string path = TempPath("blob.sqlite");
  const pair_t p = ImagePairToPairId(1, 2);
  {
    auto shard = ShardFile::Create(path, SomeInfo(), {p});
    shard->Begin();
    shard->WriteResult(SomeResult(p, true, true));
    shard->Commit();
  }
  testing::ExecSql(path, "UPDATE madsfm_shard_results SET geometry = substr(geometry, 1, 30)");
  const std::string e1 = ErrorOf([&] { ShardFile::Open(path, true)->ForEachResult([](const ShardResult&) {}); });
  EXPECT_NE(e1.find("shard file '" + path + "', pair " + std::to_string(p) + " geometry: blob too short"),
            std::string::npos) << e1;
  testing::ExecSql(path, "UPDATE madsfm_shard_results SET geometry = NULL, madsfm = madsfm || x'00'");
  const std::string e2 = ErrorOf([&] { ShardFile::Open(path, true)->ForEachResult([](const ShardResult&) {}); });
  EXPECT_NE(e2.find("result: blob has 1 extra bytes"), std::string::npos) << e2;
  // A corrupt match count (2^40) is rejected before anything is allocated for it.
  testing::ExecSql(path, "UPDATE madsfm_shard_results SET madsfm = substr(madsfm, 1, length(madsfm) - 1), "
                         "geometry = x'02' || x'03000000' || x'0000000000010000'");
  const std::string e3 = ErrorOf([&] { ShardFile::Open(path, true)->ForEachResult([](const ShardResult&) {}); });
  EXPECT_NE(e3.find("pair " + std::to_string(p) + " geometry: blob too short for its 1099511627776 inlier matches"),
            std::string::npos) << e3;
}

}  // namespace
}  // namespace madsfm::colmap
