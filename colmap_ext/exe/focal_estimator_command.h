// `madsfm focal_estimator`: option parsing and printing around colmap_ext/pipeline/focal_estimator.h.
#pragma once

namespace madsfm {

int RunFocalEstimator(int argc, char** argv);

}  // namespace madsfm
