// A synthetic set on disk (`madsfm synth`): pair directories <output_path>/<preset>_<i>/ of a preset with their true
// depth maps, and the list <output_path>/pairs.txt.
#pragma once

#include <cstdint>
#include <string>

namespace madsfm {

// Returns the path of pairs.txt. Throws std::invalid_argument for an unknown preset or num_pairs < 1, and
// std::runtime_error naming the file on write errors.
std::string WriteSyntheticPairSet(const std::string& preset, int num_pairs, uint64_t seed, const std::string& output_path);

}  // namespace madsfm
