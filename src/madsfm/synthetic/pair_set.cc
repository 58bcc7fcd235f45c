#include "madsfm/synthetic/pair_set.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "madsfm/io/pair_directory.h"
#include "madsfm/synthetic/two_view_scene.h"

namespace madsfm {

std::string WriteSyntheticPairSet(const std::string& preset, int num_pairs, uint64_t seed, const std::string& output_path) {
  const auto options = SyntheticPairPreset(preset);
  if (!options) throw std::invalid_argument("unknown --preset '" + preset + "'");
  if (num_pairs < 1) throw std::invalid_argument("--num_pairs must be >= 1");
  std::filesystem::create_directories(output_path);
  const std::string list_path = (std::filesystem::path(output_path) / "pairs.txt").string();
  std::ofstream list(list_path);
  if (!list) throw std::runtime_error("cannot write '" + list_path + "'");
  const auto set = GenerateTwoViewSet(*options, num_pairs, seed);
  for (int i = 0; i < num_pairs; ++i) {
    char name[256];
    std::snprintf(name, sizeof(name), "%s_%04d", preset.c_str(), i);
    PairData pair = set[i].pair;
    pair.gt_depth0 = set[i].true_depth_map0;  // for bench's depth-correction errors
    pair.gt_depth1 = set[i].true_depth_map1;
    WritePairDirectory(pair, (std::filesystem::path(output_path) / name).string());
    list << name << "\n";
  }
  list.close();
  if (!list) throw std::runtime_error("cannot write '" + list_path + "'");
  return list_path;
}

}  // namespace madsfm
