// `madsfm seed_model`: option parsing and printing around colmap_ext/pipeline/seed_model.h.
#pragma once

namespace madsfm {

int RunSeedModel(int argc, char** argv);

}  // namespace madsfm
