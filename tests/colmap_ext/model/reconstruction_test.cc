// Tests of the COLMAP sparse-model reader/writer: exact binary layout, binary and text round trips, the real
// `colmap` 3.8 binary reading what we write (and us reading what it writes), corrupt / truncated files, and
// the quaternion helpers.
#include "colmap_ext/model/reconstruction.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "testing/temp_dir.h"

namespace madsfm::colmap {
namespace {

namespace fs = std::filesystem;

// A scratch folder per test, removed afterwards.
class TempDir : public testing::TempDir {
 public:
  TempDir() : testing::TempDir("reconstruction_test") {}
};

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void WriteFile(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

template <typename T>
std::string Bytes(T value) {
  std::string s(sizeof(T), '\0');
  std::memcpy(s.data(), &value, sizeof(T));
  return s;
}

bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

Eigen::Matrix3d RandomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
  q.normalize();
  return q.toRotationMatrix();
}

// A consistent random model: several camera models, images with all their keypoints, 3-D points whose tracks
// and the images' point3D_ids agree. Ids are sparse, one 3-D point id is above 2^32.
Reconstruction RandomModel(uint64_t seed, int num_images = 5, int num_points = 40) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  Reconstruction model;
  const int kModels[] = {0, 1, 2, 4};
  for (int c = 0; c < 4; ++c) {
    ModelCamera camera;
    camera.camera_id = static_cast<uint32_t>(1 + 2 * c);
    camera.intrinsics.model_id = kModels[c];
    camera.intrinsics.width = 640 + 32 * c;
    camera.intrinsics.height = 480 + 16 * c;
    const int n = CameraModelNumParams(kModels[c]);
    for (int k = 0; k < n; ++k) camera.intrinsics.params.push_back(k < 2 ? 500.0 + 100.0 * uni(rng) : 0.1 * uni(rng));
    model.cameras[camera.camera_id] = camera;
  }
  std::vector<uint32_t> image_ids;
  for (int i = 0; i < num_images; ++i) {
    ModelImage image;
    image.image_id = static_cast<uint32_t>(3 + 5 * i);
    image.qvec = RotationToQuaternion(RandomRotation(rng));
    image.tvec = Eigen::Vector3d(uni(rng), uni(rng), uni(rng)) * 3.0;
    image.camera_id = static_cast<uint32_t>(1 + 2 * (i % 4));
    char name[64];
    std::snprintf(name, sizeof(name), "dir/img_%03d.png", i);
    image.name = name;
    const int num_keypoints = i == 1 ? 0 : 30 + 7 * i;  // one image without keypoints
    for (int k = 0; k < num_keypoints; ++k) {
      image.points2D.emplace_back(320.0 + 300.0 * uni(rng), 240.0 + 200.0 * uni(rng));
      image.point3D_ids.push_back(kInvalidPoint3DId);
    }
    image_ids.push_back(image.image_id);
    model.images[image.image_id] = image;
  }
  for (int p = 0; p < num_points; ++p) {
    const uint64_t id = p == 0 ? (uint64_t{1} << 33) + 7 : static_cast<uint64_t>(10 + 3 * p);
    ModelPoint3D point;
    point.xyz = Eigen::Vector3d(uni(rng), uni(rng), uni(rng)) * 10.0;
    for (uint8_t& channel : point.rgb) channel = static_cast<uint8_t>(rng() % 256);
    point.error = 0.5 + 0.5 * uni(rng);
    for (const uint32_t image_id : image_ids) {
      ModelImage& image = model.images[image_id];
      if (image.points2D.empty() || rng() % 3 == 0) continue;
      const uint32_t idx = static_cast<uint32_t>(rng() % image.points2D.size());
      if (image.point3D_ids[idx] != kInvalidPoint3DId) continue;
      image.point3D_ids[idx] = id;
      point.track.emplace_back(image_id, idx);
    }
    if (!point.track.empty()) model.points3D[id] = point;
  }
  return model;
}

// Field-by-field equality, doubles bit for bit; quaternions to `qvec_tol` if given (COLMAP re-normalises them).
void ExpectModelsEqual(const Reconstruction& a, const Reconstruction& b, double qvec_tol = -1.0) {
  auto same = [](double x, double y) { return SameBits(x, y); };
  auto same_q = [&](double x, double y) { return qvec_tol < 0 ? SameBits(x, y) : std::abs(x - y) <= qvec_tol; };
  ASSERT_EQ(a.cameras.size(), b.cameras.size());
  for (const auto& [id, ca] : a.cameras) {
    ASSERT_EQ(b.cameras.count(id), 1u) << "camera " << id;
    const ModelCamera& cb = b.cameras.at(id);
    EXPECT_EQ(ca.camera_id, cb.camera_id);
    EXPECT_EQ(ca.intrinsics.model_id, cb.intrinsics.model_id);
    EXPECT_EQ(ca.intrinsics.width, cb.intrinsics.width);
    EXPECT_EQ(ca.intrinsics.height, cb.intrinsics.height);
    ASSERT_EQ(ca.intrinsics.params.size(), cb.intrinsics.params.size());
    for (size_t k = 0; k < ca.intrinsics.params.size(); ++k) {
      EXPECT_TRUE(same(ca.intrinsics.params[k], cb.intrinsics.params[k])) << "camera " << id << " param " << k;
    }
  }
  ASSERT_EQ(a.images.size(), b.images.size());
  for (const auto& [id, ia] : a.images) {
    ASSERT_EQ(b.images.count(id), 1u) << "image " << id;
    const ModelImage& ib = b.images.at(id);
    EXPECT_EQ(ia.image_id, ib.image_id);
    EXPECT_EQ(ia.camera_id, ib.camera_id);
    EXPECT_EQ(ia.name, ib.name);
    for (int k = 0; k < 4; ++k) EXPECT_TRUE(same_q(ia.qvec(k), ib.qvec(k))) << "image " << id << " qvec " << k;
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(same(ia.tvec(k), ib.tvec(k))) << "image " << id << " tvec " << k;
    ASSERT_EQ(ia.points2D.size(), ib.points2D.size());
    ASSERT_EQ(ia.point3D_ids.size(), ib.point3D_ids.size());
    for (size_t k = 0; k < ia.points2D.size(); ++k) {
      EXPECT_TRUE(same(ia.points2D[k].x(), ib.points2D[k].x()) && same(ia.points2D[k].y(), ib.points2D[k].y()))
          << "image " << id << " point2D " << k;
      EXPECT_EQ(ia.point3D_ids[k], ib.point3D_ids[k]) << "image " << id << " point2D " << k;
    }
  }
  ASSERT_EQ(a.points3D.size(), b.points3D.size());
  for (const auto& [id, pa] : a.points3D) {
    ASSERT_EQ(b.points3D.count(id), 1u) << "point " << id;
    const ModelPoint3D& pb = b.points3D.at(id);
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(same(pa.xyz(k), pb.xyz(k))) << "point " << id;
    EXPECT_EQ(pa.rgb, pb.rgb);
    EXPECT_TRUE(same(pa.error, pb.error)) << "point " << id;
    EXPECT_EQ(pa.track, pb.track) << "point " << id;
  }
}

// Expects `fn` to throw std::runtime_error whose message contains `needle`; returns the message.
template <typename Fn>
std::string ExpectThrowsMentioning(Fn fn, const std::string& needle) {
  try {
    fn();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << "message: " << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no std::runtime_error thrown (expected one mentioning '" << needle << "')";
  return "";
}

// The header lines, then the records (groups of `lines_per_record` lines) sorted.
std::vector<std::string> SplitRecords(const std::string& text, int header_lines, int lines_per_record) {
  std::vector<std::string> lines;
  size_t start = 0;
  while (start < text.size()) {
    const size_t end = text.find('\n', start);
    lines.push_back(text.substr(start, end == std::string::npos ? std::string::npos : end - start));
    if (end == std::string::npos) break;
    start = end + 1;
  }
  std::vector<std::string> header(lines.begin(), lines.begin() + std::min<size_t>(header_lines, lines.size()));
  std::vector<std::string> records;
  for (size_t i = header.size(); i < lines.size(); i += lines_per_record) {
    std::string record;
    for (int k = 0; k < lines_per_record && i + k < lines.size(); ++k) record += lines[i + k] + "\n";
    records.push_back(record);
  }
  std::sort(records.begin(), records.end());
  header.insert(header.end(), records.begin(), records.end());
  return header;
}

int RunShell(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

bool HaveColmap() { return RunShell("command -v colmap > /dev/null 2>&1") == 0; }

// `colmap model_converter` from `in` to `out` with the given output type; true on success.
bool ColmapConvert(const std::string& in, const std::string& out, const std::string& type, const std::string& log) {
  fs::create_directories(out);
  const std::string cmd = "colmap model_converter --input_path '" + in + "' --output_path '" + out +
                          "' --output_type " + type + " > '" + log + "' 2>&1";
  return RunShell(cmd) == 0;
}

// ------------------------------------------------------------------------------------------------------------

TEST(ReconstructionTest, BinaryLayoutMatchesColmapByteForByte) {
  // A hand-assembled expectation of COLMAP 3.8's binary layout (docs/colmap.md), independent of the reader.
  Reconstruction model;
  ModelCamera camera;
  camera.camera_id = 7;
  camera.intrinsics.model_id = 1;  // PINHOLE
  camera.intrinsics.width = 640;
  camera.intrinsics.height = 480;
  camera.intrinsics.params = {500.25, 501.5, 320.0, 240.125};
  model.cameras[7] = camera;
  ModelImage image;
  image.image_id = 3;
  image.qvec = Eigen::Vector4d(0.5, 0.5, -0.5, 0.5);
  image.tvec = Eigen::Vector3d(1.0, -2.0, 0.25);
  image.camera_id = 7;
  image.name = "a.png";
  image.points2D = {Eigen::Vector2d(10.5, 20.5), Eigen::Vector2d(30.0, 40.0)};
  image.point3D_ids = {kInvalidPoint3DId, 42};
  model.images[3] = image;
  ModelPoint3D point;
  point.xyz = Eigen::Vector3d(0.1, 0.2, 0.3);
  point.rgb = {1, 2, 255};
  point.error = 0.75;
  point.track = {{3, 1}};
  model.points3D[42] = point;

  TempDir tmp;
  WriteReconstructionBinary(model, tmp.Sub("model"));

  std::string cameras = Bytes<uint64_t>(1) + Bytes<uint32_t>(7) + Bytes<int32_t>(1) + Bytes<uint64_t>(640) +
                        Bytes<uint64_t>(480);
  for (double p : camera.intrinsics.params) cameras += Bytes<double>(p);
  EXPECT_EQ(ReadFile(tmp.Sub("model/cameras.bin")), cameras);

  std::string images = Bytes<uint64_t>(1) + Bytes<uint32_t>(3);
  for (int k = 0; k < 4; ++k) images += Bytes<double>(image.qvec(k));
  for (int k = 0; k < 3; ++k) images += Bytes<double>(image.tvec(k));
  images += Bytes<uint32_t>(7) + std::string("a.png") + std::string(1, '\0') + Bytes<uint64_t>(2);
  images += Bytes<double>(10.5) + Bytes<double>(20.5) + Bytes<uint64_t>(UINT64_MAX);
  images += Bytes<double>(30.0) + Bytes<double>(40.0) + Bytes<uint64_t>(42);
  EXPECT_EQ(ReadFile(tmp.Sub("model/images.bin")), images);

  std::string points = Bytes<uint64_t>(1) + Bytes<uint64_t>(42) + Bytes<double>(0.1) + Bytes<double>(0.2) +
                       Bytes<double>(0.3) + Bytes<uint8_t>(1) + Bytes<uint8_t>(2) + Bytes<uint8_t>(255) +
                       Bytes<double>(0.75) + Bytes<uint64_t>(1) + Bytes<uint32_t>(3) + Bytes<uint32_t>(1);
  EXPECT_EQ(ReadFile(tmp.Sub("model/points3D.bin")), points);

  ExpectModelsEqual(model, ReadReconstruction(tmp.Sub("model")));
}

TEST(ReconstructionTest, BinaryRoundTripIsBitExact) {
  int num_models = 0;
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    const Reconstruction model = RandomModel(seed);
    TempDir tmp;
    WriteReconstructionBinary(model, tmp.Sub("a/b"));  // creates nested directories
    const Reconstruction read = ReadReconstruction(tmp.Sub("a/b"));
    ExpectModelsEqual(model, read);
    // Writing what was read reproduces the files byte for byte.
    WriteReconstructionBinary(read, tmp.Sub("c"));
    for (const char* f : {"cameras.bin", "images.bin", "points3D.bin"}) {
      EXPECT_EQ(ReadFile(tmp.Sub(std::string("a/b/") + f)), ReadFile(tmp.Sub(std::string("c/") + f))) << f;
    }
    ++num_models;
  }
  std::printf("binary round trip bit-exact for %d random models\n", num_models);
}

TEST(ReconstructionTest, TextRoundTripIsExactAndLooksLikeColmap) {
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    const Reconstruction model = RandomModel(seed);
    TempDir tmp;
    WriteReconstructionText(model, tmp.Sub("t"));
    // 17 significant digits: doubles survive the text round trip bit for bit.
    ExpectModelsEqual(model, ReadReconstruction(tmp.Sub("t")));
  }
  const Reconstruction model = RandomModel(3);
  TempDir tmp;
  WriteReconstructionText(model, tmp.Sub("t"));
  const std::string cameras = ReadFile(tmp.Sub("t/cameras.txt"));
  const std::string images = ReadFile(tmp.Sub("t/images.txt"));
  const std::string points = ReadFile(tmp.Sub("t/points3D.txt"));
  EXPECT_EQ(cameras.rfind("# Camera list with one line of data per camera:\n#   CAMERA_ID, MODEL, WIDTH, HEIGHT, "
                          "PARAMS[]\n# Number of cameras: 4\n",
                          0),
            0u);
  EXPECT_NE(cameras.find("\n1 SIMPLE_PINHOLE 640 480 "), std::string::npos);
  EXPECT_NE(cameras.find("\n7 OPENCV 736 528 "), std::string::npos);
  EXPECT_EQ(images.rfind("# Image list with two lines of data per image:\n#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, "
                         "CAMERA_ID, NAME\n#   POINTS2D[] as (X, Y, POINT3D_ID)\n# Number of images: 5, mean "
                         "observations per image: ",
                         0),
            0u);
  EXPECT_NE(images.find(" -1 "), std::string::npos);  // untriangulated keypoints
  EXPECT_NE(images.find(" dir/img_001.png\n\n"), std::string::npos);  // image without keypoints: empty 2nd line
  EXPECT_EQ(points.rfind("# 3D point list with one line of data per point:\n#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, "
                         "TRACK[] as (IMAGE_ID, POINT2D_IDX)\n# Number of points: " +
                             std::to_string(model.points3D.size()) + ", mean track length: ",
                         0),
            0u);
  EXPECT_NE(points.find("\n8589934599 "), std::string::npos);  // the id above 2^32
}

TEST(ReconstructionTest, BinaryFilesArePreferredOverText) {
  const Reconstruction a = RandomModel(1), b = RandomModel(2);
  TempDir tmp;
  WriteReconstructionText(a, tmp.path());
  ExpectModelsEqual(a, ReadReconstruction(tmp.path()));
  WriteReconstructionBinary(b, tmp.path());
  ExpectModelsEqual(b, ReadReconstruction(tmp.path()));
}

TEST(ReconstructionTest, EmptyModelRoundTrips) {
  TempDir tmp;
  WriteReconstructionBinary(Reconstruction(), tmp.Sub("b"));
  WriteReconstructionText(Reconstruction(), tmp.Sub("t"));
  for (const char* d : {"b", "t"}) {
    const Reconstruction r = ReadReconstruction(tmp.Sub(d));
    EXPECT_TRUE(r.cameras.empty() && r.images.empty() && r.points3D.empty()) << d;
  }
}

TEST(ReconstructionTest, ColmapReadsOurBinaryModel) {
  if (!HaveColmap()) GTEST_SKIP() << "colmap binary not found";
  const Reconstruction model = RandomModel(5, 6, 60);
  TempDir tmp;
  WriteReconstructionBinary(model, tmp.Sub("ours"));
  ASSERT_TRUE(ColmapConvert(tmp.Sub("ours"), tmp.Sub("colmap_txt"), "TXT", tmp.Sub("log.txt")))
      << ReadFile(tmp.Sub("log.txt"));
  ASSERT_TRUE(fs::exists(tmp.Sub("colmap_txt/images.txt")));
  // COLMAP re-normalises quaternions when it writes; everything else must come back exactly.
  const Reconstruction back = ReadReconstruction(tmp.Sub("colmap_txt"));
  ExpectModelsEqual(model, back, /*qvec_tol=*/1e-15);
  // Our text writer produces the same files as COLMAP's, up to the record order (COLMAP 3.8 writes in hash-map
  // order, we write in id order).
  WriteReconstructionText(model, tmp.Sub("ours_txt"));
  for (const auto& [file, header_lines, lines_per_record] :
       {std::tuple<std::string, int, int>{"cameras.txt", 3, 1}, {"images.txt", 4, 2}, {"points3D.txt", 3, 1}}) {
    const auto ours = SplitRecords(ReadFile(tmp.Sub("ours_txt/" + file)), header_lines, lines_per_record);
    const auto theirs = SplitRecords(ReadFile(tmp.Sub("colmap_txt/" + file)), header_lines, lines_per_record);
    EXPECT_EQ(ours, theirs) << file;
  }
}

TEST(ReconstructionTest, ColmapReadsOurTextModel) {
  if (!HaveColmap()) GTEST_SKIP() << "colmap binary not found";
  const Reconstruction model = RandomModel(6, 6, 60);
  TempDir tmp;
  WriteReconstructionText(model, tmp.Sub("ours"));
  ASSERT_TRUE(ColmapConvert(tmp.Sub("ours"), tmp.Sub("colmap_bin"), "BIN", tmp.Sub("log.txt")))
      << ReadFile(tmp.Sub("log.txt"));
  ASSERT_TRUE(fs::exists(tmp.Sub("colmap_bin/images.bin")));
  const Reconstruction back = ReadReconstruction(tmp.Sub("colmap_bin"));
  ExpectModelsEqual(model, back, /*qvec_tol=*/1e-15);
}

// ------------------------------------------------------------------------------------------------------------
// Corrupt input.

TEST(ReconstructionTest, EveryTruncationOfABinaryFileThrowsNamingIt) {
  const Reconstruction model = RandomModel(7, 3, 12);
  TempDir tmp;
  WriteReconstructionBinary(model, tmp.Sub("good"));
  int truncations = 0, thrown = 0;
  TempDir dir;
  for (const char* file : {"cameras.bin", "images.bin", "points3D.bin"}) {
    WriteReconstructionBinary(model, dir.path());
    const std::string good = ReadFile(tmp.Sub(std::string("good/") + file));
    for (size_t len = 0; len < good.size(); ++len) {
      WriteFile(dir.Sub(file), good.substr(0, len));
      ++truncations;
      try {
        ReadReconstruction(dir.path());
      } catch (const std::runtime_error& e) {
        const std::string msg = e.what();
        if (msg.find(dir.Sub(file)) != std::string::npos) ++thrown;
        else ADD_FAILURE() << file << " cut at " << len << ": message does not name the file: " << msg;
      }
    }
  }
  std::printf("binary truncations that threw naming the file: %d of %d\n", thrown, truncations);
  EXPECT_EQ(thrown, truncations);
}

TEST(ReconstructionTest, TrailingBytesAreRejected) {
  const Reconstruction model = RandomModel(8, 3, 10);
  TempDir tmp;
  WriteReconstructionBinary(model, tmp.path());
  WriteFile(tmp.Sub("points3D.bin"), ReadFile(tmp.Sub("points3D.bin")) + "x");
  ExpectThrowsMentioning([&] { ReadReconstruction(tmp.path()); }, "points3D.bin: 1 unexpected trailing bytes");
}

TEST(ReconstructionTest, HugeCountsThrowWithoutAllocating) {
  const Reconstruction model = RandomModel(9, 3, 10);
  TempDir tmp;
  WriteReconstructionBinary(model, tmp.path());
  const std::string images = ReadFile(tmp.Sub("images.bin"));
  const std::string points = ReadFile(tmp.Sub("points3D.bin"));
  const std::string cameras = ReadFile(tmp.Sub("cameras.bin"));
  for (const uint64_t huge : {uint64_t{1} << 40, UINT64_MAX, uint64_t{1} << 62}) {
    // Number of images / 3-D points / cameras.
    WriteFile(tmp.Sub("images.bin"), Bytes<uint64_t>(huge) + images.substr(8));
    ExpectThrowsMentioning([&] { ReadReconstruction(tmp.path()); }, "images.bin: corrupt count");
    WriteFile(tmp.Sub("images.bin"), images);
    WriteFile(tmp.Sub("points3D.bin"), Bytes<uint64_t>(huge) + points.substr(8));
    ExpectThrowsMentioning([&] { ReadReconstruction(tmp.path()); }, "points3D.bin: corrupt count");
    WriteFile(tmp.Sub("cameras.bin"), Bytes<uint64_t>(huge) + cameras.substr(8));
    ExpectThrowsMentioning([&] { ReadReconstruction(tmp.path()); }, "cameras.bin: corrupt count");
    WriteFile(tmp.Sub("cameras.bin"), cameras);
    // num_points2D of the first image (after id, 7 doubles, camera id and "dir/img_000.png\0").
    const size_t num_points2D_offset = 8 + 4 + 56 + 4 + std::string("dir/img_000.png").size() + 1;
    std::string bad = images;
    std::memcpy(bad.data() + num_points2D_offset, &huge, 8);
    WriteFile(tmp.Sub("images.bin"), bad);
    ExpectThrowsMentioning([&] { ReadReconstruction(tmp.path()); }, "images.bin: corrupt count");
    // track length of the first 3-D point (after count, id, xyz, rgb, error).
    bad = points;
    std::memcpy(bad.data() + 8 + 8 + 24 + 3 + 8, &huge, 8);
    WriteFile(tmp.Sub("images.bin"), images);
    WriteFile(tmp.Sub("points3D.bin"), bad);
    ExpectThrowsMentioning([&] { ReadReconstruction(tmp.path()); }, "points3D.bin: corrupt count");
    WriteFile(tmp.Sub("points3D.bin"), points);
  }
  // Unknown camera model id.
  std::string bad = cameras;
  const int32_t model_id = 99;
  std::memcpy(bad.data() + 8 + 4, &model_id, 4);
  WriteFile(tmp.Sub("cameras.bin"), bad);
  ExpectThrowsMentioning([&] { ReadReconstruction(tmp.path()); }, "cameras.bin: camera 1 has unknown camera model");
}

TEST(ReconstructionTest, RandomGarbageAndByteFlipsNeverCrash) {
  // Random files must throw std::runtime_error naming the file; random byte flips in a valid model either
  // read (a flipped double is still a valid file) or throw std::runtime_error naming a model file.
  std::mt19937_64 rng(12345);
  const Reconstruction model = RandomModel(10, 4, 20);
  TempDir tmp;
  WriteReconstructionBinary(model, tmp.Sub("good"));
  WriteReconstructionBinary(model, tmp.path());
  auto restore = [&](const char* file) { WriteFile(tmp.Sub(file), ReadFile(tmp.Sub(std::string("good/") + file))); };
  int garbage_thrown = 0;
  const int kGarbage = 300;
  for (int trial = 0; trial < kGarbage; ++trial) {
    const char* file = trial % 3 == 0 ? "cameras.bin" : trial % 3 == 1 ? "images.bin" : "points3D.bin";
    std::string garbage(rng() % 200, '\0');
    for (char& c : garbage) c = static_cast<char>(rng());
    WriteFile(tmp.Sub(file), garbage);
    try {
      ReadReconstruction(tmp.path());
    } catch (const std::runtime_error& e) {
      garbage_thrown += std::string(e.what()).find(file) != std::string::npos;
    }
    restore(file);
  }
  int flips_read = 0, flips_thrown = 0;
  const int kFlips = 1000;
  for (int trial = 0; trial < kFlips; ++trial) {
    const char* file = trial % 3 == 0 ? "cameras.bin" : trial % 3 == 1 ? "images.bin" : "points3D.bin";
    std::string bytes = ReadFile(tmp.Sub(std::string("good/") + file));
    for (int k = 0; k < 3; ++k) bytes[rng() % bytes.size()] = static_cast<char>(rng());
    WriteFile(tmp.Sub(file), bytes);
    try {
      ReadReconstruction(tmp.path());
      ++flips_read;
    } catch (const std::runtime_error& e) {
      const std::string msg = e.what();
      EXPECT_TRUE(msg.find(".bin: ") != std::string::npos) << msg;
      ++flips_thrown;
    }
    restore(file);
  }
  std::printf("random garbage files rejected naming the file: %d of %d\n", garbage_thrown, kGarbage);
  std::printf("3-byte flips in valid files: %d read, %d threw std::runtime_error, 0 crashed\n", flips_read,
              flips_thrown);
  EXPECT_EQ(garbage_thrown, kGarbage);
  EXPECT_EQ(flips_read + flips_thrown, kFlips);
}

TEST(ReconstructionTest, TextTruncatedAtAnyLineBoundaryThrowsNamingTheFile) {
  const Reconstruction model = RandomModel(11, 4, 20);
  TempDir tmp;
  WriteReconstructionText(model, tmp.Sub("good"));
  int cuts = 0, thrown = 0;
  TempDir dir;
  for (const char* file : {"cameras.txt", "images.txt", "points3D.txt"}) {
    WriteReconstructionText(model, dir.path());
    const std::string good = ReadFile(tmp.Sub(std::string("good/") + file));
    const size_t header_end = good.find("\n", good.find("# Number of")) + 1;
    // Cut after every complete line past the header except the last one (which would be the whole file).
    for (size_t pos = good.find('\n', header_end); pos + 1 < good.size(); pos = good.find('\n', pos + 1)) {
      WriteFile(dir.Sub(file), good.substr(0, pos + 1));
      ++cuts;
      try {
        ReadReconstruction(dir.path());
      } catch (const std::runtime_error& e) {
        if (std::string(e.what()).find(dir.Sub(file)) != std::string::npos) ++thrown;
        else ADD_FAILURE() << e.what();
      }
    }
  }
  std::printf("text files cut at a line boundary that threw naming the file: %d of %d\n", thrown, cuts);
  EXPECT_EQ(thrown, cuts);
  EXPECT_GT(cuts, 20);
}

TEST(ReconstructionTest, MalformedTextLinesThrowNamingFileAndLine) {
  const Reconstruction model = RandomModel(12, 3, 10);
  TempDir tmp;
  auto with_line = [&](const char* file, const std::string& line, const std::string& needle) {
    WriteReconstructionText(model, tmp.path());
    std::string text = ReadFile(tmp.Sub(file));
    const size_t header_end = text.find("\n", text.find("# Number of")) + 1;
    const size_t line_end = text.find('\n', header_end);
    text = text.substr(0, header_end) + line + text.substr(line_end);  // replaces the first data line
    WriteFile(tmp.Sub(file), text);
    ExpectThrowsMentioning([&] { ReadReconstruction(tmp.path()); }, tmp.Sub(file) + ": " + needle);
  };
  with_line("cameras.txt", "1 NO_SUCH_MODEL 640 480 500 320 240", "line 4: unknown camera model 'NO_SUCH_MODEL'");
  with_line("cameras.txt", "1 SIMPLE_PINHOLE 640 480 500 320", "line 4: camera model SIMPLE_PINHOLE needs 3");
  with_line("cameras.txt", "1 SIMPLE_PINHOLE 640 480 500 320 abc", "line 4: bad parameter 'abc'");
  with_line("cameras.txt", "-1 SIMPLE_PINHOLE 640 480 500 320 240", "line 4: bad camera id '-1'");
  with_line("cameras.txt", "1 SIMPLE_PINHOLE 640 -480 500 320 240", "line 4: bad height '-480'");
  with_line("images.txt", "3 1 0 0 0 0 0 0 1 a b.png", "line 5: expected IMAGE_ID");
  with_line("images.txt", "3 0 0 0 0 0 0 0 1 a.png", "line 5: zero quaternion");
  with_line("images.txt", "3 1 0 0 0 0 0 0 99999999999 a.png", "line 5: bad camera id '99999999999'");
  with_line("points3D.txt", "10 1 2 3 256 0 0 0.5", "line 4: bad colour '256'");
  with_line("points3D.txt", "10 1 2 3 1 2 3 0.5 3", "line 4: expected POINT3D_ID");
  with_line("points3D.txt", "10 1 2 x 1 2 3 0.5", "line 4: bad coordinate 'x'");
  // An odd points2D line (second line of the first image).
  WriteReconstructionText(model, tmp.path());
  std::string images = ReadFile(tmp.Sub("images.txt"));
  const size_t image_line_end = images.find('\n', images.find("# Number of images"));
  const size_t points_line_start = images.find('\n', image_line_end + 1) + 1;
  const size_t points_line_end = images.find('\n', points_line_start);
  images = images.substr(0, points_line_start) + "1.0 2.0" + images.substr(points_line_end);
  WriteFile(tmp.Sub("images.txt"), images);
  ExpectThrowsMentioning([&] { ReadReconstruction(tmp.path()); }, "images.txt: line 6: POINTS2D line");
}

TEST(ReconstructionTest, MissingFilesAndBrokenReferencesThrow) {
  TempDir tmp;
  ExpectThrowsMentioning([&] { ReadReconstruction(tmp.Sub("nope")); }, "nope: model directory does not exist");
  ExpectThrowsMentioning([&] { ReadReconstruction(tmp.path()); }, "no COLMAP model");
  const Reconstruction model = RandomModel(13, 3, 10);
  WriteReconstructionBinary(model, tmp.path());
  fs::remove(tmp.Sub("points3D.bin"));
  ExpectThrowsMentioning([&] { ReadReconstruction(tmp.path()); }, "points3D.bin: missing");

  // Image whose camera does not exist.
  Reconstruction bad = model;
  bad.images.begin()->second.camera_id = 77;
  WriteReconstructionBinary(bad, tmp.path());
  ExpectThrowsMentioning([&] { ReadReconstruction(tmp.path()); },
                         "images.bin: image '" + bad.images.begin()->second.name + "' (image_id 3) uses camera_id 77");
  // Track element that does not match the image's point3D_ids.
  bad = model;
  ModelPoint3D& point = bad.points3D.begin()->second;
  ASSERT_FALSE(point.track.empty());
  point.track[0].second = 100000;
  WriteReconstructionBinary(bad, tmp.path());
  ExpectThrowsMentioning([&] { ReadReconstruction(tmp.path()); }, "points3D.bin: 3-D point");
  // A track listing the same element twice.
  bad = model;
  ModelPoint3D& twice = bad.points3D.begin()->second;
  twice.track.push_back(twice.track[0]);
  WriteReconstructionBinary(bad, tmp.path());
  ExpectThrowsMentioning([&] { ReadReconstruction(tmp.path()); }, "twice");
  // An untriangulated point2D made to refer to a 3-D point that does not exist, or whose track does not list it.
  bad = model;
  ModelImage& image = bad.images.begin()->second;
  size_t free_idx = 0;
  while (image.point3D_ids[free_idx] != kInvalidPoint3DId) ++free_idx;
  image.point3D_ids[free_idx] = 123456789;
  WriteReconstructionText(bad, tmp.Sub("t"));
  ExpectThrowsMentioning([&] { ReadReconstruction(tmp.Sub("t")); },
                         "images.txt: image '" + image.name + "' (image_id 3) point2D " + std::to_string(free_idx) +
                             " refers to 3-D point 123456789, which points3D.txt does not contain");
  image.point3D_ids[free_idx] = bad.points3D.begin()->first;
  WriteReconstructionText(bad, tmp.Sub("t"));
  ExpectThrowsMentioning([&] { ReadReconstruction(tmp.Sub("t")); }, "whose track in points3D.txt does not list it");
}

TEST(ReconstructionTest, WritersRejectUnrepresentableModels) {
  TempDir tmp;
  Reconstruction model = RandomModel(14, 3, 10);
  model.cameras.begin()->second.intrinsics.params.pop_back();
  EXPECT_THROW(WriteReconstructionBinary(model, tmp.path()), std::invalid_argument);
  try {
    WriteReconstructionBinary(model, tmp.path());
  } catch (const std::invalid_argument& e) {
    // The camera is named with the images that use it.
    const uint32_t camera_id = model.cameras.begin()->first;
    std::string first_user;
    for (const auto& [id, image] : model.images) {
      if (image.camera_id == camera_id) {
        first_user = image.name;
        break;
      }
    }
    const std::string expected = "camera_id " + std::to_string(camera_id) +
                                 (first_user.empty() ? " (used by no image)" : " (used by '" + first_user + "'");
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
  }
  model = RandomModel(14, 3, 10);
  model.images.begin()->second.point3D_ids.pop_back();
  EXPECT_THROW(WriteReconstructionBinary(model, tmp.path()), std::invalid_argument);
  model = RandomModel(14, 3, 10);
  model.images.begin()->second.name = "with space.png";
  EXPECT_THROW(WriteReconstructionText(model, tmp.path()), std::invalid_argument);
  WriteReconstructionBinary(model, tmp.path());  // the binary format holds any name without NUL
  EXPECT_EQ(ReadReconstruction(tmp.path()).images.begin()->second.name, "with space.png");
}

// ------------------------------------------------------------------------------------------------------------
// Quaternions.

TEST(ReconstructionTest, QuaternionKnownValues) {
  const double s = std::sqrt(0.5);
  const Eigen::Matrix3d Rz = QuaternionToRotation(Eigen::Vector4d(s, 0, 0, s));  // 90 deg about z
  Eigen::Matrix3d expected;
  expected << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  EXPECT_LT((Rz - expected).norm(), 1e-15);
  EXPECT_EQ((QuaternionToRotation(Eigen::Vector4d(1, 0, 0, 0)) - Eigen::Matrix3d::Identity()).norm(), 0.0);
  // Not normalised: COLMAP normalises first.
  EXPECT_LT((QuaternionToRotation(Eigen::Vector4d(3 * s, 0, 0, 3 * s)) - expected).norm(), 1e-15);
  const Eigen::Vector4d q = RotationToQuaternion(expected);
  EXPECT_LT((q - Eigen::Vector4d(s, 0, 0, s)).norm(), 1e-15);
  // 180 degrees about x: w = 0.
  Eigen::Matrix3d Rx;
  Rx << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  const Eigen::Vector4d qx = RotationToQuaternion(Rx);
  EXPECT_LT((qx.cwiseAbs() - Eigen::Vector4d(0, 1, 0, 0)).norm(), 1e-15);
}

TEST(ReconstructionTest, QuaternionRoundTrips) {
  std::mt19937_64 rng(2024);
  std::normal_distribution<double> normal;
  double worst_R = 0.0, worst_q = 0.0;
  const int kTrials = 10000;
  int canonical = 0;
  for (int i = 0; i < kTrials; ++i) {
    Eigen::Vector4d q(normal(rng), normal(rng), normal(rng), normal(rng));
    if (i % 10 == 0) q(0) = 1e-9 * normal(rng);  // near 180 degrees
    q.normalize();
    const Eigen::Matrix3d R = QuaternionToRotation(q);
    EXPECT_LT((R * R.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-14);
    EXPECT_GT(R.determinant(), 0.0);
    const Eigen::Vector4d q2 = RotationToQuaternion(R);
    canonical += q2(0) >= 0.0 && std::abs(q2.norm() - 1.0) < 1e-15;
    worst_q = std::max(worst_q, std::min((q2 - q).norm(), (q2 + q).norm()));
    worst_R = std::max(worst_R, (QuaternionToRotation(q2) - R).norm());
  }
  std::printf("quaternion round trips over %d rotations: worst |q' -+ q| %.2e, worst |R' - R| %.2e, "
              "w >= 0 and unit in %d\n",
              kTrials, worst_q, worst_R, canonical);
  EXPECT_LT(worst_q, 1e-14);
  EXPECT_LT(worst_R, 1e-14);
  EXPECT_EQ(canonical, kTrials);
}

}  // namespace
}  // namespace madsfm::colmap
