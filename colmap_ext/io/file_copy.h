// Copying a file through streams: libstdc++ retries reads and writes a signal interrupted, where the sendfile() of
// std::filesystem::copy_file fails with EINTR (libFuzzer's timers, a colmap child, Slurm).
#pragma once

#include <filesystem>

namespace madsfm::colmap {

// Copies src to dst (replacing it); throws std::runtime_error naming both files on failure.
void CopyFileContents(const std::filesystem::path& src, const std::filesystem::path& dst);

}  // namespace madsfm::colmap
