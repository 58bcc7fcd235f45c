#include "colmap_ext/synthetic/synthetic_project.h"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "colmap_ext/database/database_builder.h"
#include "madsfm/io/depth_map_io.h"

namespace madsfm::colmap {
namespace {

uint64_t Mix(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

}  // namespace

void SyntheticProjectOptions::Check() const {
  if (output_path.empty()) throw std::invalid_argument("--output_path must be set");
  if (!SyntheticPairPreset(preset)) throw std::invalid_argument("unknown --preset '" + preset + "'");
  if (num_pairs < 1) throw std::invalid_argument("--num_pairs must be >= 1");
  if (min_num_matches < 16 || max_num_matches < min_num_matches) {
    throw std::invalid_argument("need 16 <= --min_num_matches <= --max_num_matches");
  }
  if (outlier_ratio >= 0.9) throw std::invalid_argument("--outlier_ratio must be < 0.9 (negative: the preset's)");
}

SyntheticProject WriteSyntheticProject(const SyntheticProjectOptions& options) {
  options.Check();
  namespace fs = std::filesystem;
  SyntheticProject project;
  project.database_path = (fs::path(options.output_path) / "database.db").string();
  project.depth_path = (fs::path(options.output_path) / "depths").string();
  fs::create_directories(project.depth_path);
  DatabaseBuilder db(project.database_path, options.colmap_release);
  db.Exec("BEGIN");
  for (int k = 0; k < options.num_pairs; ++k) {
    SyntheticPairOptions pair_options = *SyntheticPairPreset(options.preset);
    const uint64_t seed = Mix(options.seed ^ Mix(static_cast<uint64_t>(k)));
    const int span = options.max_num_matches - options.min_num_matches + 1;
    pair_options.num_matches = options.min_num_matches + static_cast<int>(Mix(seed + 1) % static_cast<uint64_t>(span));
    if (options.outlier_ratio >= 0) {
      pair_options.min_outlier_ratio = pair_options.max_outlier_ratio = options.outlier_ratio;
    }
    const SyntheticPair synthetic = GenerateTwoViewPair(pair_options, seed);
    const PairData& d = synthetic.pair;
    // COLMAP's pixel convention: the upper-left pixel centre is (0.5, 0.5).
    const double f = options.calibrated ? d.K0(0, 0) : 1.2 * std::max(d.width0, d.height0);
    const uint32_t cam = db.AddCamera(0, d.width0, d.height0, {f, d.K0(0, 2) + 0.5, d.K0(1, 2) + 0.5},
                                      options.calibrated);
    // A second camera only when the views differ (two-focal presets).
    const double f2 = options.calibrated ? d.K1(0, 0) : 1.2 * std::max(d.width1, d.height1);
    const uint32_t cam2 = d.K1 == d.K0 ? cam
                                       : db.AddCamera(0, d.width1, d.height1, {f2, d.K1(0, 2) + 0.5, d.K1(1, 2) + 0.5},
                                                      options.calibrated);
    const std::string n1 = "pair" + std::to_string(k) + "_a.png", n2 = "pair" + std::to_string(k) + "_b.png";
    const uint32_t i1 = db.AddImage(n1, cam), i2 = db.AddImage(n2, cam2);
    std::vector<Eigen::Vector2d> k1, k2;
    std::vector<std::array<uint32_t, 2>> matches;
    for (size_t i = 0; i < d.p0.size(); ++i) {
      k1.push_back(d.p0[i] + Eigen::Vector2d(0.5, 0.5));
      k2.push_back(d.p1[i] + Eigen::Vector2d(0.5, 0.5));
      matches.push_back({static_cast<uint32_t>(i), static_cast<uint32_t>(i)});
    }
    db.AddKeypoints(i1, k1);
    db.AddKeypoints(i2, k2);
    db.AddMatches(i1, i2, matches);
    WriteDepthMapNpy(*d.depth0, project.depth_path + "/" + n1 + ".npy");
    WriteDepthMapNpy(*d.depth1, project.depth_path + "/" + n2 + ".npy");
    if (options.keep_pairs) project.pairs.push_back(synthetic);
  }
  db.Exec("COMMIT");
  return project;
}

}  // namespace madsfm::colmap
