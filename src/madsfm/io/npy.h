// Reading and writing NumPy .npy files (format versions 1.0, 2.0 and 3.0).
//
// In: a .npy file (or its bytes) holding a plain numeric array: float16/32/64, int8..int64, uint8..uint64 or bool,
// little- or big-endian, C or Fortran order, any number of dimensions (including 0-D scalars and 0-size arrays).
// Out: the shape and the values converted to double (or float) in row-major (C) order, plus the NumPy dtype name.
// Complex, object, string, structured and long-double arrays are rejected. Every failure (missing file, bad
// magic, malformed header, unsupported dtype, truncated data) throws std::runtime_error whose message is
// "<what> '<path>': <problem>", e.g. "depth file 'a.npy': unsupported dtype 'complex128' (descr '<c16')". Sizes
// are checked against the file size before anything is allocated, so garbage input never triggers a huge
// allocation.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace madsfm {

// An n-dimensional array in row-major (C) order: element (i0, ..., ik) is at
// data[((i0 * shape[1] + i1) * shape[2] + ...) + ik]. A 0-D array has an empty shape and one element.
template <typename T>
struct BasicNpyArray {
  std::vector<size_t> shape;
  std::vector<T> data;
  std::string dtype;  // NumPy name of the stored type ("float32", "uint16", ...); informational only

  size_t NumDims() const { return shape.size(); }
  size_t NumElements() const {
    size_t n = 1;
    for (const size_t d : shape) n *= d;
    return n;
  }
};

using NpyArray = BasicNpyArray<double>;
using NpyArrayFloat = BasicNpyArray<float>;

// Reads a .npy file. `what` names the file's role in error messages ("npy file", "depth file", "matches file").
NpyArray ReadNpy(const std::string& path, const std::string& what = "npy file");

// Same, converting to float (exact for float16/float32 files; float64 values are rounded). Faster for float32
// input: the data are read straight into the output.
NpyArrayFloat ReadNpyFloat(const std::string& path, const std::string& what = "npy file");

// Parses the bytes of a .npy file held in memory; `name` stands in for the path in error messages.
NpyArray ParseNpy(const void* bytes, size_t num_bytes, const std::string& name, const std::string& what = "npy file");

// Formats a shape as NumPy prints it: "(3, 480, 640)", "(5,)", "()".
std::string FormatNpyShape(const std::vector<size_t>& shape);

enum class NpyWriteType { kFloat32, kFloat64 };

// Writes a little-endian, C-order, format-1.0 .npy file. data holds prod(shape) values in row-major order.
// Throws std::runtime_error naming the file when the size does not match the shape or the file cannot be written.
void WriteNpy(const std::string& path, const std::vector<size_t>& shape, const double* data,
              NpyWriteType type = NpyWriteType::kFloat64);
void WriteNpy(const std::string& path, const std::vector<size_t>& shape, const float* data,
              NpyWriteType type = NpyWriteType::kFloat32);
void WriteNpy(const std::string& path, const NpyArray& array, NpyWriteType type = NpyWriteType::kFloat64);

}  // namespace madsfm
