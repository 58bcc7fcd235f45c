#include "colmap_ext/io/file_copy.h"

#include <fstream>
#include <stdexcept>

namespace madsfm::colmap {

void CopyFileContents(const std::filesystem::path& src, const std::filesystem::path& dst) {
  std::ifstream in(src, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read '" + src.string() + "'");
  std::ofstream out(dst, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error("cannot write '" + dst.string() + "'");
  if (in.peek() != std::ifstream::traits_type::eof()) out << in.rdbuf();  // << of an empty buffer sets failbit
  out.close();
  if (!out || in.bad()) throw std::runtime_error("cannot copy '" + src.string() + "' to '" + dst.string() + "'");
}

}  // namespace madsfm::colmap
