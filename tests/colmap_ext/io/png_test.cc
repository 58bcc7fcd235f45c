#include "colmap_ext/io/png.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "testing/temp_dir.h"

namespace madsfm {
namespace {

uint32_t BigEndian32(const uint8_t* p) {
  return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | uint32_t{p[3]};
}

struct Chunk {
  std::string type;
  std::vector<uint8_t> data;
};

// Splits a PNG stream into chunks, checking the signature, every length and every CRC.
std::vector<Chunk> ParseChunks(const std::vector<uint8_t>& png) {
  static const uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  EXPECT_GE(png.size(), 8u);
  EXPECT_TRUE(std::equal(kSignature, kSignature + 8, png.begin()));
  std::vector<Chunk> chunks;
  size_t pos = 8;
  while (pos + 12 <= png.size()) {
    const uint32_t length = BigEndian32(&png[pos]);
    EXPECT_LE(pos + 12 + length, png.size());
    if (pos + 12 + length > png.size()) break;
    Chunk c;
    c.type.assign(reinterpret_cast<const char*>(&png[pos + 4]), 4);
    c.data.assign(png.begin() + pos + 8, png.begin() + pos + 8 + length);
    const uint32_t crc = static_cast<uint32_t>(crc32(0L, &png[pos + 4], 4 + length));
    EXPECT_EQ(BigEndian32(&png[pos + 8 + length]), crc) << "CRC of chunk " << c.type;
    chunks.push_back(std::move(c));
    pos += 12 + length;
  }
  EXPECT_EQ(pos, png.size());
  return chunks;
}

// Reverses the PNG scanline filters (filter method 0) of 8-bit samples.
std::vector<uint8_t> Unfilter(const std::vector<uint8_t>& raw, int width, int height, int channels) {
  const size_t stride = static_cast<size_t>(width) * channels;
  std::vector<uint8_t> out(stride * height);
  for (int y = 0; y < height; ++y) {
    const uint8_t type = raw[y * (stride + 1)];
    EXPECT_LE(type, 4);
    const uint8_t* in = &raw[y * (stride + 1) + 1];
    uint8_t* row = &out[y * stride];
    const uint8_t* prev = y > 0 ? row - stride : nullptr;
    for (size_t i = 0; i < stride; ++i) {
      const int a = i >= static_cast<size_t>(channels) ? row[i - channels] : 0;
      const int b = prev ? prev[i] : 0;
      const int c = prev && i >= static_cast<size_t>(channels) ? prev[i - channels] : 0;
      int pred = 0;
      if (type == 1) pred = a;
      if (type == 2) pred = b;
      if (type == 3) pred = (a + b) / 2;
      if (type == 4) {
        const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
        pred = (pa <= pb && pa <= pc) ? a : (pb <= pc ? b : c);
      }
      row[i] = static_cast<uint8_t>(in[i] + pred);
    }
  }
  return out;
}

// Decodes what EncodePng writes (IHDR, IDAT..., IEND) with zlib's uncompress and checks the header fields.
std::vector<uint8_t> Decode(const std::vector<uint8_t>& png, int width, int height, int channels) {
  const std::vector<Chunk> chunks = ParseChunks(png);
  EXPECT_GE(chunks.size(), 3u);
  if (chunks.size() < 3) return {};
  EXPECT_EQ(chunks.front().type, "IHDR");
  EXPECT_EQ(chunks.back().type, "IEND");
  EXPECT_TRUE(chunks.back().data.empty());
  const std::vector<uint8_t>& ihdr = chunks.front().data;
  EXPECT_EQ(ihdr.size(), 13u);
  EXPECT_EQ(BigEndian32(&ihdr[0]), static_cast<uint32_t>(width));
  EXPECT_EQ(BigEndian32(&ihdr[4]), static_cast<uint32_t>(height));
  EXPECT_EQ(ihdr[8], 8);  // bit depth
  const uint8_t kColorType[5] = {0, 0, 4, 2, 6};
  EXPECT_EQ(ihdr[9], kColorType[channels]);
  EXPECT_EQ(ihdr[10], 0);
  EXPECT_EQ(ihdr[11], 0);
  EXPECT_EQ(ihdr[12], 0);
  std::vector<uint8_t> idat;
  for (size_t i = 1; i + 1 < chunks.size(); ++i) {
    EXPECT_EQ(chunks[i].type, "IDAT");
    idat.insert(idat.end(), chunks[i].data.begin(), chunks[i].data.end());
  }
  const size_t stride = static_cast<size_t>(width) * channels;
  std::vector<uint8_t> raw((stride + 1) * height + 1);
  uLongf raw_size = raw.size();
  EXPECT_EQ(uncompress(raw.data(), &raw_size, idat.data(), idat.size()), Z_OK);
  EXPECT_EQ(raw_size, (stride + 1) * height);
  raw.resize(raw_size);
  if (raw_size != (stride + 1) * height) return {};
  return Unfilter(raw, width, height, channels);
}

TEST(Png, RoundTripsAllChannelCountsAndContents) {
  std::mt19937 rng(3);
  int filters_seen[5] = {0, 0, 0, 0, 0};
  for (int channels = 1; channels <= 4; ++channels) {
    for (const auto& [w, h] : std::vector<std::pair<int, int>>{{1, 1}, {7, 3}, {64, 48}, {33, 65}}) {
      for (int kind = 0; kind < 3; ++kind) {  // random noise, smooth gradients, constant
        std::vector<uint8_t> pixels(static_cast<size_t>(w) * h * channels);
        for (size_t i = 0; i < pixels.size(); ++i) {
          const size_t x = (i / channels) % w, y = i / channels / w;
          pixels[i] = kind == 0   ? static_cast<uint8_t>(rng())
                      : kind == 1 ? static_cast<uint8_t>(3 * x + 5 * y + i % channels * 40)
                                  : 77;
        }
        const std::vector<uint8_t> png = EncodePng(w, h, channels, pixels.data());
        const std::vector<uint8_t> decoded = Decode(png, w, h, channels);
        EXPECT_EQ(decoded, pixels) << channels << " channels, " << w << " x " << h << ", kind " << kind;
        // Record which row filters the encoder chose (re-inflate to read the filter bytes).
        std::vector<uint8_t> raw((static_cast<size_t>(w) * channels + 1) * h);
        uLongf n = raw.size();
        const std::vector<Chunk> chunks = ParseChunks(png);
        uncompress(raw.data(), &n, chunks[1].data.data(), chunks[1].data.size());
        for (int y = 0; y < h; ++y) ++filters_seen[raw[y * (static_cast<size_t>(w) * channels + 1)]];
      }
    }
  }
  std::printf("row filters chosen: none %d, sub %d, up %d, average %d, paeth %d\n", filters_seen[0], filters_seen[1],
              filters_seen[2], filters_seen[3], filters_seen[4]);
  // Smooth content must be filtered (otherwise the filter/unfilter path would be untested).
  EXPECT_GT(filters_seen[1] + filters_seen[2] + filters_seen[3] + filters_seen[4], 0);
}

TEST(Png, WritesAFile) {
  const testing::TempDir scratch("png_test");
  const std::string path = scratch.Sub("test.png");
  std::vector<uint8_t> rgb(20 * 10 * 3);
  for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<uint8_t>(i * 7);
  WritePng(path, 20, 10, 3, rgb.data());
  std::ifstream file(path, std::ios::binary);
  const std::vector<uint8_t> png((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  EXPECT_EQ(png, EncodePng(20, 10, 3, rgb.data()));
  EXPECT_EQ(Decode(png, 20, 10, 3), rgb);
}

TEST(Png, RejectsBadArguments) {
  const uint8_t pixel[4] = {1, 2, 3, 4};
  EXPECT_THROW(EncodePng(0, 1, 3, pixel), std::runtime_error);
  EXPECT_THROW(EncodePng(1, -1, 3, pixel), std::runtime_error);
  EXPECT_THROW(EncodePng(1, 1, 5, pixel), std::runtime_error);
  EXPECT_THROW(EncodePng(1, 1, 0, pixel), std::runtime_error);
  EXPECT_THROW(EncodePng(1, 1, 3, nullptr), std::runtime_error);
  try {
    WritePng("/nonexistent_dir_madsfm/x.png", 1, 1, 3, pixel);
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent_dir_madsfm/x.png"), std::string::npos);
  }
}

}  // namespace
}  // namespace madsfm
