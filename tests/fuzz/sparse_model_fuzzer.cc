// libFuzzer target: madsfm::colmap::ReadReconstruction on a binary model built from the input. Layout: bytes 0-1
// and 2-3 are the little-endian uint16 sizes of cameras.bin and images.bin (clamped to what is left), which follow
// in that order; the rest is points3D.bin. A std::exception is a clean rejection; anything else is a finding.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>

#include "colmap_ext/model/reconstruction.h"
#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 4) return 0;
  size_t lengths[2] = {static_cast<size_t>(data[0] | (data[1] << 8)), static_cast<size_t>(data[2] | (data[3] << 8))};
  const uint8_t* p = data + 4;
  size_t left = size - 4;
  const std::string dir = madsfm::fuzz::ScratchDir();
  const char* names[3] = {"/cameras.bin", "/images.bin", "/points3D.bin"};
  for (int k = 0; k < 3; ++k) {
    const size_t n = k < 2 ? std::min(lengths[k], left) : left;
    madsfm::fuzz::WriteFile(dir + names[k], p, n);
    p += n;
    left -= n;
  }
  try {
    const madsfm::colmap::Reconstruction model = madsfm::colmap::ReadReconstruction(dir);
    for (const auto& [id, image] : model.images) {
      if (image.points2D.size() != image.point3D_ids.size()) __builtin_trap();
    }
  } catch (const std::exception&) {
  }
  return 0;
}
