#include "madsfm/io/depth_map_io.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <system_error>
#include <vector>

#include <png.h>

#include "madsfm/io/npy.h"

namespace madsfm {
namespace {

namespace fs = std::filesystem;

const char* const kWhat = "depth file";

[[noreturn]] void Fail(const std::string& path, const std::string& problem) {
  throw std::runtime_error(std::string(kWhat) + " '" + path + "': " + problem);
}

// A file opened for reading with its size known up front, so that sizes in headers can be checked before
// anything is allocated.
class InputFile {
 public:
  explicit InputFile(const std::string& path) : path_(path) {
    file_ = std::fopen(path.c_str(), "rb");
    if (file_ == nullptr) Fail(path, std::string("cannot open: ") + std::strerror(errno));
    if (std::fseek(file_, 0, SEEK_END) != 0) Fail(path, "cannot determine the file size");
    const long size = std::ftell(file_);
    if (size < 0) Fail(path, "cannot determine the file size");
    size_ = static_cast<size_t>(size);
  }
  ~InputFile() { std::fclose(file_); }
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;

  size_t Size() const { return size_; }
  // Reads up to max_bytes from the start of the file.
  std::string ReadPrefix(size_t max_bytes) {
    std::string bytes(std::min(max_bytes, size_), '\0');
    Read(0, bytes.size(), bytes.data());
    return bytes;
  }
  void Read(size_t offset, size_t n, void* dst) {
    if (n == 0) return;
    if (std::fseek(file_, static_cast<long>(offset), SEEK_SET) != 0 || std::fread(dst, 1, n, file_) != n) {
      Fail(path_, "read error");
    }
  }

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
  size_t size_ = 0;
};

std::string Lowercase(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

// Parses a positive decimal integer of at most 9 digits at bytes[*pos], advancing *pos.
bool ParseDimension(const std::string& bytes, size_t* pos, int* value) {
  size_t p = *pos;
  int64_t v = 0;
  while (p < bytes.size() && bytes[p] >= '0' && bytes[p] <= '9' && p - *pos < 10) v = v * 10 + (bytes[p++] - '0');
  if (p == *pos || p - *pos > 9) return false;
  *pos = p;
  *value = static_cast<int>(v);
  return true;
}

void CheckNotEmpty(const std::string& path, int width, int height) {
  if (width <= 0 || height <= 0) {
    Fail(path, "empty depth map (" + std::to_string(width) + "x" + std::to_string(height) + ")");
  }
}

DepthMap ReadDepthNpy(const std::string& path) {
  NpyArrayFloat array = ReadNpyFloat(path, kWhat);
  if (array.dtype.rfind("float", 0) != 0) {
    Fail(path, "expected a float16/float32/float64 array, got dtype " + array.dtype);
  }
  const std::vector<size_t>& s = array.shape;
  size_t height = 0, width = 0;
  if (s.size() == 2) {
    height = s[0];
    width = s[1];
  } else if (s.size() == 3 && s[0] == 1) {
    height = s[1];
    width = s[2];
  } else if (s.size() == 3 && s[2] == 1) {
    height = s[0];
    width = s[1];
  } else {
    Fail(path, "expected a 2-D array, got shape " + FormatNpyShape(s));
  }
  if (width == 0 || height == 0) Fail(path, "empty depth map, shape " + FormatNpyShape(s));
  const size_t kMaxSide = static_cast<size_t>(std::numeric_limits<int>::max());
  if (width > kMaxSide || height > kMaxSide) Fail(path, "depth map too large, shape " + FormatNpyShape(s));
  DepthMap map;
  map.width = static_cast<int>(width);
  map.height = static_cast<int>(height);
  map.data = std::move(array.data);
  return map;
}

DepthMap ReadDepthPfm(const std::string& path) {
  InputFile file(path);
  const std::string header = file.ReadPrefix(256);
  size_t pos = 0;
  if (header.size() < 2 || header[0] != 'P' || (header[1] != 'f' && header[1] != 'F') ||
      (header.size() > 2 && !IsSpace(header[2]))) {
    Fail(path, "not a PFM file (expected the magic 'Pf')");
  }
  if (header[1] == 'F') Fail(path, "3-channel PFM ('PF'); expected a grayscale depth map ('Pf')");
  pos = 2;
  auto skip_space = [&]() {
    const size_t start = pos;
    while (pos < header.size() && IsSpace(header[pos])) ++pos;
    return pos > start;
  };
  int width = 0, height = 0;
  if (!skip_space() || !ParseDimension(header, &pos, &width) || !skip_space() ||
      !ParseDimension(header, &pos, &height) || !skip_space()) {
    Fail(path, "malformed PFM header (expected 'Pf', width, height and scale)");
  }
  const size_t scale_start = pos;
  while (pos < header.size() && !IsSpace(header[pos])) ++pos;
  const std::string scale_text = header.substr(scale_start, pos - scale_start);
  char* end = nullptr;
  const double scale = scale_text.empty() ? 0.0 : std::strtod(scale_text.c_str(), &end);
  if (scale_text.empty() || end != scale_text.c_str() + scale_text.size() || !std::isfinite(scale) || scale == 0) {
    Fail(path, "malformed PFM header (scale '" + scale_text.substr(0, 32) + "' is not a non-zero number)");
  }
  if (pos >= header.size()) Fail(path, "malformed PFM header (no data after the scale)");
  ++pos;  // exactly one whitespace character separates the header from the data
  CheckNotEmpty(path, width, height);
  const size_t count = static_cast<size_t>(width) * static_cast<size_t>(height);
  const size_t available = file.Size() - pos;
  if (count * 4 > available) {
    Fail(path, "truncated data: " + std::to_string(width) + "x" + std::to_string(height) + " needs " +
                   std::to_string(count * 4) + " bytes, the file has " + std::to_string(available));
  }
  DepthMap map;
  map.width = width;
  map.height = height;
  map.data.resize(count);
  std::vector<uint32_t> raw(count);
  file.Read(pos, count * 4, raw.data());
  const bool big_endian = scale > 0;
  for (int row = 0; row < height; ++row) {
    const uint32_t* src = raw.data() + static_cast<size_t>(height - 1 - row) * width;  // rows bottom-to-top
    float* dst = map.data.data() + static_cast<size_t>(row) * width;
    for (int col = 0; col < width; ++col) {
      uint32_t bits = src[col];
      if (big_endian) bits = __builtin_bswap32(bits);
      std::memcpy(dst + col, &bits, 4);
    }
  }
  return map;
}

DepthMap ReadDepthColmapBin(const std::string& path) {
  InputFile file(path);
  const std::string header = file.ReadPrefix(64);
  size_t pos = 0;
  int dims[3] = {0, 0, 0};
  for (int i = 0; i < 3; ++i) {
    if (!ParseDimension(header, &pos, &dims[i]) || pos >= header.size() || header[pos] != '&') {
      Fail(path, "not a COLMAP depth map (expected the header 'width&height&channels&')");
    }
    ++pos;
  }
  const int width = dims[0], height = dims[1], channels = dims[2];
  if (channels != 1) {
    Fail(path, "COLMAP map with " + std::to_string(channels) + " channels; expected a 1-channel depth map");
  }
  CheckNotEmpty(path, width, height);
  const size_t count = static_cast<size_t>(width) * static_cast<size_t>(height);
  const size_t available = file.Size() - pos;
  if (count * 4 > available) {
    Fail(path, "truncated data: " + std::to_string(width) + "x" + std::to_string(height) + " needs " +
                   std::to_string(count * 4) + " bytes, the file has " + std::to_string(available));
  }
  DepthMap map;
  map.width = width;
  map.height = height;
  map.data.resize(count);
  file.Read(pos, count * 4, map.data.data());  // little-endian float32, row-major
  return map;
}

uint32_t BigEndian32(const std::string& bytes, size_t pos) {
  return (static_cast<uint32_t>(static_cast<unsigned char>(bytes[pos])) << 24) |
         (static_cast<uint32_t>(static_cast<unsigned char>(bytes[pos + 1])) << 16) |
         (static_cast<uint32_t>(static_cast<unsigned char>(bytes[pos + 2])) << 8) |
         static_cast<uint32_t>(static_cast<unsigned char>(bytes[pos + 3]));
}

// 16-bit grayscale PNG, the format of sensor depth (TUM RGB-D, ScanNet, Redwood, ICL-NUIM) and of 16-bit exports of
// monocular depth models: the raw 16-bit values, any unit (madsfm estimates a scale); 0 is "no depth" and stays
// invalid. The header chunks are checked first so that the errors can say what the file is; libpng decodes it.
DepthMap ReadDepthPng(const std::string& path) {
  InputFile file(path);
  const std::string bytes = file.ReadPrefix(file.Size());
  static const char kSignature[] = "\x89PNG\r\n\x1a\n";
  if (bytes.size() < 8 || bytes.compare(0, 8, kSignature, 8) != 0) Fail(path, "not a PNG file (bad signature)");
  // Chunks before the image data: IHDR (size, bit depth, colour type) and any colour-space chunk, which would make
  // libpng convert the samples instead of returning them as stored.
  int bit_depth = 0, color_type = -1;
  for (size_t pos = 8; pos + 8 <= bytes.size();) {
    const uint32_t length = BigEndian32(bytes, pos);
    const std::string type = bytes.substr(pos + 4, 4);
    if (length > bytes.size() || pos + 12 + length > bytes.size()) Fail(path, "truncated PNG chunk '" + type + "'");
    if (type == "IHDR") {
      if (length != 13) Fail(path, "bad PNG header chunk");
      bit_depth = static_cast<unsigned char>(bytes[pos + 16]);
      color_type = static_cast<unsigned char>(bytes[pos + 17]);
    } else if (type == "IDAT" || type == "IEND") {
      break;
    } else if (type == "sRGB" || type == "iCCP" ||
               (type == "gAMA" && (length != 4 || BigEndian32(bytes, pos + 8) != 100000))) {
      Fail(path, "PNG with a non-linear colour space ('" + type +
                     "' chunk): depth PNGs must store raw values (16-bit grayscale, no gamma)");
    }
    pos += 12 + length;
  }
  if (color_type < 0) Fail(path, "PNG without a header chunk");
  if (color_type != 0) {
    const char* kind = color_type == 2 ? "RGB" : color_type == 3 ? "palette" : color_type == 4 ? "grayscale+alpha"
                                                                                : color_type == 6 ? "RGBA" : "unknown";
    Fail(path, std::string(kind) + " PNG: depth PNGs must be single-channel 16-bit grayscale (is --depth_path the "
                                   "image folder?)");
  }
  if (bit_depth != 16) {
    Fail(path, std::to_string(bit_depth) + "-bit grayscale PNG: depth PNGs must be 16-bit (fewer bits cannot hold a "
                                           "depth map; save the model's output as .npy, .pfm or 16-bit PNG)");
  }
  png_image image;
  std::memset(&image, 0, sizeof(image));
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&image, bytes.data(), bytes.size())) {
    Fail(path, std::string("bad PNG: ") + image.message);
  }
  const uint64_t pixels = static_cast<uint64_t>(image.width) * image.height;
  if (pixels == 0 || pixels > (uint64_t{1} << 28)) {
    const std::string size = std::to_string(image.width) + "x" + std::to_string(image.height);
    png_image_free(&image);
    Fail(path, "PNG of " + size + " pixels: expected 1 to 2^28 pixels");
  }
  image.format = PNG_FORMAT_LINEAR_Y;
  std::vector<uint16_t> samples;
  try {
    samples.resize(static_cast<size_t>(pixels));
  } catch (...) {
    png_image_free(&image);
    throw;
  }
  if (!png_image_finish_read(&image, nullptr, samples.data(), 0, nullptr)) {
    Fail(path, std::string("bad PNG: ") + image.message);
  }
  DepthMap map;
  map.width = static_cast<int>(image.width);
  map.height = static_cast<int>(image.height);
  map.data.assign(samples.begin(), samples.end());
  return map;
}

void CheckWritable(const DepthMap& map, const std::string& path) {
  CheckNotEmpty(path, map.width, map.height);
  if (map.data.size() != static_cast<size_t>(map.width) * static_cast<size_t>(map.height)) {
    Fail(path, "cannot write: the map is " + std::to_string(map.width) + "x" + std::to_string(map.height) +
                   " but holds " + std::to_string(map.data.size()) + " values");
  }
}

void WriteBytes(const std::string& path, const std::string& header, const std::vector<float>& data) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) Fail(path, std::string("cannot open for writing: ") + std::strerror(errno));
  bool ok = std::fwrite(header.data(), 1, header.size(), file) == header.size();
  ok = ok && std::fwrite(data.data(), sizeof(float), data.size(), file) == data.size();
  ok = (std::fclose(file) == 0) && ok;
  if (!ok) Fail(path, "write error");
}

}  // namespace

DepthMap ReadDepthMap(const std::string& path) {
  std::error_code ec;
  const auto status = fs::status(path, ec);
  if (ec || !fs::exists(status)) Fail(path, "file does not exist");
  if (fs::is_directory(status)) Fail(path, "is a directory, not a file");
  const std::string extension = Lowercase(fs::path(path).extension().string());
  if (extension == ".npy") return ReadDepthNpy(path);
  if (extension == ".pfm") return ReadDepthPfm(path);
  if (extension == ".bin") return ReadDepthColmapBin(path);
  if (extension == ".png") return ReadDepthPng(path);
  Fail(path, "unsupported extension '" + extension + "' (expected .npy, .pfm, COLMAP .bin or 16-bit .png)");
}

std::optional<std::string> FindDepthSidecar(const std::string& depth_dir, const std::string& image_name) {
  const fs::path base = fs::path(depth_dir) / image_name;
  const std::string with_ext = base.string();
  const std::string without_ext = fs::path(base).replace_extension().string();
  const std::string candidates[] = {
      with_ext + ".npy",           without_ext + ".npy",           with_ext + ".pfm", without_ext + ".pfm",
      with_ext + ".geometric.bin", with_ext + ".photometric.bin", with_ext + ".bin",
      with_ext + ".png",           without_ext + ".png",
  };
  for (const std::string& candidate : candidates) {
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec)) return candidate;
  }
  return std::nullopt;
}

void WriteDepthMapNpy(const DepthMap& map, const std::string& path) {
  CheckWritable(map, path);
  WriteNpy(path, {static_cast<size_t>(map.height), static_cast<size_t>(map.width)}, map.data.data(),
           NpyWriteType::kFloat32);
}

void WriteDepthMapPfm(const DepthMap& map, const std::string& path) {
  CheckWritable(map, path);
  std::vector<float> flipped(map.data.size());
  for (int row = 0; row < map.height; ++row) {
    std::copy_n(map.data.data() + static_cast<size_t>(map.height - 1 - row) * map.width, map.width,
                flipped.data() + static_cast<size_t>(row) * map.width);
  }
  WriteBytes(path, "Pf\n" + std::to_string(map.width) + " " + std::to_string(map.height) + "\n-1\n", flipped);
}

void WriteDepthMapColmapBin(const DepthMap& map, const std::string& path) {
  CheckWritable(map, path);
  WriteBytes(path, std::to_string(map.width) + "&" + std::to_string(map.height) + "&1&", map.data);
}

DepthMap DisparityToDepth(const DepthMap& disparity) {
  DepthMap depth;
  depth.width = disparity.width;
  depth.height = disparity.height;
  depth.data.resize(disparity.data.size());
  for (size_t i = 0; i < disparity.data.size(); ++i) {
    const float v = disparity.data[i];
    depth.data[i] = (std::isfinite(v) && v > 0) ? 1.0f / v : std::numeric_limits<float>::quiet_NaN();
  }
  return depth;
}

}  // namespace madsfm
