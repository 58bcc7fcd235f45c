// libFuzzer target: madsfm::ParseNpy on arbitrary bytes. A std::exception is a clean rejection; a crash, a
// sanitizer report, a leak or an allocation over -rss_limit_mb / -malloc_limit_mb is a finding.
#include <cstddef>
#include <cstdint>
#include <exception>

#include "madsfm/io/npy.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const madsfm::NpyArray array = madsfm::ParseNpy(data, size, "fuzz");
    // The result must be self-consistent.
    if (array.data.size() != array.NumElements()) __builtin_trap();
    (void)madsfm::FormatNpyShape(array.shape);
  } catch (const std::exception&) {
  }
  return 0;
}
