#include "colmap_ext/model/reconstruction.h"

#include <Eigen/Geometry>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <type_traits>

namespace madsfm::colmap {
namespace {

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "COLMAP model files are little-endian; this reader/writer assumes a little-endian host."
#endif

namespace fs = std::filesystem;

[[noreturn]] void Fail(const std::string& path, const std::string& message) {
  throw std::runtime_error(path + ": " + message);
}

std::string ReadWholeFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) Fail(path, "cannot open file");
  const std::streamoff size = in.tellg();
  if (size < 0) Fail(path, "cannot determine the file size");
  std::string bytes(static_cast<size_t>(size), '\0');
  in.seekg(0);
  if (!in.read(bytes.data(), size)) Fail(path, "read error");
  return bytes;
}

// ---------------------------------------------------------------------------------------------------------------
// Binary reading: a bounds-checked little-endian cursor. Every count is checked against the bytes that remain
// before anything is allocated, so a corrupt count fails with a message instead of a huge allocation.

class BinaryCursor {
 public:
  BinaryCursor(const std::string& bytes, const std::string& path) : bytes_(bytes), path_(path) {}

  template <typename T>
  T Read(const char* what) {
    static_assert(std::is_trivially_copyable_v<T>);
    if (Remaining() < sizeof(T)) {
      Fail(path_, "truncated: file ends at byte " + std::to_string(bytes_.size()) + " while reading " + what +
                      " at byte " + std::to_string(pos_));
    }
    T value;
    std::memcpy(&value, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return value;
  }

  std::string ReadNulTerminated(const char* what) {
    const size_t end = bytes_.find('\0', pos_);
    if (end == std::string::npos) {
      Fail(path_, std::string("truncated: no terminating NUL for ") + what + " starting at byte " +
                      std::to_string(pos_));
    }
    std::string s = bytes_.substr(pos_, end - pos_);
    pos_ = end + 1;
    return s;
  }

  // Checks that `count` records of at least `min_bytes_each` bytes can still follow.
  void CheckCount(uint64_t count, uint64_t min_bytes_each, const std::string& what) const {
    if (min_bytes_each > 0 && count > Remaining() / min_bytes_each) {
      Fail(path_, "corrupt count: " + std::to_string(count) + " " + what + " need at least " +
                      (count > UINT64_MAX / min_bytes_each ? std::string("more than 2^64")
                                                           : std::to_string(count * min_bytes_each)) +
                      " bytes but only " + std::to_string(Remaining()) + " remain (at byte " + std::to_string(pos_) +
                      ")");
    }
  }

  void ExpectEnd() const {
    if (Remaining() != 0) {
      Fail(path_, std::to_string(Remaining()) + " unexpected trailing bytes after byte " + std::to_string(pos_));
    }
  }

  uint64_t Remaining() const { return bytes_.size() - pos_; }
  size_t pos() const { return pos_; }

 private:
  const std::string& bytes_;
  const std::string& path_;
  size_t pos_ = 0;
};

// "'name' (image_id N)": how errors name an image of the model.
std::string ImageLabel(uint32_t image_id, const ModelImage& image) {
  return "'" + image.name + "' (image_id " + std::to_string(image_id) + ")";
}

// Called once the image (name included) is read.
void CheckFiniteQvecTvec(const ModelImage& image, const std::string& path) {
  if (!image.qvec.allFinite() || !image.tvec.allFinite()) {
    Fail(path, "image " + ImageLabel(image.image_id, image) + " has a non-finite pose");
  }
  if (!(image.qvec.norm() > 1e-12)) {
    Fail(path, "image " + ImageLabel(image.image_id, image) + " has a zero quaternion");
  }
}

int CheckedDimension(uint64_t v, const std::string& path, uint32_t camera_id, const char* what) {
  if (v > static_cast<uint64_t>(INT_MAX)) {
    Fail(path, "camera " + std::to_string(camera_id) + " has an implausible " + what + " " + std::to_string(v));
  }
  return static_cast<int>(v);
}

void ReadCamerasBinary(const std::string& path, Reconstruction* model) {
  const std::string bytes = ReadWholeFile(path);
  BinaryCursor in(bytes, path);
  const uint64_t num = in.Read<uint64_t>("the number of cameras");
  in.CheckCount(num, 4 + 4 + 8 + 8, "cameras");
  for (uint64_t i = 0; i < num; ++i) {
    ModelCamera camera;
    camera.camera_id = in.Read<uint32_t>("camera_id");
    const int32_t model_id = in.Read<int32_t>("model_id");
    const uint64_t width = in.Read<uint64_t>("width");
    const uint64_t height = in.Read<uint64_t>("height");
    const int num_params = CameraModelNumParams(model_id);
    if (num_params < 0) {
      Fail(path, "camera " + std::to_string(camera.camera_id) + " has unknown camera model id " +
                     std::to_string(model_id) + " (at byte " + std::to_string(in.pos() - 20) + ")");
    }
    camera.intrinsics.model_id = model_id;
    camera.intrinsics.width = CheckedDimension(width, path, camera.camera_id, "width");
    camera.intrinsics.height = CheckedDimension(height, path, camera.camera_id, "height");
    in.CheckCount(static_cast<uint64_t>(num_params), 8, "parameters of camera " + std::to_string(camera.camera_id));
    camera.intrinsics.params.resize(static_cast<size_t>(num_params));
    for (double& p : camera.intrinsics.params) p = in.Read<double>("camera parameters");
    const uint32_t id = camera.camera_id;
    if (!model->cameras.emplace(id, std::move(camera)).second) Fail(path, "duplicate camera_id " + std::to_string(id));
  }
  in.ExpectEnd();
}

void ReadImagesBinary(const std::string& path, Reconstruction* model) {
  const std::string bytes = ReadWholeFile(path);
  BinaryCursor in(bytes, path);
  const uint64_t num = in.Read<uint64_t>("the number of images");
  // image_id, qvec, tvec, camera_id, name (>= 1 byte: its NUL), num_points2D.
  in.CheckCount(num, 4 + 7 * 8 + 4 + 1 + 8, "images");
  for (uint64_t i = 0; i < num; ++i) {
    ModelImage image;
    image.image_id = in.Read<uint32_t>("image_id");
    for (int k = 0; k < 4; ++k) image.qvec(k) = in.Read<double>("qvec");
    for (int k = 0; k < 3; ++k) image.tvec(k) = in.Read<double>("tvec");
    image.camera_id = in.Read<uint32_t>("camera_id");
    image.name = in.ReadNulTerminated("the image name");
    const uint64_t num_points2D = in.Read<uint64_t>("the number of points2D");
    in.CheckCount(num_points2D, 8 + 8 + 8, "points2D of image " + std::to_string(image.image_id));
    image.points2D.resize(static_cast<size_t>(num_points2D));
    image.point3D_ids.resize(static_cast<size_t>(num_points2D));
    for (uint64_t k = 0; k < num_points2D; ++k) {
      image.points2D[k].x() = in.Read<double>("point2D x");
      image.points2D[k].y() = in.Read<double>("point2D y");
      image.point3D_ids[k] = in.Read<uint64_t>("point3D_id");
    }
    CheckFiniteQvecTvec(image, path);
    const uint32_t id = image.image_id;
    if (!model->images.emplace(id, std::move(image)).second) Fail(path, "duplicate image_id " + std::to_string(id));
  }
  in.ExpectEnd();
}

void ReadPoints3DBinary(const std::string& path, Reconstruction* model) {
  const std::string bytes = ReadWholeFile(path);
  BinaryCursor in(bytes, path);
  const uint64_t num = in.Read<uint64_t>("the number of 3-D points");
  in.CheckCount(num, 8 + 3 * 8 + 3 + 8 + 8, "3-D points");
  for (uint64_t i = 0; i < num; ++i) {
    ModelPoint3D point;
    const uint64_t id = in.Read<uint64_t>("point3D_id");
    for (int k = 0; k < 3; ++k) point.xyz(k) = in.Read<double>("xyz");
    for (int k = 0; k < 3; ++k) point.rgb[k] = in.Read<uint8_t>("rgb");
    point.error = in.Read<double>("error");
    const uint64_t track_length = in.Read<uint64_t>("track length");
    in.CheckCount(track_length, 8, "track elements of 3-D point " + std::to_string(id));
    point.track.resize(static_cast<size_t>(track_length));
    for (auto& element : point.track) {
      element.first = in.Read<uint32_t>("track image_id");
      element.second = in.Read<uint32_t>("track point2D_idx");
    }
    if (id == kInvalidPoint3DId) Fail(path, "3-D point with the invalid id 2^64-1");
    if (!model->points3D.emplace(id, std::move(point)).second) {
      Fail(path, "duplicate point3D_id " + std::to_string(id));
    }
  }
  in.ExpectEnd();
}

// ---------------------------------------------------------------------------------------------------------------
// Text reading.

std::vector<std::string> SplitWhitespace(const std::string& line) {
  std::vector<std::string> tokens;
  size_t pos = 0;
  while (true) {
    pos = line.find_first_not_of(" \t\r\n", pos);
    if (pos == std::string::npos) break;
    const size_t end = line.find_first_of(" \t\r\n", pos);
    tokens.push_back(line.substr(pos, end == std::string::npos ? std::string::npos : end - pos));
    if (end == std::string::npos) break;
    pos = end;
  }
  return tokens;
}

std::string Trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const size_t e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

class TextFile {
 public:
  explicit TextFile(const std::string& path) : path_(path), in_(path) {
    if (!in_) Fail(path, "cannot open file");
  }

  // Next line (trimmed); false at end of file.
  bool NextLine(std::string* line) {
    if (!std::getline(in_, *line)) {
      if (in_.bad()) Fail(path_, "read error");
      return false;
    }
    ++line_number_;
    *line = Trim(*line);
    return true;
  }

  [[noreturn]] void Error(const std::string& message) const {
    Fail(path_, "line " + std::to_string(line_number_) + ": " + message);
  }

  uint64_t ParseUnsigned(const std::string& token, uint64_t max_value, const char* what) const {
    if (token.empty() || token[0] == '-' || token[0] == '+') Error(std::string("bad ") + what + " '" + token + "'");
    char* end = nullptr;
    errno = 0;
    const unsigned long long v = std::strtoull(token.c_str(), &end, 10);
    if (*end != '\0' || errno != 0 || v > max_value) Error(std::string("bad ") + what + " '" + token + "'");
    return static_cast<uint64_t>(v);
  }

  double ParseDouble(const std::string& token, const char* what) const {
    char* end = nullptr;
    const double v = std::strtod(token.c_str(), &end);
    if (token.empty() || *end != '\0') Error(std::string("bad ") + what + " '" + token + "'");
    return v;
  }

  // Value of a COLMAP header comment "# <key>: N[, ...]" if this line is one, else -1.
  static int64_t HeaderCount(const std::string& line, const std::string& key) {
    const std::string prefix = "# " + key + ": ";
    if (line.rfind(prefix, 0) != 0) return -1;
    const std::string rest = line.substr(prefix.size());
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(rest.c_str(), &end, 10);
    if (end == rest.c_str() || errno != 0 || v < 0 || (*end != '\0' && *end != ',')) return -1;
    return v;
  }

  void CheckHeaderCount(int64_t header_count, size_t actual, const char* what) const {
    if (header_count >= 0 && static_cast<uint64_t>(header_count) != actual) {
      Fail(path_, "the header announces " + std::to_string(header_count) + " " + what + " but the file holds " +
                      std::to_string(actual) + " (truncated or edited?)");
    }
  }

  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::ifstream in_;
  size_t line_number_ = 0;
};

void ReadCamerasText(const std::string& path, Reconstruction* model) {
  TextFile file(path);
  std::string line;
  int64_t header_count = -1;
  while (file.NextLine(&line)) {
    if (line.empty()) continue;
    if (line[0] == '#') {
      const int64_t c = TextFile::HeaderCount(line, "Number of cameras");
      if (c >= 0) header_count = c;
      continue;
    }
    const std::vector<std::string> tok = SplitWhitespace(line);
    if (tok.size() < 4) file.Error("expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS[]");
    ModelCamera camera;
    camera.camera_id = static_cast<uint32_t>(file.ParseUnsigned(tok[0], UINT32_MAX, "camera id"));
    camera.intrinsics.model_id = CameraModelId(tok[1]);
    const int num_params = CameraModelNumParams(camera.intrinsics.model_id);
    if (camera.intrinsics.model_id < 0 || num_params < 0) file.Error("unknown camera model '" + tok[1] + "'");
    camera.intrinsics.width = static_cast<int>(file.ParseUnsigned(tok[2], INT_MAX, "width"));
    camera.intrinsics.height = static_cast<int>(file.ParseUnsigned(tok[3], INT_MAX, "height"));
    if (tok.size() != static_cast<size_t>(4 + num_params)) {
      file.Error("camera model " + tok[1] + " needs " + std::to_string(num_params) + " parameters, got " +
                 std::to_string(tok.size() - 4));
    }
    for (int k = 0; k < num_params; ++k) camera.intrinsics.params.push_back(file.ParseDouble(tok[4 + k], "parameter"));
    const uint32_t id = camera.camera_id;
    if (!model->cameras.emplace(id, std::move(camera)).second) file.Error("duplicate camera id " + std::to_string(id));
  }
  file.CheckHeaderCount(header_count, model->cameras.size(), "cameras");
}

void ReadImagesText(const std::string& path, Reconstruction* model) {
  TextFile file(path);
  std::string line;
  int64_t header_count = -1;
  while (file.NextLine(&line)) {
    if (line.empty()) continue;
    if (line[0] == '#') {
      const int64_t c = TextFile::HeaderCount(line, "Number of images");
      if (c >= 0) header_count = c;
      continue;
    }
    const std::vector<std::string> tok = SplitWhitespace(line);
    if (tok.size() != 10) {
      file.Error("expected IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME (10 fields, names without spaces), got " +
                 std::to_string(tok.size()) + " fields");
    }
    ModelImage image;
    image.image_id = static_cast<uint32_t>(file.ParseUnsigned(tok[0], UINT32_MAX, "image id"));
    for (int k = 0; k < 4; ++k) image.qvec(k) = file.ParseDouble(tok[1 + k], "quaternion component");
    for (int k = 0; k < 3; ++k) image.tvec(k) = file.ParseDouble(tok[5 + k], "translation component");
    image.camera_id = static_cast<uint32_t>(file.ParseUnsigned(tok[8], UINT32_MAX, "camera id"));
    image.name = tok[9];
    if (!image.qvec.allFinite() || !image.tvec.allFinite()) file.Error("non-finite pose");
    if (!(image.qvec.norm() > 1e-12)) file.Error("zero quaternion");
    // The second line of every image holds its points2D (possibly empty), as COLMAP writes it.
    if (!file.NextLine(&line)) {
      file.Error("file ends before the POINTS2D line of image " + std::to_string(image.image_id));
    }
    const std::vector<std::string> pts = SplitWhitespace(line);
    if (pts.size() % 3 != 0) file.Error("POINTS2D line must hold (X, Y, POINT3D_ID) triplets");
    image.points2D.reserve(pts.size() / 3);
    image.point3D_ids.reserve(pts.size() / 3);
    for (size_t k = 0; k < pts.size(); k += 3) {
      image.points2D.emplace_back(file.ParseDouble(pts[k], "point2D x"), file.ParseDouble(pts[k + 1], "point2D y"));
      if (pts[k + 2] == "-1") {
        image.point3D_ids.push_back(kInvalidPoint3DId);
      } else {
        image.point3D_ids.push_back(file.ParseUnsigned(pts[k + 2], UINT64_MAX, "point3D id"));
      }
    }
    const uint32_t id = image.image_id;
    if (!model->images.emplace(id, std::move(image)).second) file.Error("duplicate image id " + std::to_string(id));
  }
  file.CheckHeaderCount(header_count, model->images.size(), "images");
}

void ReadPoints3DText(const std::string& path, Reconstruction* model) {
  TextFile file(path);
  std::string line;
  int64_t header_count = -1;
  while (file.NextLine(&line)) {
    if (line.empty()) continue;
    if (line[0] == '#') {
      const int64_t c = TextFile::HeaderCount(line, "Number of points");
      if (c >= 0) header_count = c;
      continue;
    }
    const std::vector<std::string> tok = SplitWhitespace(line);
    if (tok.size() < 8 || (tok.size() - 8) % 2 != 0) {
      file.Error("expected POINT3D_ID X Y Z R G B ERROR (IMAGE_ID POINT2D_IDX)...");
    }
    ModelPoint3D point;
    const uint64_t id = file.ParseUnsigned(tok[0], UINT64_MAX - 1, "point3D id");
    for (int k = 0; k < 3; ++k) point.xyz(k) = file.ParseDouble(tok[1 + k], "coordinate");
    for (int k = 0; k < 3; ++k) point.rgb[k] = static_cast<uint8_t>(file.ParseUnsigned(tok[4 + k], 255, "colour"));
    point.error = file.ParseDouble(tok[7], "error");
    point.track.reserve((tok.size() - 8) / 2);
    for (size_t k = 8; k < tok.size(); k += 2) {
      point.track.emplace_back(static_cast<uint32_t>(file.ParseUnsigned(tok[k], UINT32_MAX, "track image id")),
                               static_cast<uint32_t>(file.ParseUnsigned(tok[k + 1], UINT32_MAX, "track point2D idx")));
    }
    if (!model->points3D.emplace(id, std::move(point)).second) file.Error("duplicate point3D id " + std::to_string(id));
  }
  file.CheckHeaderCount(header_count, model->points3D.size(), "points");
}

// Cross-file references: cameras of images, 3-D points of points2D, and tracks.
void CheckConsistency(const Reconstruction& model, const std::string& cameras_path, const std::string& images_path,
                      const std::string& points_path) {
  const std::string cameras_file = fs::path(cameras_path).filename().string();
  const std::string images_file = fs::path(images_path).filename().string();
  const std::string points_file = fs::path(points_path).filename().string();
  size_t num_observations = 0;
  std::map<uint32_t, std::vector<bool>> claimed;  // points2D already claimed by a track element
  for (const auto& [image_id, image] : model.images) {
    if (model.cameras.count(image.camera_id) == 0) {
      Fail(images_path, "image " + ImageLabel(image_id, image) + " uses camera_id " + std::to_string(image.camera_id) +
                            ", which " + cameras_file + " does not contain");
    }
    for (const uint64_t id : image.point3D_ids) num_observations += id != kInvalidPoint3DId;
    claimed[image_id].assign(image.point3D_ids.size(), false);
  }
  // Every track element must name a distinct point2D that refers back to its 3-D point.
  size_t num_track_elements = 0;
  for (const auto& [point_id, point] : model.points3D) {
    for (const auto& [image_id, point2D_idx] : point.track) {
      const auto it = model.images.find(image_id);
      if (it == model.images.end()) {
        Fail(points_path, "3-D point " + std::to_string(point_id) + " is observed in image " +
                              std::to_string(image_id) + ", which " + images_file + " does not contain");
      }
      if (point2D_idx >= it->second.point3D_ids.size() || it->second.point3D_ids[point2D_idx] != point_id) {
        Fail(points_path, "3-D point " + std::to_string(point_id) + " track element (" + std::to_string(image_id) +
                              ", " + std::to_string(point2D_idx) + ") does not match point2D " +
                              std::to_string(point2D_idx) + " of image " + ImageLabel(image_id, it->second) + " in " +
                              images_file);
      }
      std::vector<bool>& flags = claimed[image_id];
      if (flags[point2D_idx]) {
        Fail(points_path, "3-D point " + std::to_string(point_id) + " lists track element (" +
                              std::to_string(image_id) + ", " + std::to_string(point2D_idx) + ") twice");
      }
      flags[point2D_idx] = true;
      ++num_track_elements;
    }
  }
  // Track elements map one-to-one onto points2D with a 3-D point; if some of those are unclaimed, name one.
  if (num_track_elements == num_observations) return;
  for (const auto& [image_id, image] : model.images) {
    const std::vector<bool>& flags = claimed[image_id];
    for (size_t k = 0; k < image.point3D_ids.size(); ++k) {
      const uint64_t id = image.point3D_ids[k];
      if (id == kInvalidPoint3DId || flags[k]) continue;
      if (model.points3D.count(id) == 0) {
        Fail(images_path, "image " + ImageLabel(image_id, image) + " point2D " + std::to_string(k) +
                              " refers to 3-D point " + std::to_string(id) + ", which " + points_file +
                              " does not contain");
      }
      Fail(images_path, "image " + ImageLabel(image_id, image) + " point2D " + std::to_string(k) +
                            " refers to 3-D point " + std::to_string(id) + ", whose track in " + points_file +
                            " does not list it");
    }
  }
}

// ---------------------------------------------------------------------------------------------------------------
// Writing.

// "camera_id N (used by 'a.png', 'b.png')": how the writers' errors name a camera of the model.
std::string CameraLabel(const Reconstruction& model, uint32_t camera_id) {
  std::string names;
  int count = 0;
  for (const auto& [image_id, image] : model.images) {
    if (image.camera_id != camera_id) continue;
    if (count < 3) names += (count > 0 ? ", '" : "'") + image.name + "'";
    ++count;
  }
  if (count > 3) names += " and " + std::to_string(count - 3) + " more";
  return "camera_id " + std::to_string(camera_id) + (count > 0 ? " (used by " + names + ")" : " (used by no image)");
}

void CheckWritable(const Reconstruction& model) {
  for (const auto& [id, camera] : model.cameras) {
    const int n = CameraModelNumParams(camera.intrinsics.model_id);
    if (n < 0) {
      throw std::invalid_argument(CameraLabel(model, id) + " has unknown model id " +
                                  std::to_string(camera.intrinsics.model_id));
    }
    if (camera.intrinsics.params.size() != static_cast<size_t>(n)) {
      throw std::invalid_argument(CameraLabel(model, id) + " (" + CameraModelName(camera.intrinsics.model_id) +
                                  ") has " + std::to_string(camera.intrinsics.params.size()) + " parameters, needs " +
                                  std::to_string(n));
    }
    if (camera.intrinsics.width < 0 || camera.intrinsics.height < 0) {
      throw std::invalid_argument(CameraLabel(model, id) + " has a negative size");
    }
  }
  for (const auto& [id, image] : model.images) {
    if (image.points2D.size() != image.point3D_ids.size()) {
      throw std::invalid_argument("image " + ImageLabel(id, image) + ": points2D and point3D_ids differ in size");
    }
    if (image.name.empty() || image.name.find('\0') != std::string::npos) {
      throw std::invalid_argument("image " + std::to_string(id) + " has an empty name or one containing NUL");
    }
  }
}

class BinaryWriter {
 public:
  explicit BinaryWriter(const std::string& path) : path_(path), out_(path, std::ios::binary | std::ios::trunc) {
    if (!out_) Fail(path, "cannot create file");
  }
  template <typename T>
  void Write(T value) {
    static_assert(std::is_trivially_copyable_v<T>);
    out_.write(reinterpret_cast<const char*>(&value), sizeof(T));
  }
  void WriteString(const std::string& s) { out_.write(s.c_str(), static_cast<std::streamsize>(s.size() + 1)); }
  void Close() {
    out_.close();
    if (!out_) Fail(path_, "write error");
  }

 private:
  std::string path_;
  std::ofstream out_;
};

class TextWriter {
 public:
  explicit TextWriter(const std::string& path) : path_(path), out_(path, std::ios::trunc) {
    if (!out_) Fail(path, "cannot create file");
    out_.precision(17);  // as COLMAP: doubles survive the text round trip exactly
  }
  std::ofstream& out() { return out_; }
  void Close() {
    out_.close();
    if (!out_) Fail(path_, "write error");
  }

 private:
  std::string path_;
  std::ofstream out_;
};

std::string JoinPath(const std::string& dir, const char* name) { return (fs::path(dir) / name).string(); }

void CreateDirectory(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) Fail(dir, "cannot create directory" + (ec ? ": " + ec.message() : ""));
}

}  // namespace

Reconstruction ReadReconstruction(const std::string& dir) {
  if (!fs::is_directory(dir)) Fail(dir, "model directory does not exist");
  const char* kNames[3] = {"cameras", "images", "points3D"};
  for (const char* ext : {".bin", ".txt"}) {
    std::string paths[3];
    int present = 0;
    for (int i = 0; i < 3; ++i) {
      paths[i] = JoinPath(dir, (std::string(kNames[i]) + ext).c_str());
      present += fs::exists(paths[i]);
    }
    if (present == 0) continue;
    for (int i = 0; i < 3; ++i) {
      if (!fs::exists(paths[i])) Fail(paths[i], "missing (the other " + std::string(ext) + " model files exist)");
    }
    Reconstruction model;
    if (std::string(ext) == ".bin") {
      ReadCamerasBinary(paths[0], &model);
      ReadImagesBinary(paths[1], &model);
      ReadPoints3DBinary(paths[2], &model);
    } else {
      ReadCamerasText(paths[0], &model);
      ReadImagesText(paths[1], &model);
      ReadPoints3DText(paths[2], &model);
    }
    CheckConsistency(model, paths[0], paths[1], paths[2]);
    return model;
  }
  Fail(dir, "no COLMAP model: neither cameras.bin/images.bin/points3D.bin nor the .txt files exist");
}

void WriteReconstructionBinary(const Reconstruction& model, const std::string& dir) {
  CheckWritable(model);
  CreateDirectory(dir);
  {
    BinaryWriter out(JoinPath(dir, "cameras.bin"));
    out.Write<uint64_t>(model.cameras.size());
    for (const auto& [id, camera] : model.cameras) {
      out.Write<uint32_t>(id);
      out.Write<int32_t>(camera.intrinsics.model_id);
      out.Write<uint64_t>(static_cast<uint64_t>(camera.intrinsics.width));
      out.Write<uint64_t>(static_cast<uint64_t>(camera.intrinsics.height));
      for (const double p : camera.intrinsics.params) out.Write<double>(p);
    }
    out.Close();
  }
  {
    BinaryWriter out(JoinPath(dir, "images.bin"));
    out.Write<uint64_t>(model.images.size());
    for (const auto& [id, image] : model.images) {
      out.Write<uint32_t>(id);
      for (int k = 0; k < 4; ++k) out.Write<double>(image.qvec(k));
      for (int k = 0; k < 3; ++k) out.Write<double>(image.tvec(k));
      out.Write<uint32_t>(image.camera_id);
      out.WriteString(image.name);
      out.Write<uint64_t>(image.points2D.size());
      for (size_t k = 0; k < image.points2D.size(); ++k) {
        out.Write<double>(image.points2D[k].x());
        out.Write<double>(image.points2D[k].y());
        out.Write<uint64_t>(image.point3D_ids[k]);
      }
    }
    out.Close();
  }
  {
    BinaryWriter out(JoinPath(dir, "points3D.bin"));
    out.Write<uint64_t>(model.points3D.size());
    for (const auto& [id, point] : model.points3D) {
      out.Write<uint64_t>(id);
      for (int k = 0; k < 3; ++k) out.Write<double>(point.xyz(k));
      for (int k = 0; k < 3; ++k) out.Write<uint8_t>(point.rgb[k]);
      out.Write<double>(point.error);
      out.Write<uint64_t>(point.track.size());
      for (const auto& [image_id, point2D_idx] : point.track) {
        out.Write<uint32_t>(image_id);
        out.Write<uint32_t>(point2D_idx);
      }
    }
    out.Close();
  }
}

void WriteReconstructionText(const Reconstruction& model, const std::string& dir) {
  CheckWritable(model);
  for (const auto& [id, image] : model.images) {
    if (image.name.find_first_of(" \t\r\n") != std::string::npos) {
      throw std::invalid_argument("image " + std::to_string(id) + " name '" + image.name +
                                  "' contains whitespace, which the text format cannot hold");
    }
  }
  CreateDirectory(dir);
  {
    TextWriter writer(JoinPath(dir, "cameras.txt"));
    std::ofstream& out = writer.out();
    out << "# Camera list with one line of data per camera:\n";
    out << "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n";
    out << "# Number of cameras: " << model.cameras.size() << "\n";
    for (const auto& [id, camera] : model.cameras) {
      out << id << " " << CameraModelName(camera.intrinsics.model_id) << " " << camera.intrinsics.width << " "
          << camera.intrinsics.height;
      for (const double p : camera.intrinsics.params) out << " " << p;
      out << "\n";
    }
    writer.Close();
  }
  {
    size_t num_observations = 0;
    for (const auto& [id, image] : model.images) {
      for (const uint64_t p : image.point3D_ids) num_observations += p != kInvalidPoint3DId;
    }
    const double mean_observations =
        model.images.empty() ? 0.0 : static_cast<double>(num_observations) / static_cast<double>(model.images.size());
    TextWriter writer(JoinPath(dir, "images.txt"));
    std::ofstream& out = writer.out();
    out << "# Image list with two lines of data per image:\n";
    out << "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n";
    out << "#   POINTS2D[] as (X, Y, POINT3D_ID)\n";
    out << "# Number of images: " << model.images.size() << ", mean observations per image: " << mean_observations
        << "\n";
    for (const auto& [id, image] : model.images) {
      out << id;
      for (int k = 0; k < 4; ++k) out << " " << image.qvec(k);
      for (int k = 0; k < 3; ++k) out << " " << image.tvec(k);
      out << " " << image.camera_id << " " << image.name << "\n";
      for (size_t k = 0; k < image.points2D.size(); ++k) {
        if (k > 0) out << " ";
        out << image.points2D[k].x() << " " << image.points2D[k].y() << " ";
        if (image.point3D_ids[k] == kInvalidPoint3DId) {
          out << -1;
        } else {
          out << image.point3D_ids[k];
        }
      }
      out << "\n";
    }
    writer.Close();
  }
  {
    size_t track_sum = 0;
    for (const auto& [id, point] : model.points3D) track_sum += point.track.size();
    const double mean_track =
        model.points3D.empty() ? 0.0 : static_cast<double>(track_sum) / static_cast<double>(model.points3D.size());
    TextWriter writer(JoinPath(dir, "points3D.txt"));
    std::ofstream& out = writer.out();
    out << "# 3D point list with one line of data per point:\n";
    out << "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n";
    out << "# Number of points: " << model.points3D.size() << ", mean track length: " << mean_track << "\n";
    for (const auto& [id, point] : model.points3D) {
      out << id << " " << point.xyz(0) << " " << point.xyz(1) << " " << point.xyz(2) << " "
          << static_cast<int>(point.rgb[0]) << " " << static_cast<int>(point.rgb[1]) << " "
          << static_cast<int>(point.rgb[2]) << " " << point.error;
      for (const auto& [image_id, point2D_idx] : point.track) out << " " << image_id << " " << point2D_idx;
      out << "\n";
    }
    writer.Close();
  }
}

Eigen::Matrix3d QuaternionToRotation(const Eigen::Vector4d& qvec) {
  // COLMAP normalises the quaternion first; (w, x, y, z) order.
  const Eigen::Vector4d q = qvec.normalized();
  return Eigen::Quaterniond(q(0), q(1), q(2), q(3)).toRotationMatrix();
}

Eigen::Vector4d RotationToQuaternion(const Eigen::Matrix3d& R) {
  // Unit quaternion with w >= 0 (q and -q are the same rotation; this picks one).
  const Eigen::Quaterniond q(R);
  Eigen::Vector4d v(q.w(), q.x(), q.y(), q.z());
  v.normalize();
  if (v(0) < 0) v = -v;
  return v;
}

}  // namespace madsfm::colmap
