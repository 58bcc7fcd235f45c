#include "madsfm/io/pair_directory.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>

#include "madsfm/io/depth_map_io.h"
#include "madsfm/io/depth_sampling.h"
#include "madsfm/io/io_test_util.h"
#include "madsfm/io/npy.h"

namespace madsfm {
namespace {

namespace fs = std::filesystem;
using io_test::Contains;
using io_test::ErrorOf;
using io_test::TempDir;
using io_test::WriteFile;

std::string ExamplePair(const std::string& name) { return (fs::path(MADSFM_EXAMPLE_PAIRS_DIR) / name).string(); }

// Fraction of matches with a valid sampled depth, and whether all matches lie inside the image.
void CheckMatchesAgainstDepth(const PairData& pair, const std::string& label) {
  const std::vector<double> d0 = SampleDepths(*pair.depth0, pair.p0, pair.width0, pair.height0);
  const std::vector<double> d1 = SampleDepths(*pair.depth1, pair.p1, pair.width1, pair.height1);
  int valid = 0;
  for (size_t i = 0; i < d0.size(); ++i) valid += std::isfinite(d0[i]) && std::isfinite(d1[i]);
  const double rate = static_cast<double>(valid) / d0.size();
  std::printf("%s: %zu matches, %.1f%% with valid depth in both views\n", label.c_str(), d0.size(), 100 * rate);
  EXPECT_GE(rate, 0.9) << label;
}

void ExpectInsideImage(const std::vector<Eigen::Vector2d>& points, int width, int height) {
  for (const Eigen::Vector2d& p : points) {
    EXPECT_TRUE(p.x() >= -0.5 && p.x() <= width - 0.5 && p.y() >= -0.5 && p.y() <= height - 0.5) << p.transpose();
  }
}

TEST(PairDirectory, ReadsEth3dExample) {
  const PairData pair = ReadPairDirectory(ExamplePair("1_eth3d"));
  EXPECT_EQ(pair.path, ExamplePair("1_eth3d"));
  EXPECT_EQ(pair.p0.size(), 193u);
  EXPECT_EQ(pair.p1.size(), 193u);
  EXPECT_DOUBLE_EQ(pair.K0(0, 0), 396.4448592115849);
  EXPECT_DOUBLE_EQ(pair.K0(1, 2), 239.57173860622137);
  EXPECT_DOUBLE_EQ(pair.K1(0, 2), 361.21409493161707);
  EXPECT_EQ(pair.K1(2, 2), 1.0);
  ASSERT_TRUE(pair.T_0to1.has_value());
  EXPECT_DOUBLE_EQ((*pair.T_0to1)(0, 3), -0.5263649225234985);
  EXPECT_DOUBLE_EQ((*pair.T_0to1)(2, 0), -0.9997609853744507);
  EXPECT_TRUE(pair.T_0to1->row(3) == Eigen::RowVector4d(0, 0, 0, 1));
  // From the PNG headers.
  EXPECT_EQ(pair.width0, 720);
  EXPECT_EQ(pair.height0, 480);
  EXPECT_EQ(pair.width1, 720);
  EXPECT_EQ(pair.height1, 480);
  ASSERT_TRUE(pair.HasDepth());
  EXPECT_EQ(pair.depth0->width, 720);
  EXPECT_EQ(pair.depth0->height, 480);
  EXPECT_EQ(pair.depth1->width, 720);
  EXPECT_EQ(pair.depth1->height, 480);
  EXPECT_TRUE(pair.warnings.empty());
  // Match values agree with a direct read of the .npy file.
  const NpyArray m1 = ReadNpy(ExamplePair("1_eth3d/lightglue_matches_1.npy"));
  EXPECT_EQ(pair.p1[17].x(), m1.data[34]);
  EXPECT_EQ(pair.p1[17].y(), m1.data[35]);
  ExpectInsideImage(pair.p0, pair.width0, pair.height0);
  ExpectInsideImage(pair.p1, pair.width1, pair.height1);
  CheckMatchesAgainstDepth(pair, "1_eth3d");
}

TEST(PairDirectory, Reads2d3dsExampleWithDifferentImageSizes) {
  const PairData pair = ReadPairDirectory(ExamplePair("2_2d3ds"));
  EXPECT_EQ(pair.p0.size(), 782u);
  EXPECT_EQ(pair.p1.size(), 782u);
  EXPECT_DOUBLE_EQ(pair.K0(0, 0), 618.9608364510034);
  EXPECT_DOUBLE_EQ(pair.K1(0, 0), 374.9066957111852);
  EXPECT_DOUBLE_EQ(pair.K1(0, 2), 479.5);
  ASSERT_TRUE(pair.T_0to1.has_value());
  EXPECT_DOUBLE_EQ((*pair.T_0to1)(1, 3), 0.8798591436334231);
  EXPECT_EQ(pair.width0, 1080);
  EXPECT_EQ(pair.height0, 540);
  EXPECT_EQ(pair.width1, 960);
  EXPECT_EQ(pair.height1, 540);
  ASSERT_TRUE(pair.HasDepth());
  EXPECT_EQ(pair.depth0->width, 1080);
  EXPECT_EQ(pair.depth0->height, 540);
  EXPECT_EQ(pair.depth1->width, 960);
  EXPECT_EQ(pair.depth1->height, 540);
  ExpectInsideImage(pair.p0, pair.width0, pair.height0);
  ExpectInsideImage(pair.p1, pair.width1, pair.height1);
  CheckMatchesAgainstDepth(pair, "2_2d3ds");
}

TEST(PairDirectory, ScannetExampleHasMissingDepthFiles) {
  const std::string dir = ExamplePair("0_scannet");
  // By default a depth file named in info.json but absent is an error naming the file.
  const std::string message = ErrorOf([&] { ReadPairDirectory(dir); });
  EXPECT_TRUE(Contains(message, "depth file '" + (fs::path(dir) / "marigold_depth_0.npy").string() + "'")) << message;
  EXPECT_TRUE(Contains(message, "does not exist")) << message;

  PairReadOptions options;
  options.allow_missing_depth = true;
  const PairData pair = ReadPairDirectory(dir, options);
  EXPECT_FALSE(pair.depth0.has_value());
  EXPECT_FALSE(pair.depth1.has_value());
  EXPECT_FALSE(pair.HasDepth());
  ASSERT_EQ(pair.warnings.size(), 2u);
  EXPECT_TRUE(Contains(pair.warnings[0], "marigold_depth_0.npy")) << pair.warnings[0];
  EXPECT_TRUE(Contains(pair.warnings[1], "marigold_depth_1.npy")) << pair.warnings[1];
  EXPECT_EQ(pair.p0.size(), 55u);
  EXPECT_EQ(pair.p1.size(), 55u);
  EXPECT_DOUBLE_EQ(pair.K0(1, 1), 576.0595041322314);
  ASSERT_TRUE(pair.T_0to1.has_value());
  EXPECT_DOUBLE_EQ((*pair.T_0to1)(2, 3), -0.05305);
  EXPECT_EQ(pair.width0, 640);
  EXPECT_EQ(pair.height0, 480);
  EXPECT_EQ(pair.width1, 640);
  EXPECT_EQ(pair.height1, 480);
  ExpectInsideImage(pair.p0, pair.width0, pair.height0);
}

PairData MakePair(bool with_depth, bool with_pose) {
  PairData pair;
  pair.K0 << 500, 0, 320, 0, 510, 240, 0, 0, 1;
  pair.K1 << 600, 0, 330.25, 0, 600, 250.125, 0, 0, 1;
  if (with_pose) {
    Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
    T.topLeftCorner<3, 3>() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    T.topRightCorner<3, 1>() = Eigen::Vector3d(0.1, -0.2, 0.3);
    pair.T_0to1 = T;
  }
  for (int i = 0; i < 20; ++i) {
    pair.p0.emplace_back(10.125 + 7 * i, 20.5 + 3 * i);
    pair.p1.emplace_back(1.0 / 3.0 + 5 * i, 100.0 - 0.1 * i);
  }
  pair.width0 = 640;
  pair.height0 = 480;
  pair.width1 = 660;
  pair.height1 = 500;
  if (with_depth) {
    DepthMap d0;
    d0.width = 320;
    d0.height = 240;
    d0.data.assign(320 * 240, 2.5f);
    DepthMap d1;
    d1.width = 66;
    d1.height = 50;
    d1.data.assign(66 * 50, 4.0f);
    d1.data[7] = std::nanf("");
    pair.depth0 = d0;
    pair.depth1 = d1;
  }
  return pair;
}

void ExpectSamePair(const PairData& a, const PairData& b) {
  EXPECT_EQ(a.K0, b.K0);
  EXPECT_EQ(a.K1, b.K1);
  ASSERT_EQ(a.T_0to1.has_value(), b.T_0to1.has_value());
  if (a.T_0to1) {
    EXPECT_EQ(*a.T_0to1, *b.T_0to1);
  }
  EXPECT_EQ(a.p0, b.p0);
  EXPECT_EQ(a.p1, b.p1);
  EXPECT_EQ(a.width0, b.width0);
  EXPECT_EQ(a.height0, b.height0);
  EXPECT_EQ(a.width1, b.width1);
  EXPECT_EQ(a.height1, b.height1);
  ASSERT_EQ(a.depth0.has_value(), b.depth0.has_value());
  ASSERT_EQ(a.depth1.has_value(), b.depth1.has_value());
  if (a.depth0) {
    EXPECT_EQ(a.depth0->width, b.depth0->width);
    EXPECT_EQ(a.depth0->data, b.depth0->data);
    EXPECT_EQ(a.depth1->height, b.depth1->height);
    EXPECT_TRUE(std::isnan(b.depth1->data[7]));
    EXPECT_EQ(a.depth1->data[8], b.depth1->data[8]);
  }
}

TEST(PairDirectory, WriteThenReadRoundTrip) {
  TempDir tmp;
  for (const bool with_depth : {true, false}) {
    for (const bool with_pose : {true, false}) {
      const PairData pair = MakePair(with_depth, with_pose);
      const std::string dir = tmp.File("pair_" + std::to_string(with_depth) + std::to_string(with_pose));
      WritePairDirectory(pair, dir);
      const PairData back = ReadPairDirectory(dir);
      EXPECT_EQ(back.path, dir);
      ExpectSamePair(pair, back);
      EXPECT_TRUE(back.warnings.empty());
    }
  }
  // Other depth formats and custom names.
  PairFileNames names;
  names.depth0 = "sub/d0.pfm";
  names.depth1 = "d1.jpg.geometric.bin";
  names.matches0 = "kp0.npy";
  const PairData pair = MakePair(true, true);
  WritePairDirectory(pair, tmp.File("custom"), names);
  EXPECT_TRUE(fs::exists(tmp.File("custom/kp0.npy")));
  ExpectSamePair(pair, ReadPairDirectory(tmp.File("custom")));
}

// True depth maps (gt_depth_*_file, written by `madsfm synth` for bench's depth errors) round-trip, and one of the
// wrong aspect ratio is an error naming its file.
TEST(PairDirectory, TrueDepthMapsRoundTripAndAreChecked) {
  TempDir tmp;
  PairData pair = MakePair(true, true);
  DepthMap z;
  z.width = 160;
  z.height = 120;
  z.data.assign(160 * 120, 3.25f);
  z.data[5] = 0.0f;  // no surface (sky)
  DepthMap z1;  // view 1 is 660 x 500
  z1.width = 66;
  z1.height = 50;
  z1.data.assign(66 * 50, 7.5f);
  pair.gt_depth0 = z;
  pair.gt_depth1 = z1;
  const std::string dir = tmp.File("gt");
  WritePairDirectory(pair, dir);
  const PairData back = ReadPairDirectory(dir);
  ASSERT_TRUE(back.gt_depth0.has_value() && back.gt_depth1.has_value());
  EXPECT_EQ(back.gt_depth0->width, 160);
  EXPECT_EQ(back.gt_depth0->data, z.data);
  EXPECT_EQ(back.gt_depth1->data, z1.data);
  EXPECT_FALSE(MakePair(true, true).gt_depth0.has_value());  // optional: absent unless named in info.json
  DepthMap wrong;
  wrong.width = 100;
  wrong.height = 20;
  wrong.data.assign(100 * 20, 1.0f);
  pair.gt_depth1 = wrong;
  WritePairDirectory(pair, tmp.File("gt_wrong"));
  const std::string error = ErrorOf([&] { ReadPairDirectory(tmp.File("gt_wrong")); });
  EXPECT_NE(error.find("gt_depth_1.npy"), std::string::npos) << error;
}

// Rewrites info.json of a valid pair directory with `edit` applied and returns the read error.
template <typename Edit>
std::string ErrorAfterEdit(const std::string& dir, Edit edit) {
  WritePairDirectory(MakePair(true, true), dir);
  const std::string info_path = (fs::path(dir) / "info.json").string();
  nlohmann::json info = nlohmann::json::parse(io_test::ReadFile(info_path));
  edit(info, dir);
  WriteFile(info_path, info.dump());
  return ErrorOf([&] { ReadPairDirectory(dir); });
}

TEST(PairDirectory, MalformedPairsThrowNamingTheFile) {
  TempDir tmp;
  using nlohmann::json;
  const std::string dir = tmp.File("p");
  const std::string info = (fs::path(dir) / "info.json").string();
  struct Case {
    std::string label;
    std::function<void(json&, const std::string&)> edit;
    std::string file, fragment;
  };
  const std::vector<Case> cases = {
      {"no K0", [](json& j, const std::string&) { j.erase("K0"); }, info, "missing key 'K0'"},
      {"K1 2x3", [](json& j, const std::string&) { j["K1"] = {{1, 0, 0}, {0, 1, 0}}; }, info, "'K1' must be a 3x3"},
      {"K0 text", [](json& j, const std::string&) { j["K0"][0][0] = "f"; }, info, "'K0' must hold numbers"},
      {"K0 zero focal", [](json& j, const std::string&) { j["K0"][0][0] = 0; }, info, "positive focal"},
      {"K0 last row", [](json& j, const std::string&) { j["K0"][2][2] = 2; }, info, "last row (0, 0, 1)"},
      {"T scaled", [](json& j, const std::string&) { j["T_0to1"][0][0] = 2.0; }, info, "not a rigid transform"},
      {"T 3x3", [](json& j, const std::string&) { j["T_0to1"] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}; }, info,
       "'T_0to1' must be a 4x4"},
      {"no matches key", [](json& j, const std::string&) { j.erase("matches_1_file"); }, info,
       "missing key 'matches_1_file'"},
      {"missing matches file", [](json& j, const std::string&) { j["matches_0_file"] = "nope.npy"; },
       (fs::path(dir) / "nope.npy").string(), "file does not exist"},
      {"matches N x 3",
       [](json& j, const std::string& d) {
         const std::vector<double> v(30, 1.0);
         WriteNpy((fs::path(d) / "m3.npy").string(), {10, 3}, v.data());
         j["matches_0_file"] = "m3.npy";
       },
       (fs::path(dir) / "m3.npy").string(), "expected an N x 2 array, got shape (10, 3)"},
      {"matches different N",
       [](json& j, const std::string& d) {
         const std::vector<double> v(20, 1.0);
         WriteNpy((fs::path(d) / "m10.npy").string(), {10, 2}, v.data());
         j["matches_1_file"] = "m10.npy";
       },
       (fs::path(dir) / "m10.npy").string(), "has 10 rows but"},
      {"non-finite match",
       [](json& j, const std::string& d) {
         std::vector<double> v(40, 1.0);
         v[13] = std::nan("");
         WriteNpy((fs::path(d) / "mnan.npy").string(), {20, 2}, v.data());
         j["matches_0_file"] = "mnan.npy";
       },
       (fs::path(dir) / "mnan.npy").string(), "row 6 is not finite"},
      {"depth aspect", [](json& j, const std::string&) { j["image_size_0"] = {640, 640}; },
       (fs::path(dir) / "depth_0.npy").string(), "differ by more than 1%"},
      {"bad image size", [](json& j, const std::string&) { j["image_size_1"] = {640.5, 480}; }, info,
       "'image_size_1' must be [width, height]"},
      {"huge image size", [](json& j, const std::string&) { j["image_size_0"] = {8.11111e95, 480}; }, info,
       "'image_size_0' must be [width, height]"},
      {"depth not a string", [](json& j, const std::string&) { j["depth_0_file"] = 3; }, info,
       "'depth_0_file' must be a non-empty file name"},
      {"corrupt depth",
       [](json&, const std::string& d) { WriteFile((fs::path(d) / "depth_1.npy").string(), "garbage"); },
       (fs::path(dir) / "depth_1.npy").string(), "not a .npy file"},
      {"bad png",
       [](json& j, const std::string& d) {
         j.erase("image_size_0");
         WriteFile((fs::path(d) / "image0.png").string(), "GIF89a not a png at all..");
       },
       (fs::path(dir) / "image0.png").string(), "not a PNG file"},
  };
  for (const Case& c : cases) {
    fs::remove_all(dir);
    const std::string message = ErrorAfterEdit(dir, c.edit);
    EXPECT_TRUE(Contains(message, "'" + c.file + "': ")) << c.label << ": " << message;
    EXPECT_TRUE(Contains(message, c.fragment)) << c.label << ": " << message;
  }
  // Invalid JSON, missing info.json, missing directory.
  fs::remove_all(dir);
  WritePairDirectory(MakePair(false, false), dir);
  WriteFile(info, "{\"K0\": [1, 2,");
  std::string message = ErrorOf([&] { ReadPairDirectory(dir); });
  EXPECT_TRUE(Contains(message, "pair file '" + info + "': invalid JSON")) << message;
  fs::remove(info);
  message = ErrorOf([&] { ReadPairDirectory(dir); });
  EXPECT_TRUE(Contains(message, "pair directory '" + dir + "': no info.json")) << message;
  message = ErrorOf([&] { ReadPairDirectory(tmp.File("nowhere")); });
  EXPECT_TRUE(Contains(message, "pair directory '" + tmp.File("nowhere") + "': does not exist")) << message;
}

TEST(PairDirectory, ImageSizeFallbacks) {
  TempDir tmp;
  // No image_size keys and no PNG: the depth map's size.
  PairData pair = MakePair(true, false);
  pair.width0 = pair.height0 = pair.width1 = pair.height1 = 0;
  WritePairDirectory(pair, tmp.File("a"));
  PairData back = ReadPairDirectory(tmp.File("a"));
  EXPECT_EQ(back.width0, 320);
  EXPECT_EQ(back.height0, 240);
  EXPECT_EQ(back.width1, 66);
  EXPECT_EQ(back.height1, 50);
  // A PNG header takes precedence over the depth map (only its first 24 bytes are read).
  std::string png = std::string("\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR", 16);
  png += std::string("\0\0\x02\x80\0\0\x01\xe0", 8);  // 640 x 480, big-endian
  WriteFile(tmp.File("a/image0.png"), png);
  back = ReadPairDirectory(tmp.File("a"));
  EXPECT_EQ(back.width0, 640);
  EXPECT_EQ(back.height0, 480);
  // No keys, no PNG, no depth: an error naming the directory.
  pair = MakePair(false, false);
  pair.width1 = 0;
  WritePairDirectory(pair, tmp.File("b"));
  const std::string message = ErrorOf([&] { ReadPairDirectory(tmp.File("b")); });
  EXPECT_TRUE(Contains(message, "pair directory '" + tmp.File("b") + "': cannot determine the size of image 1"))
      << message;
}

TEST(PairDirectory, PairLists) {
  // The examples directory is a directory of pair directories, sorted.
  const std::vector<std::string> examples = ReadPairList(MADSFM_EXAMPLE_PAIRS_DIR);
  ASSERT_EQ(examples.size(), 3u);
  EXPECT_EQ(fs::path(examples[0]).filename(), "0_scannet");
  EXPECT_EQ(fs::path(examples[1]).filename(), "1_eth3d");
  EXPECT_EQ(fs::path(examples[2]).filename(), "2_2d3ds");
  // A pair directory is a list of itself.
  EXPECT_EQ(ReadPairList(ExamplePair("1_eth3d")), std::vector<std::string>{ExamplePair("1_eth3d")});

  TempDir tmp;
  WritePairDirectory(MakePair(false, false), tmp.File("pairs/x"));
  WritePairDirectory(MakePair(false, false), tmp.File("pairs/y"));
  fs::create_directories(tmp.File("pairs/not_a_pair"));
  WriteFile(tmp.File("lists/list.txt"), "# my pairs\n\n  ../pairs/y  \n../pairs/x\r\n   # indented comment\n" +
                                            ExamplePair("2_2d3ds") + "\n");
  const std::vector<std::string> listed = ReadPairList(tmp.File("lists/list.txt"));
  ASSERT_EQ(listed.size(), 3u);
  EXPECT_EQ(fs::path(listed[0]), fs::path(tmp.File("pairs/y")));
  EXPECT_EQ(fs::path(listed[1]), fs::path(tmp.File("pairs/x")));
  EXPECT_EQ(fs::path(listed[2]), fs::path(ExamplePair("2_2d3ds")).lexically_normal());
  // Directory of pairs: sorted, non-pair subdirectories skipped.
  const std::vector<std::string> in_dir = ReadPairList(tmp.File("pairs"));
  ASSERT_EQ(in_dir.size(), 2u);
  EXPECT_EQ(fs::path(in_dir[0]).filename(), "x");

  WriteFile(tmp.File("lists/bad.txt"), "../pairs/x\n../pairs/not_a_pair\n");
  std::string message = ErrorOf([&] { ReadPairList(tmp.File("lists/bad.txt")); });
  EXPECT_TRUE(Contains(message, "pair list '" + tmp.File("lists/bad.txt") + "': line 2:")) << message;
  message = ErrorOf([&] { ReadPairList(tmp.File("missing.txt")); });
  EXPECT_TRUE(Contains(message, "pair list '" + tmp.File("missing.txt") + "': does not exist")) << message;
  message = ErrorOf([&] { ReadPairList(tmp.File("pairs/not_a_pair")); });
  EXPECT_TRUE(Contains(message, "neither a pair directory")) << message;
}

}  // namespace
}  // namespace madsfm
