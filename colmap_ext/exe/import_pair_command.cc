#include "colmap_ext/exe/import_pair_command.h"

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "colmap_ext/exe/option_parser.h"
#include "colmap_ext/synthetic/pair_project.h"

namespace madsfm {

int RunImportPair(int argc, char** argv) {
  std::string pair_path, output_path;
  bool known_focal = false;
  OptionParser parser("import_pair",
                      "Makes a COLMAP project of a pair directory: <output_path>/database.db (one keypoint per match,\n"
                      "the raw matches; one SIMPLE_PINHOLE camera per image with the principal point of K and, unless\n"
                      "--known_focal 1, COLMAP's default focal guess 1.2 max(W, H) without a prior), images/,\n"
                      "depths/<image>.npy and ground_truth.json (world = camera 0).");
  parser.AddRequired("pair_path", &pair_path, "Pair directory with image0.png / image1.png.");
  parser.AddRequired("output_path", &output_path, "Project folder to create.");
  parser.AddDefault("known_focal", &known_focal, "Write the true focal lengths with prior_focal_length = 1.");
  if (!parser.Parse(argc, argv, 2)) return EXIT_FAILURE;
  if (parser.help_requested()) return EXIT_SUCCESS;
  try {
    const colmap::PairProjectSummary s = colmap::WritePairProject(pair_path, output_path, known_focal);
    std::printf("import_pair: %d matches -> %s\n", s.num_matches, output_path.c_str());
    return EXIT_SUCCESS;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "madsfm import_pair: error: %s\n", e.what());
    return EXIT_FAILURE;
  }
}

}  // namespace madsfm
