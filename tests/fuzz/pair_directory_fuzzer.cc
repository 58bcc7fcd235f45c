// libFuzzer target: madsfm::ReadPairDirectory with the input as info.json. The scratch directory also holds small
// valid files info.json may name: matches_0.npy / matches_1.npy (3 x 2 float64), matches_2.npy (2 x 2),
// depth_0.npy (8 x 6 float32), depth_1.pfm (8 x 6) and image0.png (an 8 x 6 IHDR; there is no image1.png).
// A std::exception is a clean rejection; anything else is a finding.
#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>
#include <vector>

#include "fuzz_util.h"
#include "madsfm/io/depth_map_io.h"
#include "madsfm/io/npy.h"
#include "madsfm/io/pair_directory.h"

namespace {

const std::string& PairDir() {
  static const std::string dir = [] {
    const std::string d = madsfm::fuzz::ScratchDir();
    const double m0[] = {10.0, 20.0, 30.5, 40.25, 5.0, 6.0};
    const double m1[] = {11.0, 21.0, 31.5, 41.25, 6.0, 7.0};
    madsfm::WriteNpy(d + "/matches_0.npy", {3, 2}, m0);
    madsfm::WriteNpy(d + "/matches_1.npy", {3, 2}, m1);
    madsfm::WriteNpy(d + "/matches_2.npy", {2, 2}, m1);
    madsfm::DepthMap depth;
    depth.width = 8;
    depth.height = 6;
    for (int i = 0; i < 48; ++i) depth.data.push_back(1.0f + 0.1f * i);
    madsfm::WriteDepthMapNpy(depth, d + "/depth_0.npy");
    madsfm::WriteDepthMapPfm(depth, d + "/depth_1.pfm");
    // PNG signature + IHDR chunk (length 13, width 8, height 6, 8-bit RGB); the reader only needs the header.
    const uint8_t png[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R',
                           0, 0, 0, 8, 0, 0, 0, 6, 8, 2, 0, 0, 0, 0, 0, 0, 0};
    madsfm::fuzz::WriteFile(d + "/image0.png", png, sizeof(png));
    return d;
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& dir = PairDir();
  madsfm::fuzz::WriteFile(dir + "/info.json", data, size);
  madsfm::PairReadOptions options;
  options.allow_missing_depth = (size % 2) == 1;
  try {
    const madsfm::PairData pair = madsfm::ReadPairDirectory(dir, options);
    if (pair.p0.size() != pair.p1.size()) __builtin_trap();
  } catch (const std::exception&) {
  }
  return 0;
}
