// madsfm command-line entry point: `madsfm <command> [--options]`, dispatched COLMAP-style.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "colmap_ext/exe/focal_estimator_command.h"
#include "colmap_ext/exe/import_pair_command.h"
#include "colmap_ext/exe/mapper_command.h"
#include "colmap_ext/exe/merge_shards_command.h"
#include "colmap_ext/exe/model_compare_command.h"
#include "colmap_ext/exe/pair_commands.h"
#include "colmap_ext/exe/render_scene_command.h"
#include "colmap_ext/exe/seed_model_command.h"
#include "colmap_ext/exe/synth_command.h"
#include "colmap_ext/exe/two_view_estimator_command.h"

namespace {

struct Command {
  const char* name;
  std::function<int(int, char**)> run;
  const char* summary;
};

const std::vector<Command>& Commands() {
  static const std::vector<Command> commands = {
      {"mapper", madsfm::RunMapper, "The whole pipeline: two_view_estimator, focal_estimator, seed_model, colmap mapper"},
      {"two_view_estimator", madsfm::RunTwoViewEstimator,
       "Hybrid affine-depth estimation of every matched pair -> two-view geometries in the database"},
      {"merge_shards", madsfm::RunMergeShards, "Merge two_view_estimator shard files (cluster runs) into the database"},
      {"focal_estimator", madsfm::RunFocalEstimator, "Per-camera focal lengths from the pairwise estimates"},
      {"seed_model", madsfm::RunSeedModel, "Initial pair -> two-image sparse model for colmap mapper --input_path"},
      {"restore", madsfm::RunRestore, "Put COLMAP's original two-view geometries and cameras back"},
      {"pair", madsfm::RunPair, "Estimate one pair directory (relative pose, depth scale/shifts, focals) -> JSON"},
      {"bench", madsfm::RunBench, "Run methods over many pair directories -> accuracy/runtime tables, CSV"},
      {"import_pair", madsfm::RunImportPair, "Pair directory -> COLMAP project (database, images, depth sidecars)"},
      {"model_compare", madsfm::RunModelCompare, "Sparse model vs ground-truth poses: registered, rotation/focal errors"},
      {"render_scene", madsfm::RunRenderScene, "Render the multi-view demo scene: images, depth priors, ground truth"},
      {"synth", madsfm::RunSynth, "Write synthetic two-view pair directories with ground truth"},
      {"synth_project", madsfm::RunSynthProject, "Write a synthetic COLMAP project (database + depth sidecars)"},
  };
  return commands;
}

void PrintUsage() {
  std::printf(
      "madsfm: Structure-from-Motion initialisation with monocular depth priors\n\n"
      "Usage: madsfm <command> [--option value ...]\n"
      "       madsfm <command> --help\n\nCommands:\n");
  for (const Command& c : Commands()) std::printf("  %-22s %s\n", c.name, c.summary);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::strcmp(argv[1], "help") == 0 || std::strcmp(argv[1], "--help") == 0 ||
      std::strcmp(argv[1], "-h") == 0) {
    PrintUsage();
    return argc < 2 ? EXIT_FAILURE : EXIT_SUCCESS;
  }
  for (const Command& c : Commands()) {
    if (c.name == std::string(argv[1])) return c.run(argc, argv);
  }
  std::fprintf(stderr, "madsfm: unknown command '%s'\n\n", argv[1]);
  PrintUsage();
  return EXIT_FAILURE;
}
