#include "madsfm/io/pair_directory.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "madsfm/io/depth_map_io.h"
#include "madsfm/io/depth_sampling.h"
#include "madsfm/io/json_writer.h"
#include "madsfm/io/npy.h"

namespace madsfm {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

[[noreturn]] void Fail(const std::string& what, const std::string& path, const std::string& problem) {
  throw std::runtime_error(what + " '" + path + "': " + problem);
}

bool Exists(const std::string& path) {
  std::error_code ec;
  return fs::exists(path, ec);
}

bool IsRegularFile(const std::string& path) {
  std::error_code ec;
  return fs::is_regular_file(path, ec);
}

bool IsDirectory(const std::string& path) {
  std::error_code ec;
  return fs::is_directory(path, ec);
}

bool IsPairDirectory(const std::string& path) {
  return IsDirectory(path) && IsRegularFile((fs::path(path) / "info.json").string());
}

std::string Resolve(const std::string& dir, const std::string& name) {
  const fs::path p(name);
  return p.is_absolute() ? name : (fs::path(dir) / p).string();
}

json ReadJson(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) Fail("pair file", path, "cannot open");
  std::stringstream buffer;
  buffer << in.rdbuf();
  try {
    return json::parse(buffer.str());
  } catch (const json::exception& e) {
    Fail("pair file", path, std::string("invalid JSON (") + e.what() + ")");
  }
}

// Reads a rows x cols matrix given as nested arrays [[...], ...] or as a flat row-major array.
// `shape_text` describes the accepted shapes in error messages (default "<rows>x<cols>").
Eigen::MatrixXd ReadMatrix(const json& value, const std::string& key, int rows, int cols, const std::string& file,
                           const std::string& shape_text = "") {
  const std::string shape = shape_text.empty() ? std::to_string(rows) + "x" + std::to_string(cols) : shape_text;
  std::vector<double> values;
  auto add_number = [&](const json& v) {
    if (!v.is_number()) Fail("pair file", file, "'" + key + "' must hold numbers");
    values.push_back(v.get<double>());
  };
  if (!value.is_array()) Fail("pair file", file, "'" + key + "' must be a " + shape + " array");
  if (value.size() == static_cast<size_t>(rows) && value[0].is_array()) {
    for (const json& row : value) {
      if (!row.is_array() || row.size() != static_cast<size_t>(cols)) {
        Fail("pair file", file, "'" + key + "' must be a " + shape + " array");
      }
      for (const json& v : row) add_number(v);
    }
  } else if (value.size() == static_cast<size_t>(rows * cols)) {
    for (const json& v : value) add_number(v);
  } else {
    Fail("pair file", file, "'" + key + "' must be a " + shape + " array");
  }
  Eigen::MatrixXd m(rows, cols);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) m(r, c) = values[static_cast<size_t>(r) * cols + c];
  }
  if (!m.allFinite()) Fail("pair file", file, "'" + key + "' has non-finite entries");
  return m;
}

Eigen::Matrix3d ReadIntrinsics(const json& info, const std::string& key, const std::string& file) {
  if (!info.contains(key)) Fail("pair file", file, "missing key '" + key + "'");
  const Eigen::Matrix3d K = ReadMatrix(info[key], key, 3, 3, file);
  if (!(K(0, 0) > 0 && K(1, 1) > 0)) Fail("pair file", file, "'" + key + "' must have positive focal lengths");
  if (std::abs(K(2, 0)) > 1e-9 || std::abs(K(2, 1)) > 1e-9 || std::abs(K(2, 2) - 1.0) > 1e-9) {
    Fail("pair file", file, "'" + key + "' must have the last row (0, 0, 1)");
  }
  return K;
}

Eigen::Matrix4d ReadPose(const json& value, const std::string& file) {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  if (value.is_array() && (value.size() == 3 || value.size() == 12)) {
    T.topRows<3>() = ReadMatrix(value, "T_0to1", 3, 4, file, "4x4 (or 3x4)");
  } else {
    T = ReadMatrix(value, "T_0to1", 4, 4, file, "4x4 (or 3x4)");
  }
  const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
  const double bottom_error = (T.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff();
  const double orthogonality_error = (R * R.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (bottom_error > 1e-6 || orthogonality_error > 1e-3 || R.determinant() <= 0) {
    Fail("pair file", file, "'T_0to1' is not a rigid transform [R t; 0 0 0 1] with R a rotation");
  }
  return T;
}

std::vector<Eigen::Vector2d> ReadMatches(const std::string& path) {
  if (!Exists(path)) Fail("matches file", path, "file does not exist");
  const NpyArray array = ReadNpy(path, "matches file");
  if (array.shape.size() != 2 || array.shape[1] != 2) {
    Fail("matches file", path, "expected an N x 2 array, got shape " + FormatNpyShape(array.shape));
  }
  std::vector<Eigen::Vector2d> points(array.shape[0]);
  for (size_t i = 0; i < points.size(); ++i) {
    points[i] = Eigen::Vector2d(array.data[2 * i], array.data[2 * i + 1]);
    if (!points[i].allFinite()) Fail("matches file", path, "row " + std::to_string(i) + " is not finite");
  }
  return points;
}

// Width and height from the IHDR chunk of a PNG file.
bool ReadPngSize(const std::string& path, int* width, int* height) {
  std::ifstream in(path, std::ios::binary);
  if (!in) Fail("image file", path, "cannot open");
  unsigned char bytes[24];
  if (!in.read(reinterpret_cast<char*>(bytes), sizeof(bytes))) {
    Fail("image file", path, "not a PNG file (too short)");
  }
  static const unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (!std::equal(kSignature, kSignature + 8, bytes) || !std::equal(bytes + 12, bytes + 16, "IHDR")) {
    Fail("image file", path, "not a PNG file (bad signature or no IHDR chunk)");
  }
  auto big_endian = [&](int offset) {
    return (uint32_t{bytes[offset]} << 24) | (uint32_t{bytes[offset + 1]} << 16) |
           (uint32_t{bytes[offset + 2]} << 8) | uint32_t{bytes[offset + 3]};
  };
  const uint32_t w = big_endian(16), h = big_endian(20);
  if (w == 0 || h == 0 || w > 0x7fffffffu || h > 0x7fffffffu) {
    Fail("image file", path, "invalid PNG size " + std::to_string(w) + "x" + std::to_string(h));
  }
  *width = static_cast<int>(w);
  *height = static_cast<int>(h);
  return true;
}

// The optional file named by `key`: nullopt when the key is absent or null.
std::optional<std::string> OptionalFile(const json& info, const std::string& key, const std::string& dir,
                                        const std::string& file) {
  if (!info.contains(key) || info[key].is_null()) return std::nullopt;
  if (!info[key].is_string() || info[key].get<std::string>().empty()) {
    Fail("pair file", file, "'" + key + "' must be a non-empty file name");
  }
  return Resolve(dir, info[key].get<std::string>());
}

std::string RequiredFile(const json& info, const std::string& key, const std::string& dir, const std::string& file) {
  const std::optional<std::string> path = OptionalFile(info, key, dir, file);
  if (!path) Fail("pair file", file, "missing key '" + key + "'");
  return *path;
}

void ReadImageSize(const json& info, int index, const std::string& dir, const std::string& file,
                   const std::optional<DepthMap>& depth, int* width, int* height) {
  const std::string key = "image_size_" + std::to_string(index);
  if (info.contains(key)) {
    const json& v = info[key];
    bool ok = v.is_array() && v.size() == 2 && v[0].is_number() && v[1].is_number();
    if (ok) {
      const double w = v[0].get<double>(), h = v[1].get<double>();
      ok = w >= 1 && h >= 1 && w <= 1e9 && h <= 1e9 && w == std::floor(w) && h == std::floor(h);
      if (ok) {  // converted only once in range (a double beyond int's range is undefined behaviour)
        *width = static_cast<int>(w);
        *height = static_cast<int>(h);
      }
    }
    if (!ok) Fail("pair file", file, "'" + key + "' must be [width, height] with positive integers");
    return;
  }
  const std::string png = (fs::path(dir) / ("image" + std::to_string(index) + ".png")).string();
  if (IsRegularFile(png)) {
    ReadPngSize(png, width, height);
    return;
  }
  if (depth) {
    *width = depth->width;
    *height = depth->height;
    return;
  }
  Fail("pair directory", dir, "cannot determine the size of image " + std::to_string(index) + ": no '" + key +
                                  "' in info.json, no image" + std::to_string(index) + ".png and no depth map");
}

// Creates the parent directory of a file to be written (names may contain subdirectories).
void CreateParent(const std::string& path) {
  std::error_code ec;
  const fs::path parent = fs::path(path).parent_path();
  if (!parent.empty()) fs::create_directories(parent, ec);
}

void WriteDepth(const DepthMap& map, const std::string& path) {
  CreateParent(path);
  std::string extension = fs::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".pfm") {
    WriteDepthMapPfm(map, path);
  } else if (extension == ".bin") {
    WriteDepthMapColmapBin(map, path);
  } else {
    WriteDepthMapNpy(map, path);
  }
}

json MatrixToJson(const Eigen::MatrixXd& m) {
  json rows = json::array();
  for (int r = 0; r < m.rows(); ++r) {
    json row = json::array();
    for (int c = 0; c < m.cols(); ++c) row.push_back(m(r, c));
    rows.push_back(row);
  }
  return rows;
}

void WriteMatches(const std::vector<Eigen::Vector2d>& points, const std::string& path) {
  CreateParent(path);
  std::vector<double> flat(2 * points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    flat[2 * i] = points[i].x();
    flat[2 * i + 1] = points[i].y();
  }
  WriteNpy(path, {points.size(), 2}, flat.data(), NpyWriteType::kFloat64);
}

}  // namespace

PairData ReadPairDirectory(const std::string& dir, const PairReadOptions& options) {
  if (!IsDirectory(dir)) Fail("pair directory", dir, Exists(dir) ? "is not a directory" : "does not exist");
  const std::string info_path = (fs::path(dir) / "info.json").string();
  if (!IsRegularFile(info_path)) Fail("pair directory", dir, "no info.json");
  const json info = ReadJson(info_path);
  if (!info.is_object()) Fail("pair file", info_path, "expected a JSON object");

  PairData pair;
  pair.path = dir;
  pair.K0 = ReadIntrinsics(info, "K0", info_path);
  pair.K1 = ReadIntrinsics(info, "K1", info_path);
  if (info.contains("T_0to1") && !info["T_0to1"].is_null()) pair.T_0to1 = ReadPose(info["T_0to1"], info_path);

  const std::string matches0 = RequiredFile(info, "matches_0_file", dir, info_path);
  const std::string matches1 = RequiredFile(info, "matches_1_file", dir, info_path);
  pair.p0 = ReadMatches(matches0);
  pair.p1 = ReadMatches(matches1);
  if (pair.p0.size() != pair.p1.size()) {
    Fail("matches file", matches1, "has " + std::to_string(pair.p1.size()) + " rows but '" + matches0 + "' has " +
                                       std::to_string(pair.p0.size()));
  }

  std::optional<DepthMap>* depths[2] = {&pair.depth0, &pair.depth1};
  std::string depth_paths[2];
  for (int i = 0; i < 2; ++i) {
    const std::string key = "depth_" + std::to_string(i) + "_file";
    const std::optional<std::string> depth_path = OptionalFile(info, key, dir, info_path);
    if (!depth_path) continue;
    if (!Exists(*depth_path)) {
      const std::string problem = "named by '" + key + "' in '" + info_path + "' but does not exist";
      if (!options.allow_missing_depth) Fail("depth file", *depth_path, problem);
      pair.warnings.push_back("depth file '" + *depth_path + "': " + problem);
      continue;
    }
    *depths[i] = ReadDepthMap(*depth_path);
    depth_paths[i] = *depth_path;
  }
  std::optional<DepthMap>* gt_depths[2] = {&pair.gt_depth0, &pair.gt_depth1};
  std::string gt_paths[2];
  for (int i = 0; i < 2; ++i) {
    const std::optional<std::string> path = OptionalFile(info, "gt_depth_" + std::to_string(i) + "_file", dir, info_path);
    if (!path) continue;
    *gt_depths[i] = ReadDepthMap(*path);
    gt_paths[i] = *path;
  }

  ReadImageSize(info, 0, dir, info_path, pair.depth0, &pair.width0, &pair.height0);
  ReadImageSize(info, 1, dir, info_path, pair.depth1, &pair.width1, &pair.height1);
  if (pair.depth0) CheckAspectRatio(*pair.depth0, pair.width0, pair.height0, depth_paths[0]);
  if (pair.depth1) CheckAspectRatio(*pair.depth1, pair.width1, pair.height1, depth_paths[1]);
  if (pair.gt_depth0) CheckAspectRatio(*pair.gt_depth0, pair.width0, pair.height0, gt_paths[0]);
  if (pair.gt_depth1) CheckAspectRatio(*pair.gt_depth1, pair.width1, pair.height1, gt_paths[1]);
  return pair;
}

std::vector<std::string> ReadPairList(const std::string& path) {
  if (!Exists(path)) Fail("pair list", path, "does not exist");
  if (IsPairDirectory(path)) return {path};
  std::vector<std::string> dirs;
  if (IsDirectory(path)) {
    std::error_code ec;
    for (fs::directory_iterator it(path, ec), end; !ec && it != end; it.increment(ec)) {
      const std::string sub = it->path().string();
      if (IsPairDirectory(sub)) dirs.push_back(sub);
    }
    if (ec) Fail("pair list", path, "cannot list the directory: " + ec.message());
    std::sort(dirs.begin(), dirs.end());
    if (dirs.empty()) Fail("pair list", path, "neither a pair directory (no info.json) nor a directory of them");
    return dirs;
  }
  std::ifstream in(path);
  if (!in) Fail("pair list", path, "cannot open");
  const fs::path base = fs::path(path).parent_path();
  std::string line;
  for (int line_number = 1; std::getline(in, line); ++line_number) {
    const size_t first = line.find_first_not_of(" \t\r\n");
    if (first == std::string::npos || line[first] == '#') continue;
    const size_t last = line.find_last_not_of(" \t\r\n");
    const std::string entry = line.substr(first, last - first + 1);
    const fs::path p(entry);
    const std::string dir = (p.is_absolute() ? p : base / p).lexically_normal().string();
    if (!IsPairDirectory(dir)) {
      Fail("pair list", path, "line " + std::to_string(line_number) + ": '" + dir +
                                  "' is not a pair directory (no info.json)");
    }
    dirs.push_back(dir);
  }
  if (in.bad()) Fail("pair list", path, "read error");
  return dirs;
}

void WritePairDirectory(const PairData& pair, const std::string& dir, const PairFileNames& names) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !IsDirectory(dir)) Fail("pair directory", dir, "cannot create: " + ec.message());
  if (pair.p0.size() != pair.p1.size()) {
    Fail("pair directory", dir, "cannot write " + std::to_string(pair.p0.size()) + " vs " +
                                    std::to_string(pair.p1.size()) + " matched points");
  }
  json info = json::object();
  info["K0"] = MatrixToJson(pair.K0);
  info["K1"] = MatrixToJson(pair.K1);
  if (pair.T_0to1) info["T_0to1"] = MatrixToJson(*pair.T_0to1);
  info["matches_0_file"] = names.matches0;
  info["matches_1_file"] = names.matches1;
  WriteMatches(pair.p0, Resolve(dir, names.matches0));
  WriteMatches(pair.p1, Resolve(dir, names.matches1));
  if (pair.depth0) {
    info["depth_0_file"] = names.depth0;
    WriteDepth(*pair.depth0, Resolve(dir, names.depth0));
  }
  if (pair.depth1) {
    info["depth_1_file"] = names.depth1;
    WriteDepth(*pair.depth1, Resolve(dir, names.depth1));
  }
  if (pair.gt_depth0) {
    info["gt_depth_0_file"] = names.gt_depth0;
    WriteDepth(*pair.gt_depth0, Resolve(dir, names.gt_depth0));
  }
  if (pair.gt_depth1) {
    info["gt_depth_1_file"] = names.gt_depth1;
    WriteDepth(*pair.gt_depth1, Resolve(dir, names.gt_depth1));
  }
  if (pair.width0 > 0 && pair.height0 > 0) info["image_size_0"] = {pair.width0, pair.height0};
  if (pair.width1 > 0 && pair.height1 > 0) info["image_size_1"] = {pair.width1, pair.height1};

  const std::string info_path = (fs::path(dir) / "info.json").string();
  std::ofstream out(info_path, std::ios::binary);
  out << DumpJson(info, 4) << "\n";
  out.close();
  if (!out) Fail("pair file", info_path, "write error");
}

}  // namespace madsfm
