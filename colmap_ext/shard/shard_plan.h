// The deterministic split of a database's pairs into shards for `two_view_estimator --num_shards` (issue 7).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "colmap_ext/database/database.h"

namespace madsfm::colmap {

// (pair id, number of matches) of the pairs to split, as Database::ReadMatchedPairs returns them.
using PairCounts = std::vector<std::pair<pair_t, int>>;

// Splits the pairs into num_shards shards balanced by match count (the estimator's work per pair grows with it):
// longest-processing-time greedy, pairs by decreasing match count (ties: increasing pair id) each go to the shard
// with the least work so far (ties: the lowest index). Each shard's pairs are returned sorted by pair id. The result
// depends only on the input set, not its order: every task of an array job computes the same split. The largest
// shard holds at most max(matches of one pair) more than the mean (LPT bound).
std::vector<std::vector<pair_t>> SplitPairsIntoShards(const PairCounts& pairs, int num_shards);

// Identifies the split: the pair set with its match counts and the number of shards. Shards of different splits are
// never merged together.
std::string SplitFingerprint(const PairCounts& pairs, int num_shards);

}  // namespace madsfm::colmap
