// Synthetic COLMAP projects: a database of independent synthetic image pairs (src/madsfm/synthetic/two_view_scene)
// with their depth sidecars, for `madsfm synth_project`, the sharding tests and the pipeline benchmarks. No images
// are rendered: keypoints, matches (with outliers) and monocular-depth-like priors come straight from the generator.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "colmap_ext/database/database_schema.h"
#include "madsfm/synthetic/two_view_scene.h"

namespace madsfm::colmap {

struct SyntheticProjectOptions {
  std::string output_path;                       // folder to create: database.db, depths/
  std::string preset = "indoor_shared_focal";    // a SyntheticPairPreset name
  int num_pairs = 100;                           // images 2k+1 and 2k+2 form pair k
  // Matches per pair uniform in [min_num_matches, max_num_matches] (so shards have unequal work).
  int min_num_matches = 100;
  int max_num_matches = 500;
  // < 0: the preset's outlier range; else this fixed outlier ratio.
  double outlier_ratio = -1.0;
  // true: one SIMPLE_PINHOLE camera per pair with the true focal and prior_focal_length = 1; false: COLMAP's guess
  // 1.2 max(W, H) without a prior (the focal modes estimate it).
  bool calibrated = false;
  uint64_t seed = 0;
  bool keep_pairs = false;  // return the generated pairs (ground truth) in SyntheticProject::pairs
  ColmapRelease colmap_release = ColmapRelease::k3_8;  // the database's schema (database_schema.h)

  void Check() const;  // std::invalid_argument naming the option
};

struct SyntheticProject {
  std::string database_path, depth_path;
  // With keep_pairs. Pair k: images "pair<k>_a.png", "pair<k>_b.png" (ids 2k+1, 2k+2).
  std::vector<SyntheticPair> pairs;
};

// Writes the project; throws when output_path/database.db already exists (nothing is overwritten) or on I/O
// errors, naming the path. Pair k uses a seed derived from (seed, k): a project is a prefix of a larger one.
SyntheticProject WriteSyntheticProject(const SyntheticProjectOptions& options);

}  // namespace madsfm::colmap
