#include "colmap_ext/exe/synth_command.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "colmap_ext/database/database_schema.h"
#include "colmap_ext/exe/option_parser.h"
#include "colmap_ext/synthetic/synthetic_project.h"
#include "madsfm/io/pair_directory.h"
#include "madsfm/synthetic/pair_set.h"
#include "madsfm/synthetic/two_view_scene.h"

namespace madsfm {

int RunSynth(int argc, char** argv) {
  std::string preset = "indoor_calibrated", output_path;
  int num_pairs = 100, seed = 0;
  std::string presets_help = "Scene / camera / prior preset:";
  for (const std::string& n : SyntheticPairPresetNames()) presets_help += " " + n;
  OptionParser parser("synth",
                      "Writes synthetic two-view pairs (rendered scene, monocular-depth-like priors with unknown\n"
                      "scale/shift and distortions, outliers, pixel noise, ground truth) as pair directories\n"
                      "<output_path>/<preset>_<i>/ and a list <output_path>/pairs.txt.");
  parser.AddRequired("output_path", &output_path, "Directory to write into (created).");
  parser.AddDefault("preset", &preset, presets_help);
  parser.AddDefault("num_pairs", &num_pairs, "Number of pairs.");
  parser.AddDefault("seed", &seed, "Seed of the set (pair i uses a seed derived from it).");
  if (!parser.Parse(argc, argv, 2)) return EXIT_FAILURE;
  if (parser.help_requested()) return EXIT_SUCCESS;
  try {
    const std::string list_path = WriteSyntheticPairSet(preset, num_pairs, static_cast<uint64_t>(seed), output_path);
    std::fprintf(stderr, "synth: wrote %d pairs and %s\n", num_pairs, list_path.c_str());
    return EXIT_SUCCESS;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "madsfm synth: error: %s\n", e.what());
    return EXIT_FAILURE;
  }
}

int RunSynthProject(int argc, char** argv) {
  colmap::SyntheticProjectOptions o;
  int seed = 0;
  std::string colmap_version = "3.8";
  std::string versions;
  for (colmap::ColmapRelease r : colmap::AllColmapReleases()) versions += " " + colmap::ColmapReleaseName(r);
  std::string presets_help = "Scene / camera / prior preset:";
  for (const std::string& n : SyntheticPairPresetNames()) presets_help += " " + n;
  OptionParser parser("synth_project",
                      "Writes a synthetic COLMAP project: <output_path>/database.db (COLMAP 3.8 schema by default) holding\n"
                      "num_pairs independent image pairs (images pair<k>_a.png, pair<k>_b.png; keypoints, raw matches\n"
                      "with outliers, no two-view geometries yet) and <output_path>/depths/<image>.npy depth priors.\n"
                      "For trying two_view_estimator, sharding and merging at scale without images.");
  parser.AddRequired("output_path", &o.output_path, "Folder to write into (database.db must not exist yet).");
  parser.AddDefault("preset", &o.preset, presets_help);
  parser.AddDefault("num_pairs", &o.num_pairs, "Number of image pairs.");
  parser.AddDefault("min_num_matches", &o.min_num_matches, "Fewest matches of a pair (drawn uniformly per pair).");
  parser.AddDefault("max_num_matches", &o.max_num_matches, "Most matches of a pair.");
  parser.AddDefault("outlier_ratio", &o.outlier_ratio, "Fixed outlier ratio (negative: the preset's range).");
  parser.AddDefault("calibrated", &o.calibrated, "Write the true focal lengths with prior_focal_length = 1.");
  parser.AddDefault("seed", &seed, "Seed (pair k uses a seed derived from it and k).");
  parser.AddDefault("colmap_version", &colmap_version,
                    "Schema of the database, as that COLMAP release creates it (docs/formats.md):" + versions + ".");
  if (!parser.Parse(argc, argv, 2)) return EXIT_FAILURE;
  if (parser.help_requested()) return EXIT_SUCCESS;
  o.seed = static_cast<uint64_t>(seed);
  try {
    o.colmap_release = colmap::ParseColmapRelease(colmap_version);
    const colmap::SyntheticProject p = colmap::WriteSyntheticProject(o);
    std::printf("synth_project: %d pairs -> %s, depths in %s\n", o.num_pairs, p.database_path.c_str(),
                p.depth_path.c_str());
    return EXIT_SUCCESS;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "madsfm synth_project: error: %s\n", e.what());
    return EXIT_FAILURE;
  }
}

}  // namespace madsfm
