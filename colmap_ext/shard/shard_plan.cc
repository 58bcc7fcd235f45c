#include "colmap_ext/shard/shard_plan.h"

#include <algorithm>
#include <functional>
#include <queue>
#include <stdexcept>

#include "colmap_ext/shard/fingerprint.h"

namespace madsfm::colmap {

std::vector<std::vector<pair_t>> SplitPairsIntoShards(const PairCounts& pairs, int num_shards) {
  if (num_shards < 1) throw std::invalid_argument("--num_shards must be >= 1");
  PairCounts order = pairs;
  std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) {
    return a.second != b.second ? a.second > b.second : a.first < b.first;
  });
  // Min-heap of (work so far, shard index).
  using Load = std::pair<long long, int>;
  std::priority_queue<Load, std::vector<Load>, std::greater<Load>> heap;
  for (int k = 0; k < num_shards; ++k) heap.push({0, k});
  std::vector<std::vector<pair_t>> shards(num_shards);
  for (const auto& [pair_id, num_matches] : order) {
    Load least = heap.top();
    heap.pop();
    shards[least.second].push_back(pair_id);
    least.first += std::max(1, num_matches);
    heap.push(least);
  }
  for (auto& s : shards) std::sort(s.begin(), s.end());
  return shards;
}

std::string SplitFingerprint(const PairCounts& pairs, int num_shards) {
  PairCounts sorted = pairs;
  std::sort(sorted.begin(), sorted.end());
  Fingerprinter fp;
  fp.Add(static_cast<int64_t>(num_shards));
  fp.Add(static_cast<int64_t>(sorted.size()));
  for (const auto& [pair_id, num_matches] : sorted) {
    fp.Add(static_cast<int64_t>(pair_id));
    fp.Add(static_cast<int64_t>(num_matches));
  }
  return fp.Hex();
}

}  // namespace madsfm::colmap
