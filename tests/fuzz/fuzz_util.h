// Helpers shared by the libFuzzer targets of tests/fuzz (see scripts/fuzz.sh): a per-process scratch directory
// and whole-file writes. Not part of the library.
#pragma once

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <system_error>
#include <filesystem>

namespace madsfm::fuzz {

// A fresh directory (under /dev/shm when available, for speed), created once per process and removed at exit.
inline const std::string& ScratchDir() {
  static const std::string dir = [] {
    const char* base = std::filesystem::is_directory("/dev/shm") ? "/dev/shm" : "/tmp";
    std::string templ = std::string(base) + "/madsfm_fuzz_XXXXXX";
    if (mkdtemp(templ.data()) == nullptr) {
      std::perror("mkdtemp");
      std::abort();
    }
    static std::string to_remove = templ;
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(to_remove, ec);
    });
    return templ;
  }();
  return dir;
}

// Writes bytes to path (replacing it); aborts on I/O failure (that is a harness problem, not a finding). Retries
// writes a signal interrupted: libFuzzer's timers deliver signals without SA_RESTART.
inline void WriteFile(const std::string& path, const uint8_t* data, size_t size) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) {
    std::perror(path.c_str());
    std::abort();
  }
  size_t done = 0;
  while (done < size) {
    const ssize_t n = ::write(fd, data + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      std::perror(path.c_str());
      std::abort();
    }
    done += static_cast<size_t>(n);
  }
  if (::close(fd) != 0 && errno != EINTR) {
    std::perror(path.c_str());
    std::abort();
  }
}

// The whole content of a file; aborts on failure (a harness problem).
inline std::string ReadFile(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) {
    std::perror(path.c_str());
    std::abort();
  }
  std::string bytes;
  char buf[1 << 14];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) bytes.append(buf, n);
  if (std::ferror(f) || std::fclose(f) != 0) {
    std::perror(path.c_str());
    std::abort();
  }
  return bytes;
}

}  // namespace madsfm::fuzz
