#include "colmap_ext/synthetic/pair_project.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "colmap_ext/database/database.h"
#include "madsfm/io/pair_directory.h"
#include "testing/temp_dir.h"

namespace madsfm::colmap {
namespace {

namespace fs = std::filesystem;

const std::string kPairs = MADSFM_EXAMPLE_PAIRS_DIR;

TEST(PairProject, WritesCamerasImagesKeypointsAndMatchesOfThePair) {
  const testing::TempDir scratch("pair_project_write");
  const std::string out = scratch.Sub("out");
  const PairProjectSummary s = WritePairProject(kPairs + "/2_2d3ds", out, /*known_focal=*/false);
  const PairData pair = ReadPairDirectory(kPairs + "/2_2d3ds");
  EXPECT_EQ(s.num_matches, static_cast<int>(pair.p0.size()));
  auto db = Database::Open(s.database_path, /*read_only=*/true);
  const auto cameras = db->ReadCameras();
  ASSERT_EQ(cameras.size(), 2u);
  EXPECT_FALSE(cameras[0].prior_focal_length);
  EXPECT_DOUBLE_EQ(cameras[0].intrinsics.FocalX(), 1.2 * std::max(pair.width0, pair.height0));
  const auto images = db->ReadImages();
  ASSERT_EQ(images.size(), 2u);
  const auto k1 = db->ReadKeypoints(images[0].image_id);
  ASSERT_EQ(k1.size(), pair.p0.size());
  EXPECT_NEAR(k1[5].x(), pair.p0[5].x() + 0.5, 1e-3);  // COLMAP's pixel centres at +0.5 (float32 storage)
  EXPECT_TRUE(fs::exists(out + "/depths/image0.png.npy"));
  EXPECT_TRUE(fs::exists(out + "/images/image1.png"));
  EXPECT_TRUE(fs::exists(out + "/ground_truth.json"));
}

TEST(PairProject, KnownFocalIsAPrior) {
  const testing::TempDir scratch("pair_project_known");
  const std::string out = scratch.Sub("out");
  const PairProjectSummary s = WritePairProject(kPairs + "/1_eth3d", out, /*known_focal=*/true);
  const PairData pair = ReadPairDirectory(kPairs + "/1_eth3d");
  auto db = Database::Open(s.database_path, true);
  const auto cameras = db->ReadCameras();
  ASSERT_EQ(cameras.size(), 2u);
  EXPECT_TRUE(cameras[0].prior_focal_length);
  EXPECT_NEAR(cameras[0].intrinsics.FocalX(), 0.5 * (pair.K0(0, 0) + pair.K0(1, 1)), 1e-9);
}

TEST(PairProject, RefusesAnExistingDatabaseAndPairsWithoutDepth) {
  const testing::TempDir scratch("pair_project_refuse");
  const std::string out = scratch.Sub("out");
  WritePairProject(kPairs + "/2_2d3ds", out, false);
  try {
    WritePairProject(kPairs + "/2_2d3ds", out, false);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("already exists"), std::string::npos) << e.what();
  }
  // 0_scannet names depth files it does not ship: the error names the file.
  EXPECT_THROW(WritePairProject(kPairs + "/0_scannet", scratch.Sub("no_depth"), false), std::runtime_error);
}

}  // namespace
}  // namespace madsfm::colmap
