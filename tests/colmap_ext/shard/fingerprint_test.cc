#include "colmap_ext/shard/fingerprint.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>

#include "colmap_ext/database/database.h"
#include "colmap_ext/pipeline/two_view_estimator.h"
#include "colmap_ext/synthetic/synthetic_project.h"
#include "testing/colmap_database_builder.h"
#include "testing/temp_dir.h"

namespace madsfm::colmap {
namespace {

namespace fs = std::filesystem;

std::string FingerprintOf(const std::string& path) { return DatabaseFingerprint(*Database::Open(path, true)); }

TEST(Fingerprinter, DeterministicHexAndSensitiveToContentAndSplitting) {
  Fingerprinter a, b, c;
  a.Add(std::string("ab"));
  a.Add(std::string("c"));
  b.Add(std::string("a"));
  b.Add(std::string("bc"));
  c.Add(std::string("ab"));
  c.Add(std::string("c"));
  EXPECT_EQ(a.Hex(), c.Hex());
  EXPECT_NE(a.Hex(), b.Hex());
  EXPECT_EQ(a.Hex().size(), 32u);
  EXPECT_EQ(a.Hex().find_first_not_of("0123456789abcdef"), std::string::npos);
  Fingerprinter x, y;
  x.Add(int64_t{1});
  y.Add(int64_t{2});
  EXPECT_NE(x.Hex(), y.Hex());
  EXPECT_NE(Fingerprinter().Hex(), x.Hex());
}

class DatabaseFingerprintTest : public ::testing::Test {
 protected:
  void SetUp() override {
    scratch_ = std::make_unique<testing::TempDir>("fingerprint_test");
    dir_ = scratch_->Sub("project");
    SyntheticProjectOptions o;
    o.output_path = dir_;
    o.num_pairs = 3;
    o.min_num_matches = 40;
    o.max_num_matches = 60;
    project_ = WriteSyntheticProject(o);
    copy_ = dir_ + "/copy.db";
    fs::copy_file(project_.database_path, copy_);
    base_ = FingerprintOf(project_.database_path);
  }
  std::unique_ptr<testing::TempDir> scratch_;
  std::string dir_, copy_, base_;
  SyntheticProject project_;
};

TEST_F(DatabaseFingerprintTest, CopiesAgreeAndEstimationResultsDoNotCount) {
  EXPECT_EQ(FingerprintOf(copy_), base_);
  // What two_view_estimator (and so merge_shards) writes is not part of the fingerprint.
  TwoViewEstimatorOptions o;
  o.database_path = copy_;
  o.depth_path = project_.depth_path;
  o.progress = false;
  o.num_threads = 1;
  ASSERT_EQ(RunTwoViewEstimatorImpl(o).num_estimated, 3);
  EXPECT_EQ(FingerprintOf(copy_), base_);
}

TEST_F(DatabaseFingerprintTest, ChangesWhenWhatTheEstimatorReadsChanges) {
  testing::ExecSql(copy_, "UPDATE images SET name = 'other.png' WHERE image_id = 2");
  EXPECT_NE(FingerprintOf(copy_), base_);
  fs::copy_file(project_.database_path, copy_, fs::copy_options::overwrite_existing);
  testing::ExecSql(copy_, "UPDATE cameras SET width = width + 1 WHERE camera_id = 1");
  EXPECT_NE(FingerprintOf(copy_), base_);
  fs::copy_file(project_.database_path, copy_, fs::copy_options::overwrite_existing);
  testing::ExecSql(copy_, "DELETE FROM matches WHERE pair_id = (SELECT MIN(pair_id) FROM matches)");
  EXPECT_NE(FingerprintOf(copy_), base_);
  fs::copy_file(project_.database_path, copy_, fs::copy_options::overwrite_existing);
  testing::ExecSql(copy_, "UPDATE keypoints SET rows = rows - 1, data = substr(data, 1, length(data) - 24) "
                          "WHERE image_id = 1");
  EXPECT_NE(FingerprintOf(copy_), base_);
}

}  // namespace
}  // namespace madsfm::colmap
