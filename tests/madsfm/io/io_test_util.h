// Helpers shared by the io tests: a scratch directory, raw file writing, hand-made .npy bytes, error capture.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "testing/temp_dir.h"

namespace madsfm {
namespace io_test {

// A scratch folder, removed with its contents on destruction (File: a path inside it).
class TempDir : public testing::TempDir {
 public:
  TempDir() : testing::TempDir("io_test") {}
  std::string File(const std::string& name) const { return Sub(name); }
};

inline void WriteFile(const std::string& path, const std::string& bytes) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

inline std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Raw bytes of a value, optionally byte-swapped (big-endian).
template <typename T>
std::string Bytes(T value, bool big_endian = false) {
  std::string s(sizeof(T), '\0');
  std::memcpy(s.data(), &value, sizeof(T));
  if (big_endian) std::reverse(s.begin(), s.end());
  return s;
}

// A .npy file with the given header dictionary text (written verbatim, then padded) and raw data bytes.
inline std::string MakeNpy(const std::string& dict, const std::string& data, int major = 1) {
  std::string header = dict;
  const size_t prefix = major == 1 ? 10 : 12;
  while ((prefix + header.size() + 1) % 64 != 0) header.push_back(' ');
  header.push_back('\n');
  std::string bytes = std::string("\x93NUMPY", 6);
  bytes.push_back(static_cast<char>(major));
  bytes.push_back('\0');
  if (major == 1) {
    bytes += Bytes(static_cast<uint16_t>(header.size()));
  } else {
    bytes += Bytes(static_cast<uint32_t>(header.size()));
  }
  return bytes + header + data;
}

inline std::string NpyDict(const std::string& descr, bool fortran, const std::string& shape) {
  return "{'descr': '" + descr + "', 'fortran_order': " + (fortran ? "True" : "False") + ", 'shape': " + shape +
         ", }";
}

// The message of the std::runtime_error thrown by f, or "<no exception>".
template <typename F>
std::string ErrorOf(F&& f) {
  try {
    f();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "<no exception>";
}

inline bool Contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

}  // namespace io_test
}  // namespace madsfm
