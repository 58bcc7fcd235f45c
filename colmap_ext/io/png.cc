#include "colmap_ext/io/png.h"

#include <zlib.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>

namespace madsfm {
namespace {

void AppendBigEndian32(uint32_t v, std::vector<uint8_t>* out) {
  out->push_back(static_cast<uint8_t>(v >> 24));
  out->push_back(static_cast<uint8_t>(v >> 16));
  out->push_back(static_cast<uint8_t>(v >> 8));
  out->push_back(static_cast<uint8_t>(v));
}

// Length, type, data, CRC-32 of type + data.
void AppendChunk(const char type[4], const uint8_t* data, size_t size, std::vector<uint8_t>* out) {
  if (size > 0x7FFFFFFFu) throw std::runtime_error("PNG chunk too large");
  AppendBigEndian32(static_cast<uint32_t>(size), out);
  const size_t type_pos = out->size();
  out->insert(out->end(), type, type + 4);
  if (size > 0) out->insert(out->end(), data, data + size);
  const uLong crc = crc32(0L, out->data() + type_pos, static_cast<uInt>(4 + size));
  AppendBigEndian32(static_cast<uint32_t>(crc), out);
}

inline uint8_t Paeth(int a, int b, int c) {
  const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  if (pa <= pb && pa <= pc) return static_cast<uint8_t>(a);
  return static_cast<uint8_t>(pb <= pc ? b : c);
}

}  // namespace

std::vector<uint8_t> EncodePng(int width, int height, int channels, const uint8_t* pixels) {
  if (width <= 0 || height <= 0 || width > (1 << 24) || height > (1 << 24))
    throw std::runtime_error("PNG: invalid size " + std::to_string(width) + " x " + std::to_string(height));
  if (channels < 1 || channels > 4)
    throw std::runtime_error("PNG: channels must be 1-4, got " + std::to_string(channels));
  if (pixels == nullptr) throw std::runtime_error("PNG: null pixel buffer");
  const size_t stride = static_cast<size_t>(width) * channels;
  const int bpp = channels;  // bytes per pixel (8-bit samples)

  // Filtered scanlines: one filter-type byte, then the row.
  std::vector<uint8_t> raw((stride + 1) * height);
  std::vector<uint8_t> candidate(stride), best(stride);
  for (int y = 0; y < height; ++y) {
    const uint8_t* row = pixels + static_cast<size_t>(y) * stride;
    const uint8_t* prev = y > 0 ? row - stride : nullptr;
    long best_cost = -1;
    uint8_t best_type = 0;
    for (uint8_t type = 0; type <= 4; ++type) {
      if (y == 0 && (type == 2)) continue;  // Up == None on the first row
      long cost = 0;
      for (size_t i = 0; i < stride; ++i) {
        const int a = i >= static_cast<size_t>(bpp) ? row[i - bpp] : 0;
        const int b = prev ? prev[i] : 0;
        const int c = (prev && i >= static_cast<size_t>(bpp)) ? prev[i - bpp] : 0;
        int predictor = 0;
        switch (type) {
          case 1:
            predictor = a;
            break;
          case 2:
            predictor = b;
            break;
          case 3:
            predictor = (a + b) / 2;
            break;
          case 4:
            predictor = Paeth(a, b, c);
            break;
          default:
            break;
        }
        const uint8_t r = static_cast<uint8_t>(row[i] - predictor);
        candidate[i] = r;
        cost += r < 128 ? r : 256 - r;  // residuals as signed bytes
      }
      if (best_cost < 0 || cost < best_cost) {
        best_cost = cost;
        best_type = type;
        best.swap(candidate);
      }
    }
    uint8_t* out_row = raw.data() + static_cast<size_t>(y) * (stride + 1);
    out_row[0] = best_type;
    std::copy(best.begin(), best.end(), out_row + 1);
  }

  uLongf compressed_size = compressBound(static_cast<uLong>(raw.size()));
  std::vector<uint8_t> compressed(compressed_size);
  const int status = compress2(compressed.data(), &compressed_size, raw.data(), static_cast<uLong>(raw.size()), 6);
  if (status != Z_OK) throw std::runtime_error("PNG: zlib compress2 failed (" + std::to_string(status) + ")");
  compressed.resize(compressed_size);

  std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  png.reserve(compressed.size() + 64);
  std::vector<uint8_t> ihdr;
  AppendBigEndian32(static_cast<uint32_t>(width), &ihdr);
  AppendBigEndian32(static_cast<uint32_t>(height), &ihdr);
  static const uint8_t kColorType[5] = {0, 0, 4, 2, 6};  // grey, grey + alpha, RGB, RGBA
  ihdr.push_back(8);                                     // bit depth
  ihdr.push_back(kColorType[channels]);
  ihdr.push_back(0);  // compression: deflate
  ihdr.push_back(0);  // filter method 0
  ihdr.push_back(0);  // no interlace
  AppendChunk("IHDR", ihdr.data(), ihdr.size(), &png);
  AppendChunk("IDAT", compressed.data(), compressed.size(), &png);
  AppendChunk("IEND", nullptr, 0, &png);
  return png;
}

void WritePng(const std::string& path, int width, int height, int channels, const uint8_t* pixels) {
  std::vector<uint8_t> png;
  try {
    png = EncodePng(width, height, channels, pixels);
  } catch (const std::exception& e) {
    throw std::runtime_error("PNG file '" + path + "': " + e.what());
  }
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) throw std::runtime_error("PNG file '" + path + "': cannot open for writing");
  file.write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
  if (!file) throw std::runtime_error("PNG file '" + path + "': write failed");
}

}  // namespace madsfm
