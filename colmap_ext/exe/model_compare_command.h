// `madsfm model_compare`: compares a COLMAP sparse model (e.g. the mapper's output) with ground-truth poses and
// focal lengths from a JSON file (format in colmap_ext/model/model_comparison.h) and prints image counts, relative
// rotation / translation-direction errors over all pairs of registered images, focal errors, the number of 3-D
// points and the mean reprojection error, as text or JSON. Returns EXIT_FAILURE (1) on bad options or files.
#pragma once

namespace madsfm {

int RunModelCompare(int argc, char** argv);

}  // namespace madsfm
