#include "madsfm/io/depth_map_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include <zlib.h>

#include "madsfm/io/io_test_util.h"
#include "madsfm/io/npy.h"

namespace madsfm {
namespace {

using io_test::Bytes;
using io_test::Contains;
using io_test::ErrorOf;
using io_test::MakeNpy;
using io_test::NpyDict;
using io_test::TempDir;
using io_test::WriteFile;

constexpr float kNaNf = std::numeric_limits<float>::quiet_NaN();
constexpr float kInff = std::numeric_limits<float>::infinity();

// A W x H map with distinct values, plus a few invalid ones that must survive reading unchanged.
DepthMap MakeMap(int width, int height) {
  DepthMap map;
  map.width = width;
  map.height = height;
  map.data.resize(static_cast<size_t>(width) * height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) map.data[static_cast<size_t>(y) * width + x] = 1.0f + x + 0.01f * y;
  }
  map.data[0] = kNaNf;
  map.data[1] = -2.5f;
  map.data[2] = 0.0f;
  map.data[3] = kInff;
  return map;
}

void ExpectSameMap(const DepthMap& a, const DepthMap& b) {
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  ASSERT_EQ(a.data.size(), b.data.size());
  for (size_t i = 0; i < a.data.size(); ++i) {
    if (std::isnan(a.data[i])) {
      EXPECT_TRUE(std::isnan(b.data[i])) << i;
    } else {
      EXPECT_EQ(a.data[i], b.data[i]) << i;
    }
  }
}

// Asserts that reading `path` throws a std::runtime_error starting with "depth file '<path>': " and containing
// `fragment`.
void ExpectDepthError(const std::string& path, const std::string& fragment) {
  const std::string message = ErrorOf([&] { ReadDepthMap(path); });
  EXPECT_EQ(message.rfind("depth file '" + path + "': ", 0), 0u) << message;
  EXPECT_TRUE(Contains(message, fragment)) << "expected '" << fragment << "' in: " << message;
}

TEST(DepthMapIo, RoundTripAllFormats) {
  TempDir tmp;
  const DepthMap map = MakeMap(7, 5);
  WriteDepthMapNpy(map, tmp.File("d.npy"));
  WriteDepthMapPfm(map, tmp.File("d.pfm"));
  WriteDepthMapColmapBin(map, tmp.File("d.jpg.geometric.bin"));
  ExpectSameMap(map, ReadDepthMap(tmp.File("d.npy")));
  ExpectSameMap(map, ReadDepthMap(tmp.File("d.pfm")));
  ExpectSameMap(map, ReadDepthMap(tmp.File("d.jpg.geometric.bin")));
  // The .npy file is (H, W) float32.
  const NpyArray array = ReadNpy(tmp.File("d.npy"));
  EXPECT_EQ(array.shape, (std::vector<size_t>{5, 7}));
  EXPECT_EQ(array.dtype, "float32");
  // Extensions are case-insensitive.
  WriteDepthMapNpy(map, tmp.File("UPPER.NPY"));
  ExpectSameMap(map, ReadDepthMap(tmp.File("UPPER.NPY")));
}

TEST(DepthMapIo, NpyDtypesOrdersAndSingletonAxes) {
  TempDir tmp;
  // 2 x 3 map v(x, y) = 10 y + x in several encodings.
  const std::vector<float> expected = {0, 1, 2, 10, 11, 12};
  std::string f64, f16, fortran, big;
  const uint16_t halves[] = {0x0000, 0x3c00, 0x4000, 0x4900, 0x4980, 0x4a00};  // 0 1 2 10 11 12
  for (int i = 0; i < 6; ++i) {
    f64 += Bytes(static_cast<double>(expected[i]));
    f16 += Bytes(halves[i]);
    big += Bytes(expected[i], true);
  }
  for (int x = 0; x < 3; ++x) {
    for (int y = 0; y < 2; ++y) fortran += Bytes(expected[y * 3 + x]);
  }
  std::string data32;
  for (const float v : expected) data32 += Bytes(v);
  const std::vector<std::pair<std::string, std::string>> files = {
      {"f64.npy", MakeNpy(NpyDict("<f8", false, "(2, 3)"), f64)},
      {"f16.npy", MakeNpy(NpyDict("<f2", false, "(2, 3)"), f16)},
      {"fortran.npy", MakeNpy(NpyDict("<f4", true, "(2, 3)"), fortran)},
      {"big.npy", MakeNpy(NpyDict(">f4", false, "(2, 3)"), big)},
      {"chw.npy", MakeNpy(NpyDict("<f4", false, "(1, 2, 3)"), data32)},
      {"hwc.npy", MakeNpy(NpyDict("<f4", false, "(2, 3, 1)"), data32)},
      {"v2.npy", MakeNpy(NpyDict("<f4", false, "(2, 3)"), data32, 2)},
  };
  for (const auto& [name, bytes] : files) {
    WriteFile(tmp.File(name), bytes);
    const DepthMap map = ReadDepthMap(tmp.File(name));
    EXPECT_EQ(map.width, 3) << name;
    EXPECT_EQ(map.height, 2) << name;
    EXPECT_EQ(map.data, expected) << name;
    EXPECT_EQ(map.At(2, 1), 12.0f) << name;
  }
}

TEST(DepthMapIo, NpyShapeAndDtypeErrors) {
  TempDir tmp;
  const std::string data(3 * 4 * 5 * 8, '\0');
  const std::vector<std::tuple<std::string, std::string, std::string>> cases = {
      {"chw3.npy", MakeNpy(NpyDict("<f4", false, "(3, 4, 5)"), data), "expected a 2-D array, got shape (3, 4, 5)"},
      {"one_d.npy", MakeNpy(NpyDict("<f4", false, "(20,)"), data), "expected a 2-D array, got shape (20,)"},
      {"four_d.npy", MakeNpy(NpyDict("<f4", false, "(1, 1, 4, 5)"), data), "got shape (1, 1, 4, 5)"},
      {"scalar.npy", MakeNpy(NpyDict("<f4", false, "()"), data), "got shape ()"},
      {"empty_rows.npy", MakeNpy(NpyDict("<f4", false, "(0, 5)"), ""), "empty depth map, shape (0, 5)"},
      {"empty_cols.npy", MakeNpy(NpyDict("<f4", false, "(5, 0)"), ""), "empty depth map"},
      {"empty_chw.npy", MakeNpy(NpyDict("<f4", false, "(1, 0, 3)"), ""), "empty depth map"},
      {"int.npy", MakeNpy(NpyDict("<i4", false, "(4, 5)"), data), "expected a float16/float32/float64 array"},
      {"uint16.npy", MakeNpy(NpyDict("<u2", false, "(4, 5)"), data), "got dtype uint16"},
      {"complex.npy", MakeNpy(NpyDict("<c8", false, "(4, 5)"), data), "unsupported dtype 'complex64'"},
      {"object.npy", MakeNpy(NpyDict("|O", false, "(4, 5)"), data), "unsupported dtype 'object'"},
      {"truncated.npy", MakeNpy(NpyDict("<f4", false, "(40, 50)"), data), "truncated data"},
      {"truncated_header.npy", MakeNpy(NpyDict("<f4", false, "(4, 5)"), data).substr(0, 30), "truncated header"},
      {"garbage.npy", "\x7f" "ELF\x02\x01\x01 definitely not a numpy file", "not a .npy file"},
  };
  for (const auto& [name, bytes, fragment] : cases) {
    WriteFile(tmp.File(name), bytes);
    ExpectDepthError(tmp.File(name), fragment);
  }
}

TEST(DepthMapIo, PfmOrientationEndiannessAndErrors) {
  TempDir tmp;
  // Big-endian (positive scale) 2 x 3 file; the first stored row is the BOTTOM row of the image.
  std::string bytes = "Pf\n2 3\n1.0\n";
  const float stored[] = {20, 21, 10, 11, 0, 1};  // rows y = 2, 1, 0
  for (const float v : stored) bytes += Bytes(v, true);
  WriteFile(tmp.File("be.pfm"), bytes);
  DepthMap map = ReadDepthMap(tmp.File("be.pfm"));
  ASSERT_EQ(map.width, 2);
  ASSERT_EQ(map.height, 3);
  EXPECT_EQ(map.data, (std::vector<float>{0, 1, 10, 11, 20, 21}));
  // Little-endian with a scale magnitude other than 1 and the header on one line separated by spaces.
  bytes = "Pf 2 3 -0.5\n";
  for (const float v : stored) bytes += Bytes(v);
  WriteFile(tmp.File("le.pfm"), bytes);
  map = ReadDepthMap(tmp.File("le.pfm"));
  EXPECT_EQ(map.data, (std::vector<float>{0, 1, 10, 11, 20, 21}));

  std::string data;
  for (int i = 0; i < 6; ++i) data += Bytes(1.0f);
  const std::vector<std::tuple<std::string, std::string, std::string>> cases = {
      {"color.pfm", "PF\n2 3\n-1.0\n" + data + data + data, "3-channel PFM"},
      {"magic.pfm", "P5\n2 3\n255\n" + data, "not a PFM file"},
      {"empty.pfm", "", "not a PFM file"},
      {"no_height.pfm", "Pf\n2\n", "malformed PFM header"},
      {"bad_dims.pfm", "Pf\n-2 3\n-1.0\n" + data, "malformed PFM header"},
      {"zero.pfm", "Pf\n0 3\n-1.0\n", "empty depth map"},
      {"bad_scale.pfm", "Pf\n2 3\nabc\n" + data, "scale 'abc'"},
      {"zero_scale.pfm", "Pf\n2 3\n0\n" + data, "not a non-zero number"},
      {"no_data.pfm", "Pf\n2 3\n-1.0", "no data after the scale"},
      {"truncated.pfm", "Pf\n2 3\n-1.0\n" + data.substr(0, 23), "truncated data"},
      {"huge.pfm", "Pf\n999999999 999999999\n-1.0\n" + data, "truncated data"},
  };
  for (const auto& [name, content, fragment] : cases) {
    WriteFile(tmp.File(name), content);
    ExpectDepthError(tmp.File(name), fragment);
  }
}

TEST(DepthMapIo, ColmapBinLayoutAndErrors) {
  TempDir tmp;
  std::string bytes = "3&2&1&";
  for (int i = 0; i < 6; ++i) bytes += Bytes(static_cast<float>(i));
  WriteFile(tmp.File("a.jpg.photometric.bin"), bytes);
  const DepthMap map = ReadDepthMap(tmp.File("a.jpg.photometric.bin"));
  ASSERT_EQ(map.width, 3);
  ASSERT_EQ(map.height, 2);
  EXPECT_EQ(map.At(2, 0), 2.0f);  // element index = row * W + col
  EXPECT_EQ(map.At(0, 1), 3.0f);
  // What COLMAP's writer produces for this map, byte for byte.
  WriteDepthMapColmapBin(map, tmp.File("b.bin"));
  EXPECT_EQ(io_test::ReadFile(tmp.File("b.bin")), bytes);

  std::string data;
  for (int i = 0; i < 18; ++i) data += Bytes(1.0f);
  const std::vector<std::tuple<std::string, std::string, std::string>> cases = {
      {"normals.bin", "3&2&3&" + data, "3 channels; expected a 1-channel depth map"},
      {"truncated.bin", "3&2&1&" + data.substr(0, 10), "truncated data"},
      {"huge.bin", "99999&99999&1&" + data, "truncated data"},
      {"no_amp.bin", "3 2 1 " + data, "not a COLMAP depth map"},
      {"short.bin", "3&2&", "not a COLMAP depth map"},
      {"empty.bin", "", "not a COLMAP depth map"},
      {"zero.bin", "0&2&1&", "empty depth map"},
      {"overlong.bin", "1234567890&1&1&" + data, "not a COLMAP depth map"},
  };
  for (const auto& [name, content, fragment] : cases) {
    WriteFile(tmp.File(name), content);
    ExpectDepthError(tmp.File(name), fragment);
  }
}

TEST(DepthMapIo, FileLevelErrors) {
  TempDir tmp;
  ExpectDepthError(tmp.File("missing.npy"), "file does not exist");
  ExpectDepthError(tmp.path(), "is a directory");
  WriteFile(tmp.File("depth.tiff"), "II*");
  ExpectDepthError(tmp.File("depth.tiff"), "unsupported extension '.tiff'");
  WriteFile(tmp.File("noext"), "");
  ExpectDepthError(tmp.File("noext"), "unsupported extension");
  DepthMap bad;
  bad.width = 3;
  bad.height = 2;
  bad.data = {1, 2};
  const std::string path = tmp.File("bad.npy");
  EXPECT_TRUE(Contains(ErrorOf([&] { WriteDepthMapNpy(bad, path); }), "depth file '" + path + "'"));
  EXPECT_TRUE(Contains(ErrorOf([&] { WriteDepthMapPfm(DepthMap(), path); }), "empty depth map"));
}

// Reads a (possibly corrupt) depth file and counts the outcome: a consistent map, a std::runtime_error naming the
// file, or anything else (a defect).
struct ReadCounts {
  int parsed = 0, rejected = 0, other = 0;
};
void CountRead(const std::string& path, ReadCounts* counts) {
  try {
    const DepthMap read = ReadDepthMap(path);
    ++counts->parsed;
    if (read.Empty() || read.data.size() != static_cast<size_t>(read.width) * read.height) ++counts->other;
  } catch (const std::runtime_error& e) {
    ++counts->rejected;
    if (!Contains(e.what(), "depth file '" + path + "': ")) ++counts->other;
  } catch (...) {
    ++counts->other;
  }
}

// Random corruption of valid .pfm and .bin files: a clean read of a consistent map or a named error, nothing else.
TEST(DepthMapIo, FuzzedPfmAndBinNeverCrash) {
  TempDir tmp;
  const DepthMap map = MakeMap(4, 3);
  WriteDepthMapPfm(map, tmp.File("v.pfm"));
  WriteDepthMapColmapBin(map, tmp.File("v.bin"));
  std::mt19937 rng(99);
  ReadCounts counts;
  const int kTrials = 800;
  for (int trial = 0; trial < kTrials; ++trial) {
    const std::string ext = trial % 2 == 0 ? ".pfm" : ".bin";
    std::string bytes = io_test::ReadFile(tmp.File("v" + ext));
    if (trial % 4 < 2) {
      const int flips = 1 + static_cast<int>(rng() % 3);
      for (int f = 0; f < flips; ++f) {
        const size_t pos = rng() % 16;
        bytes[pos] = static_cast<char>(rng() & 0xff);
      }
    } else {
      bytes.resize(rng() % bytes.size());
    }
    const std::string path = tmp.File("fuzz" + ext);
    WriteFile(path, bytes);
    CountRead(path, &counts);
  }
  std::printf("fuzzed .pfm/.bin depth files: %d parsed, %d rejected with a named error, %d other (of %d)\n",
              counts.parsed, counts.rejected, counts.other, kTrials);
  EXPECT_EQ(counts.other, 0);
}

// A PNG byte stream written field by field (PNG specification, ISO/IEC 15948), independent of libpng: signature,
// IHDR, the extra chunks, one zlib-compressed IDAT whose rows use the None / Sub / Up filters in turn, IEND.
std::string PngChunk(const std::string& type, const std::string& data) {
  auto be32 = [](uint32_t v) {
    return std::string{static_cast<char>(v >> 24), static_cast<char>(v >> 16), static_cast<char>(v >> 8),
                       static_cast<char>(v)};
  };
  const std::string body = type + data;
  const uint32_t crc = crc32(0, reinterpret_cast<const Bytef*>(body.data()), static_cast<uInt>(body.size()));
  return be32(static_cast<uint32_t>(data.size())) + body + be32(crc);
}

std::string MakePng(int width, int height, int bit_depth, int color_type, const std::vector<uint8_t>& raw_rows,
                    const std::vector<std::string>& extra_chunks = {}) {
  const int channels = color_type == 2 ? 3 : color_type == 6 ? 4 : color_type == 4 ? 2 : 1;
  const size_t stride = static_cast<size_t>(width) * channels * bit_depth / 8;
  const size_t bpp = std::max<size_t>(1, static_cast<size_t>(channels) * bit_depth / 8);
  std::string filtered;
  for (int y = 0; y < height; ++y) {
    const uint8_t* row = raw_rows.data() + y * stride;
    const int filter = y == 0 ? (y % 2) : (y % 3);  // 0 None, 1 Sub, 2 Up
    filtered.push_back(static_cast<char>(filter));
    for (size_t x = 0; x < stride; ++x) {
      uint8_t predictor = 0;
      if (filter == 1 && x >= bpp) predictor = row[x - bpp];
      if (filter == 2) predictor = row[x - stride];
      filtered.push_back(static_cast<char>(static_cast<uint8_t>(row[x] - predictor)));
    }
  }
  std::vector<Bytef> compressed(compressBound(static_cast<uLong>(filtered.size())));
  uLongf size = static_cast<uLongf>(compressed.size());
  EXPECT_EQ(compress(compressed.data(), &size, reinterpret_cast<const Bytef*>(filtered.data()),
                     static_cast<uLong>(filtered.size())),
            Z_OK);
  std::string ihdr;
  for (uint32_t v : {static_cast<uint32_t>(width), static_cast<uint32_t>(height)}) {
    for (int shift = 24; shift >= 0; shift -= 8) ihdr.push_back(static_cast<char>(v >> shift));
  }
  ihdr += std::string{static_cast<char>(bit_depth), static_cast<char>(color_type), 0, 0, 0};
  std::string png = std::string("\x89PNG\r\n\x1a\n", 8) + PngChunk("IHDR", ihdr);
  for (const std::string& chunk : extra_chunks) png += chunk;
  return png + PngChunk("IDAT", std::string(reinterpret_cast<const char*>(compressed.data()), size)) +
         PngChunk("IEND", "");
}

// Big-endian 16-bit samples of a W x H map.
std::vector<uint8_t> Rows16(const std::vector<uint16_t>& values) {
  std::vector<uint8_t> bytes;
  for (uint16_t v : values) {
    bytes.push_back(static_cast<uint8_t>(v >> 8));
    bytes.push_back(static_cast<uint8_t>(v & 0xff));
  }
  return bytes;
}

TEST(DepthMapIo, Png16BitGrayscaleValuesAsStored) {
  TempDir tmp;
  const int w = 5, h = 4;
  std::vector<uint16_t> values(w * h);
  for (int i = 0; i < w * h; ++i) values[i] = static_cast<uint16_t>(1000 + 997 * i);
  values[0] = 0;  // no depth
  values[1] = 1;
  values[2] = 65535;
  values[7] = 256;
  // Without colour-space chunks, and with a linear gAMA (1.0): the same integers.
  const std::string gamma_linear = PngChunk("gAMA", std::string("\x00\x01\x86\xa0", 4));
  for (const auto& extra : {std::vector<std::string>{}, std::vector<std::string>{gamma_linear}}) {
    const std::string path = tmp.File("d.png");
    WriteFile(path, MakePng(w, h, 16, 0, Rows16(values), extra));
    const DepthMap map = ReadDepthMap(path);
    ASSERT_EQ(map.width, w);
    ASSERT_EQ(map.height, h);
    ASSERT_EQ(map.data.size(), values.size());
    for (size_t i = 0; i < values.size(); ++i) EXPECT_EQ(map.data[i], static_cast<float>(values[i])) << i;
  }
  // The uppercase extension too (as the other formats).
  WriteFile(tmp.File("D.PNG"), MakePng(w, h, 16, 0, Rows16(values)));
  EXPECT_EQ(ReadDepthMap(tmp.File("D.PNG")).data[2], 65535.0f);
}

TEST(DepthMapIo, PngErrorsSayWhatTheFileIs) {
  TempDir tmp;
  const std::string path = tmp.File("d.png");
  auto expect = [&](const std::string& bytes, const std::string& fragment) {
    WriteFile(path, bytes);
    ExpectDepthError(path, fragment);
  };
  const std::vector<uint16_t> values = {5, 6, 7, 8, 9, 10};  // 3 x 2
  const std::string good = MakePng(3, 2, 16, 0, Rows16(values));
  expect(std::string("GIF89a") + good, "not a PNG file");
  expect(MakePng(3, 2, 8, 2, std::vector<uint8_t>(18, 7)), "RGB PNG");
  expect(MakePng(3, 2, 8, 2, std::vector<uint8_t>(18, 7)), "image folder");
  expect(MakePng(3, 2, 8, 6, std::vector<uint8_t>(24, 7)), "RGBA PNG");
  expect(MakePng(3, 2, 16, 4, std::vector<uint8_t>(24, 7)), "grayscale+alpha PNG");
  expect(MakePng(3, 2, 8, 0, std::vector<uint8_t>(6, 7)), "8-bit grayscale PNG");
  expect(MakePng(3, 2, 16, 0, Rows16(values), {PngChunk("sRGB", std::string(1, '\0'))}), "'sRGB' chunk");
  expect(MakePng(3, 2, 16, 0, Rows16(values), {PngChunk("gAMA", std::string("\x00\x00\xb1\x8f", 4))}),
         "'gAMA' chunk");
  expect(good.substr(0, good.size() - 20), "truncated PNG chunk");
  // A corrupt compressed stream with a consistent chunk structure: libpng's error, named.
  std::string corrupt = good;
  const size_t idat = corrupt.find("IDAT");
  ASSERT_NE(idat, std::string::npos);
  corrupt[idat + 6] = static_cast<char>(corrupt[idat + 6] ^ 0x5a);
  expect(corrupt, "PNG");
  expect(std::string("\x89PNG\r\n\x1a\n", 8) + PngChunk("IEND", ""), "without a header chunk");
}

// Random corruption of a valid 16-bit PNG (any byte, or a cut): a consistent map or a named error, nothing else.
TEST(DepthMapIo, FuzzedPngNeverCrashes) {
  TempDir tmp;
  std::vector<uint16_t> values(8 * 6);
  for (size_t i = 0; i < values.size(); ++i) values[i] = static_cast<uint16_t>(300 * i + 1);
  const std::string good = MakePng(8, 6, 16, 0, Rows16(values));
  std::mt19937 rng(7);
  ReadCounts counts;
  const int kTrials = 600;
  const std::string path = tmp.File("fuzz.png");
  for (int trial = 0; trial < kTrials; ++trial) {
    std::string bytes = good;
    if (trial % 3 != 0) {
      const int flips = 1 + static_cast<int>(rng() % 3);
      for (int f = 0; f < flips; ++f) bytes[rng() % bytes.size()] = static_cast<char>(rng() & 0xff);
    } else {
      bytes.resize(rng() % bytes.size());
    }
    WriteFile(path, bytes);
    CountRead(path, &counts);
  }
  std::printf("fuzzed 16-bit PNG depth files: %d parsed, %d rejected with a named error, %d other (of %d)\n",
              counts.parsed, counts.rejected, counts.other, kTrials);
  EXPECT_EQ(counts.other, 0);
  EXPECT_GT(counts.rejected, kTrials / 2);  // the chunk CRCs catch most flips
}

TEST(DepthMapIo, FindDepthSidecarLookupOrder) {
  TempDir tmp;
  const std::string dir = tmp.path();
  EXPECT_FALSE(FindDepthSidecar(dir, "a/b.jpg").has_value());
  // A directory with a candidate's name is not a sidecar.
  std::filesystem::create_directories(tmp.File("a/b.jpg.bin"));
  EXPECT_FALSE(FindDepthSidecar(dir, "a/b.jpg").has_value());
  // Create candidates from the last to the first; each new one must win.
  const std::vector<std::string> order = {"a/b.jpg.npy",           "a/b.npy",
                                          "a/b.jpg.pfm",           "a/b.pfm",
                                          "a/b.jpg.geometric.bin", "a/b.jpg.photometric.bin",
                                          "a/b.jpg.bin",           "a/b.jpg.png",
                                          "a/b.png"};
  std::filesystem::remove(tmp.File("a/b.jpg.bin"));
  for (size_t i = order.size(); i-- > 0;) {
    WriteFile(tmp.File(order[i]), "x");
    const std::optional<std::string> found = FindDepthSidecar(dir, "a/b.jpg");
    ASSERT_TRUE(found.has_value()) << order[i];
    EXPECT_EQ(std::filesystem::path(*found), std::filesystem::path(tmp.File(order[i])));
  }
  // Another image in the same folder does not pick up b's files; dots in folder names are not extensions.
  EXPECT_FALSE(FindDepthSidecar(dir, "a/c.jpg").has_value());
  WriteFile(tmp.File("v1.2/img.npy"), "x");
  EXPECT_EQ(std::filesystem::path(FindDepthSidecar(dir, "v1.2/img.png").value()),
            std::filesystem::path(tmp.File("v1.2/img.npy")));
  EXPECT_FALSE(FindDepthSidecar(tmp.File("nonexistent"), "a/b.jpg").has_value());
  // Sensor depth beside PNG images (TUM RGB-D style: rgb/1.png with depth/rgb/1.png under --depth_path).
  WriteFile(tmp.File("rgb/1.png"), "x");
  EXPECT_EQ(std::filesystem::path(FindDepthSidecar(dir, "rgb/1.png").value()),
            std::filesystem::path(tmp.File("rgb/1.png")));
}

TEST(DepthMapIo, DisparityToDepth) {
  DepthMap disparity;
  disparity.width = 3;
  disparity.height = 2;
  disparity.data = {2.0f, 0.25f, 0.0f, -1.0f, kInff, kNaNf};
  const DepthMap depth = DisparityToDepth(disparity);
  ASSERT_EQ(depth.width, 3);
  ASSERT_EQ(depth.height, 2);
  EXPECT_EQ(depth.data[0], 0.5f);
  EXPECT_EQ(depth.data[1], 4.0f);
  for (int i = 2; i < 6; ++i) EXPECT_TRUE(std::isnan(depth.data[i])) << i;
}

}  // namespace
}  // namespace madsfm
