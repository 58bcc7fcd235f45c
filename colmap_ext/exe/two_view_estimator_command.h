// `madsfm two_view_estimator` and `madsfm restore`: option parsing and printing around
// colmap_ext/pipeline/two_view_estimator.h.
#pragma once

namespace madsfm {

int RunTwoViewEstimator(int argc, char** argv);
int RunRestore(int argc, char** argv);

}  // namespace madsfm
