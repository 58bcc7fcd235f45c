// `madsfm mapper`: two_view_estimator + focal_estimator + seed_model, then `colmap mapper --input_path SEED`.
#pragma once

namespace madsfm {

int RunMapper(int argc, char** argv);

}  // namespace madsfm
