#include "madsfm/io/npy.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>

#include "madsfm/io/io_test_util.h"

namespace madsfm {
namespace {

using io_test::Bytes;
using io_test::Contains;
using io_test::ErrorOf;
using io_test::MakeNpy;
using io_test::NpyDict;
using io_test::TempDir;
using io_test::WriteFile;

constexpr double kInf = std::numeric_limits<double>::infinity();

// Independent reference for IEEE half precision: (-1)^s * 2^(e-15) * (1 + m/1024), subnormals m * 2^-24.
double ReferenceHalf(uint16_t h) {
  const int sign = h >> 15, exponent = (h >> 10) & 31, mantissa = h & 1023;
  double v;
  if (exponent == 0) {
    v = std::ldexp(mantissa, -24);
  } else if (exponent == 31) {
    v = mantissa != 0 ? std::numeric_limits<double>::quiet_NaN() : kInf;
  } else {
    v = std::ldexp(mantissa + 1024, exponent - 25);
  }
  return sign ? -v : v;
}

bool SameValue(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  return a == b && std::signbit(a) == std::signbit(b);
}

TEST(Npy, RoundTripFloat64AndFloat32) {
  TempDir tmp;
  const std::vector<std::vector<size_t>> shapes = {{3, 4}, {2, 3, 4}, {5}, {}, {1, 1, 1, 2}, {0, 3}};
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 100.0);
  for (const auto& shape : shapes) {
    NpyArray array;
    array.shape = shape;
    array.data.resize(array.NumElements());
    for (double& v : array.data) v = normal(rng);
    if (array.data.size() >= 4) {
      array.data[0] = kInf;
      array.data[1] = -kInf;
      array.data[2] = std::numeric_limits<double>::quiet_NaN();
      array.data[3] = -0.0;
    }
    const std::string name = FormatNpyShape(shape);
    const std::string path64 = tmp.File("a64.npy"), path32 = tmp.File("a32.npy");
    WriteNpy(path64, array, NpyWriteType::kFloat64);
    WriteNpy(path32, array, NpyWriteType::kFloat32);
    // numpy pads magic + length + header to a multiple of 64 bytes; ours does the same.
    EXPECT_EQ((io_test::ReadFile(path64).size() - array.data.size() * 8) % 64, 0u) << name;

    const NpyArray back64 = ReadNpy(path64);
    EXPECT_EQ(back64.shape, shape) << name;
    EXPECT_EQ(back64.dtype, "float64");
    ASSERT_EQ(back64.data.size(), array.data.size());
    for (size_t i = 0; i < array.data.size(); ++i) EXPECT_TRUE(SameValue(back64.data[i], array.data[i])) << i;

    const NpyArray back32 = ReadNpy(path32);
    const NpyArrayFloat back32f = ReadNpyFloat(path32);
    EXPECT_EQ(back32.shape, shape) << name;
    EXPECT_EQ(back32.dtype, "float32");
    ASSERT_EQ(back32.data.size(), array.data.size());
    ASSERT_EQ(back32f.data.size(), array.data.size());
    for (size_t i = 0; i < array.data.size(); ++i) {
      const float expected = static_cast<float>(array.data[i]);
      EXPECT_TRUE(SameValue(back32.data[i], expected)) << i;
      EXPECT_TRUE(SameValue(back32f.data[i], expected)) << i;
    }
  }
}

TEST(Npy, WriterHeaderIsWhatNumpyWrites) {
  TempDir tmp;
  const std::string path = tmp.File("m.npy");
  const std::vector<float> data = {1.5f, -2.0f};
  WriteNpy(path, {1, 2}, data.data());
  const std::string bytes = io_test::ReadFile(path);
  const std::string expected_header = "{'descr': '<f4', 'fortran_order': False, 'shape': (1, 2), }";
  ASSERT_EQ(bytes.size(), 128u + 8u);
  EXPECT_EQ(bytes.substr(0, 10), std::string("\x93NUMPY\x01\x00\x76\x00", 10));
  EXPECT_EQ(bytes.substr(10, expected_header.size()), expected_header);
  EXPECT_EQ(bytes[127], '\n');
  EXPECT_EQ(bytes.substr(128), Bytes(1.5f) + Bytes(-2.0f));
}

TEST(Npy, Float16AllBitPatternsBothEndians) {
  for (const bool big_endian : {false, true}) {
    std::string data;
    for (uint32_t h = 0; h < 65536; ++h) data += Bytes(static_cast<uint16_t>(h), big_endian);
    const std::string bytes = MakeNpy(NpyDict(big_endian ? ">f2" : "<f2", false, "(65536,)"), data);
    const NpyArray array = ParseNpy(bytes.data(), bytes.size(), "half.npy");
    EXPECT_EQ(array.dtype, "float16");
    ASSERT_EQ(array.data.size(), 65536u);
    int mismatches = 0;
    for (uint32_t h = 0; h < 65536; ++h) mismatches += !SameValue(array.data[h], ReferenceHalf(h));
    EXPECT_EQ(mismatches, 0) << (big_endian ? "big-endian" : "little-endian");
  }
  // A few named values.
  const uint16_t halves[] = {0x3c00, 0xc000, 0x7bff, 0x0001, 0x03ff, 0x0400, 0x3555, 0x7c00, 0xfc00, 0x8000};
  const double expected[] = {1.0,         -2.0, 65504.0, std::ldexp(1.0, -24), 1023 * std::ldexp(1.0, -24),
                             std::ldexp(1.0, -14), 0.333251953125, kInf, -kInf, -0.0};
  std::string data;
  for (const uint16_t h : halves) data += Bytes(h);
  const std::string bytes = MakeNpy(NpyDict("<f2", false, "(10,)"), data);
  const NpyArray array = ParseNpy(bytes.data(), bytes.size(), "half.npy");
  for (int i = 0; i < 10; ++i) EXPECT_TRUE(SameValue(array.data[i], expected[i])) << i;
  const std::string nan_bytes = MakeNpy(NpyDict("<f2", false, "(1,)"), Bytes(uint16_t{0x7e00}));
  EXPECT_TRUE(std::isnan(ParseNpy(nan_bytes.data(), nan_bytes.size(), "nan.npy").data[0]));
}

TEST(Npy, FortranOrder2DAnd3D) {
  // 2 x 3 matrix a(i, j) = 10 i + j stored column by column.
  std::string data;
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 2; ++i) data += Bytes(static_cast<double>(10 * i + j));
  }
  std::string bytes = MakeNpy(NpyDict("<f8", true, "(2, 3)"), data);
  NpyArray array = ParseNpy(bytes.data(), bytes.size(), "f2d.npy");
  ASSERT_EQ(array.shape, (std::vector<size_t>{2, 3}));
  EXPECT_EQ(array.data, (std::vector<double>{0, 1, 2, 10, 11, 12}));

  // 2 x 3 x 4 array a(i, j, k) = i + 10 j + 100 k, Fortran order (first index fastest), float32.
  data.clear();
  for (int k = 0; k < 4; ++k) {
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 2; ++i) data += Bytes(static_cast<float>(i + 10 * j + 100 * k));
    }
  }
  bytes = MakeNpy(NpyDict("<f4", true, "(2, 3, 4)"), data);
  array = ParseNpy(bytes.data(), bytes.size(), "f3d.npy");
  ASSERT_EQ(array.shape, (std::vector<size_t>{2, 3, 4}));
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 3; ++j) {
      for (int k = 0; k < 4; ++k) EXPECT_EQ(array.data[(i * 3 + j) * 4 + k], i + 10 * j + 100 * k);
    }
  }
  // 1-D Fortran is the same as C.
  bytes = MakeNpy(NpyDict("<f4", true, "(3,)"), Bytes(1.0f) + Bytes(2.0f) + Bytes(3.0f));
  EXPECT_EQ(ParseNpy(bytes.data(), bytes.size(), "f1d.npy").data, (std::vector<double>{1, 2, 3}));
}

TEST(Npy, BigEndianFloatsAndInts) {
  std::string bytes = MakeNpy(NpyDict(">f4", false, "(2,)"), Bytes(1.25f, true) + Bytes(-3.5f, true));
  EXPECT_EQ(ParseNpy(bytes.data(), bytes.size(), "be.npy").data, (std::vector<double>{1.25, -3.5}));
  NpyArray array = ParseNpy(bytes.data(), bytes.size(), "be.npy");
  EXPECT_EQ(array.dtype, "float32");
  bytes = MakeNpy(NpyDict(">f8", false, "(2,)"), Bytes(0.1, true) + Bytes(-1e300, true));
  EXPECT_EQ(ParseNpy(bytes.data(), bytes.size(), "be.npy").data, (std::vector<double>{0.1, -1e300}));
  bytes = MakeNpy(NpyDict(">i4", false, "(2,)"), Bytes(int32_t{-123456}, true) + Bytes(int32_t{7}, true));
  EXPECT_EQ(ParseNpy(bytes.data(), bytes.size(), "be.npy").data, (std::vector<double>{-123456, 7}));
  bytes = MakeNpy(NpyDict(">u2", true, "(1, 2)"), Bytes(uint16_t{65535}, true) + Bytes(uint16_t{258}, true));
  EXPECT_EQ(ParseNpy(bytes.data(), bytes.size(), "be.npy").data, (std::vector<double>{65535, 258}));
}

TEST(Npy, IntegerAndBoolTypes) {
  struct Case {
    std::string descr, data, dtype;
    std::vector<double> expected;
  };
  const std::vector<Case> cases = {
      {"|i1", Bytes(int8_t{-128}) + Bytes(int8_t{127}), "int8", {-128, 127}},
      {"|u1", Bytes(uint8_t{0}) + Bytes(uint8_t{255}), "uint8", {0, 255}},
      {"<i2", Bytes(int16_t{-32768}) + Bytes(int16_t{32767}), "int16", {-32768, 32767}},
      {"<u2", Bytes(uint16_t{0}) + Bytes(uint16_t{65535}), "uint16", {0, 65535}},
      {"<i4", Bytes(int32_t{-2147483647 - 1}) + Bytes(int32_t{2147483647}), "int32", {-2147483648.0, 2147483647}},
      {"<u4", Bytes(uint32_t{0}) + Bytes(uint32_t{4294967295u}), "uint32", {0, 4294967295.0}},
      {"<i8", Bytes(int64_t{-5}) + Bytes(int64_t{1} << 40), "int64", {-5, std::ldexp(1.0, 40)}},
      {"<u8", Bytes(uint64_t{3}) + Bytes(~uint64_t{0}), "uint64", {3, 18446744073709551615.0}},
      {">i8", Bytes(int64_t{-5}, true) + Bytes(int64_t{9}, true), "int64", {-5, 9}},
      {"|b1", std::string("\x00\x01", 2), "bool", {0, 1}},
  };
  for (const Case& c : cases) {
    const std::string bytes = MakeNpy(NpyDict(c.descr, false, "(2,)"), c.data);
    const NpyArray array = ParseNpy(bytes.data(), bytes.size(), "int.npy");
    EXPECT_EQ(array.dtype, c.dtype) << c.descr;
    EXPECT_EQ(array.data, c.expected) << c.descr;
  }
}

TEST(Npy, FormatVersionsAndHeaderVariants) {
  const std::string data = Bytes(1.0f) + Bytes(2.0f);
  for (const int major : {1, 2, 3}) {
    const std::string bytes = MakeNpy(NpyDict("<f4", false, "(1, 2)"), data, major);
    const NpyArray array = ParseNpy(bytes.data(), bytes.size(), "v.npy");
    EXPECT_EQ(array.shape, (std::vector<size_t>{1, 2})) << "version " << major;
    EXPECT_EQ(array.data, (std::vector<double>{1, 2}));
  }
  // Key order, double quotes, no trailing comma, Python 2 long suffixes.
  const std::string variants[] = {
      "{'shape': (1, 2), 'fortran_order': False, 'descr': '<f4'}",
      "{\"descr\": \"<f4\", \"fortran_order\": False, \"shape\": (1,2)}",
      "{'descr': '<f4', 'fortran_order': False, 'shape': (1L, 2L), }",
  };
  for (const std::string& dict : variants) {
    const std::string bytes = MakeNpy(dict, data);
    EXPECT_EQ(ParseNpy(bytes.data(), bytes.size(), "h.npy").shape, (std::vector<size_t>{1, 2})) << dict;
  }
  // 0-D scalar and 0-size arrays are valid .npy files.
  std::string bytes = MakeNpy(NpyDict("<f8", false, "()"), Bytes(4.5));
  NpyArray array = ParseNpy(bytes.data(), bytes.size(), "s.npy");
  EXPECT_TRUE(array.shape.empty());
  EXPECT_EQ(array.data, (std::vector<double>{4.5}));
  bytes = MakeNpy(NpyDict("<f8", false, "(0, 2)"), "");
  array = ParseNpy(bytes.data(), bytes.size(), "e.npy");
  EXPECT_EQ(array.shape, (std::vector<size_t>{0, 2}));
  EXPECT_TRUE(array.data.empty());
}

TEST(Npy, MalformedInputThrowsNamingTheFile) {
  const std::string good_data = Bytes(1.0f) + Bytes(2.0f);
  struct Case {
    std::string label, bytes, fragment;
  };
  const std::vector<Case> cases = {
      {"empty file", "", "not a .npy file"},
      {"short file", std::string("\x93NUM", 4), "not a .npy file"},
      {"bad magic", "PK\x03\x04 this is a zip file, not npy", "bad magic"},
      {"version 4", std::string("\x93NUMPY\x04\x00\x10\x00", 10) + std::string(16, ' '), "version 4.0"},
      {"truncated header", MakeNpy(NpyDict("<f4", false, "(1, 2)"), "").substr(0, 40), "truncated header"},
      {"truncated data", MakeNpy(NpyDict("<f4", false, "(1, 2)"), good_data.substr(0, 7)), "truncated data"},
      {"huge shape", MakeNpy(NpyDict("<f4", false, "(1000000000, 1000000000)"), good_data), "truncated data"},
      {"overflowing shape", MakeNpy(NpyDict("<f8", false, "(4294967296, 4294967296, 4294967296)"), ""),
       "truncated data"},
      {"overflowing integer", MakeNpy(NpyDict("<f8", false, "(99999999999999999999999,)"), ""), "shape"},
      {"negative shape", MakeNpy(NpyDict("<f4", false, "(-1, 2)"), good_data), "shape"},
      {"float shape", MakeNpy(NpyDict("<f4", false, "(1.5, 2)"), good_data), "malformed header"},
      {"complex64", MakeNpy(NpyDict("<c8", false, "(1,)"), good_data), "unsupported dtype 'complex64'"},
      {"complex128", MakeNpy(NpyDict("<c16", false, "(1,)"), good_data + good_data), "'complex128'"},
      {"object", MakeNpy(NpyDict("|O", false, "(1,)"), good_data), "unsupported dtype 'object'"},
      {"unicode", MakeNpy(NpyDict("<U10", false, "(1,)"), std::string(40, 'a')), "unsupported dtype 'str'"},
      {"float128", MakeNpy(NpyDict("<f16", false, "(1,)"), std::string(16, 'a')), "'float128'"},
      {"structured", MakeNpy("{'descr': [('a', '<f4')], 'fortran_order': False, 'shape': (2,), }", good_data),
       "structured"},
      {"missing key", MakeNpy("{'descr': '<f4', 'shape': (2,), }", good_data), "needs the keys"},
      {"not a dict", MakeNpy("('<f4', False, (2,))", good_data), "not a dictionary"},
      {"unterminated", MakeNpy("{'descr': '<f4", good_data), "malformed header"},
      {"garbage header", MakeNpy("\x01\x02\x03garbage{{{", good_data), "malformed header"},
      {"deep nesting", MakeNpy("{'shape': " + std::string(5000, '(') + "}", good_data), "nesting too deep"},
      {"fortran not bool", MakeNpy("{'descr': '<f4', 'fortran_order': 0, 'shape': (2,), }", good_data), "bool"},
  };
  for (const Case& c : cases) {
    const std::string name = "case_" + std::to_string(&c - cases.data()) + ".npy";
    const std::string message = ErrorOf([&] { ParseNpy(c.bytes.data(), c.bytes.size(), name); });
    EXPECT_TRUE(Contains(message, "npy file '" + name + "': ")) << c.label << ": " << message;
    EXPECT_TRUE(Contains(message, c.fragment)) << c.label << ": " << message;
  }
}

TEST(Npy, FileErrorsNameTheFile) {
  TempDir tmp;
  const std::string missing = tmp.File("missing.npy");
  std::string message = ErrorOf([&] { ReadNpy(missing); });
  EXPECT_TRUE(Contains(message, "npy file '" + missing + "': file does not exist")) << message;
  message = ErrorOf([&] { ReadNpy(tmp.path(), "matches file"); });
  EXPECT_TRUE(Contains(message, "matches file '" + tmp.path() + "': is a directory")) << message;
  const std::string truncated = tmp.File("truncated.npy");
  WriteFile(truncated, MakeNpy(NpyDict("<f4", false, "(480, 640)"), std::string(1000, '\0')));
  message = ErrorOf([&] { ReadNpyFloat(truncated, "depth file"); });
  EXPECT_TRUE(Contains(message, "depth file '" + truncated + "': truncated data")) << message;
}

// Random corruption of a valid file and random garbage: every outcome is a clean parse or a std::runtime_error
// naming the file (a crash, another exception type or a huge allocation would fail the test).
TEST(Npy, FuzzedBytesNeverCrash) {
  std::string valid_data;
  for (int i = 0; i < 12; ++i) valid_data += Bytes(static_cast<float>(i));
  const std::string valid = MakeNpy(NpyDict("<f4", false, "(3, 4)"), valid_data);
  std::mt19937 rng(12345);
  int parsed = 0, rejected = 0, other = 0;
  const int kTrials = 20000;
  for (int trial = 0; trial < kTrials; ++trial) {
    std::string bytes;
    const int mode = trial % 3;
    if (mode == 0) {  // flip a few bytes, mostly in the header
      bytes = valid;
      const int flips = 1 + static_cast<int>(rng() % 4);
      for (int f = 0; f < flips; ++f) {
        const size_t range = rng() % 4 == 0 ? bytes.size() : 64;
        const size_t pos = rng() % range;
        bytes[pos] = static_cast<char>(rng() & 0xff);
      }
    } else if (mode == 1) {  // truncate
      bytes = valid.substr(0, rng() % valid.size());
    } else {  // garbage behind a valid magic string, or pure garbage
      const size_t n = rng() % 300;
      const bool with_magic = rng() % 2 == 0;
      bytes = with_magic ? std::string("\x93NUMPY\x01\x00", 8) : std::string();
      for (size_t i = 0; i < n; ++i) bytes.push_back(static_cast<char>(rng() & 0xff));
    }
    try {
      const NpyArray array = ParseNpy(bytes.data(), bytes.size(), "fuzz.npy");
      ++parsed;
      if (array.data.size() != array.NumElements() || array.data.size() * 1 > bytes.size()) ++other;
    } catch (const std::runtime_error& e) {
      ++rejected;
      if (!Contains(e.what(), "npy file 'fuzz.npy': ")) ++other;
    } catch (...) {
      ++other;
    }
  }
  std::printf("fuzzed .npy inputs: %d parsed, %d rejected with a named error, %d other outcomes (of %d)\n", parsed,
              rejected, other, kTrials);
  EXPECT_EQ(other, 0);
  EXPECT_GT(rejected, kTrials / 2);
}

TEST(Npy, FormatShape) {
  EXPECT_EQ(FormatNpyShape({3, 480, 640}), "(3, 480, 640)");
  EXPECT_EQ(FormatNpyShape({5}), "(5,)");
  EXPECT_EQ(FormatNpyShape({}), "()");
}

TEST(Npy, WriterRejectsInconsistentArray) {
  TempDir tmp;
  NpyArray array;
  array.shape = {2, 2};
  array.data = {1, 2, 3};
  const std::string path = tmp.File("bad.npy");
  EXPECT_TRUE(Contains(ErrorOf([&] { WriteNpy(path, array); }), "npy file '" + path + "'"));
  const std::string unwritable = tmp.File("no/such/dir/x.npy");
  EXPECT_TRUE(Contains(ErrorOf([&] { WriteNpy(unwritable, {1}, std::vector<double>{1.0}.data()); }), unwritable));
}

}  // namespace
}  // namespace madsfm
