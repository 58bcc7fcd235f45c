// `madsfm mapper`: option parsing and printing around colmap_ext/pipeline/mapper.h (two_view_estimator,
// focal_estimator, seed_model, colmap mapper with fallbacks).
#pragma once

namespace madsfm {

int RunMapper(int argc, char** argv);

}  // namespace madsfm
