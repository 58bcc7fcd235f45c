#include "colmap_ext/shard/shard_plan.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>

namespace madsfm::colmap {
namespace {

PairCounts RandomPairs(int n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> matches(15, 2000);
  PairCounts pairs;
  for (int i = 0; i < n; ++i) pairs.push_back({ImagePairToPairId(1 + i, 100000 + i), matches(rng)});
  return pairs;
}

TEST(SplitPairsIntoShards, EveryPairInExactlyOneShardSortedAndBalanced) {
  const PairCounts pairs = RandomPairs(1000, 1);
  std::map<pair_t, int> count_of;
  int max_matches = 0;
  for (const auto& [p, c] : pairs) {
    count_of[p] = c;
    max_matches = std::max(max_matches, c);
  }
  for (int num_shards : {1, 2, 3, 4, 7, 16}) {
    const auto shards = SplitPairsIntoShards(pairs, num_shards);
    ASSERT_EQ(static_cast<int>(shards.size()), num_shards);
    std::map<pair_t, int> seen;
    std::vector<long long> load;
    for (const auto& shard : shards) {
      EXPECT_TRUE(std::is_sorted(shard.begin(), shard.end()));
      long long l = 0;
      for (pair_t p : shard) {
        ++seen[p];
        l += count_of.at(p);
      }
      load.push_back(l);
    }
    ASSERT_EQ(seen.size(), pairs.size());
    for (const auto& [p, n] : seen) EXPECT_EQ(n, 1) << "pair " << p;
    const auto [lo, hi] = std::minmax_element(load.begin(), load.end());
    // Greedy LPT: the shards differ by at most one pair's work.
    EXPECT_LE(*hi - *lo, max_matches) << num_shards << " shards";
  }
}

TEST(SplitPairsIntoShards, DependsOnlyOnThePairSetNotItsOrder) {
  PairCounts pairs = RandomPairs(500, 2);
  const auto a = SplitPairsIntoShards(pairs, 5);
  std::shuffle(pairs.begin(), pairs.end(), std::mt19937(3));
  EXPECT_EQ(SplitPairsIntoShards(pairs, 5), a);
  EXPECT_EQ(SplitFingerprint(pairs, 5), SplitFingerprint(RandomPairs(500, 2), 5));
}

TEST(SplitPairsIntoShards, EqualCountsAreSplitEvenly) {
  PairCounts pairs;
  for (int i = 0; i < 10; ++i) pairs.push_back({ImagePairToPairId(1, 2 + i), 100});
  const auto shards = SplitPairsIntoShards(pairs, 4);
  std::vector<size_t> sizes;
  for (const auto& s : shards) sizes.push_back(s.size());
  std::sort(sizes.begin(), sizes.end());
  EXPECT_EQ(sizes, (std::vector<size_t>{2, 2, 3, 3}));
}

TEST(SplitPairsIntoShards, MoreShardsThanPairsLeavesEmptyShards) {
  const auto shards = SplitPairsIntoShards(RandomPairs(3, 4), 8);
  int non_empty = 0;
  for (const auto& s : shards) non_empty += !s.empty();
  EXPECT_EQ(non_empty, 3);
  EXPECT_EQ(SplitPairsIntoShards({}, 2), (std::vector<std::vector<pair_t>>{{}, {}}));
}

TEST(SplitPairsIntoShards, RejectsZeroShards) {
  EXPECT_THROW(SplitPairsIntoShards(RandomPairs(3, 5), 0), std::invalid_argument);
}

TEST(SplitFingerprint, ChangesWithShardCountPairsAndMatchCounts) {
  PairCounts pairs = RandomPairs(50, 6);
  const std::string base = SplitFingerprint(pairs, 4);
  EXPECT_EQ(base.size(), 32u);
  EXPECT_NE(SplitFingerprint(pairs, 3), base);
  PairCounts more_matches = pairs;
  more_matches[10].second += 1;
  EXPECT_NE(SplitFingerprint(more_matches, 4), base);
  PairCounts fewer = pairs;
  fewer.pop_back();
  EXPECT_NE(SplitFingerprint(fewer, 4), base);
}

}  // namespace
}  // namespace madsfm::colmap
