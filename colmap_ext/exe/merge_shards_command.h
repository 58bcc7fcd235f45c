// `madsfm merge_shards`: option parsing and printing around colmap_ext/pipeline/merge_shards.h.
#pragma once

namespace madsfm {

int RunMergeShards(int argc, char** argv);

}  // namespace madsfm
