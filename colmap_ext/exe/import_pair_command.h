// `madsfm import_pair`: turns a pair directory (real images, matches of any matcher, depth maps, ground truth)
// into a COLMAP project, the way hloc imports its matches: database with one keypoint per match and the raw
// matches, images/, depths/<image>.npy sidecars, ground_truth.json (for model_compare).
#pragma once

namespace madsfm {

int RunImportPair(int argc, char** argv);

}  // namespace madsfm
