// libFuzzer target: madsfm::ReadDepthMap on arbitrary bytes saved as .pfm, .bin, .npy and .png in turn. A
// std::exception is a clean rejection; anything else is a finding.
#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>

#include "fuzz_util.h"
#include "madsfm/io/depth_map_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  for (const char* ext : {".pfm", ".bin", ".npy", ".png"}) {
    const std::string path = madsfm::fuzz::ScratchDir() + "/depth" + ext;
    madsfm::fuzz::WriteFile(path, data, size);
    try {
      const madsfm::DepthMap map = madsfm::ReadDepthMap(path);
      if (map.width <= 0 || map.height <= 0 ||
          map.data.size() != static_cast<size_t>(map.width) * static_cast<size_t>(map.height)) {
        __builtin_trap();  // a successful read must return a non-empty, consistent map
      }
    } catch (const std::exception&) {
    }
  }
  return 0;
}
