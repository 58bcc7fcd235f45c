#include "madsfm/io/npy.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <stdexcept>
#include <system_error>
#include <type_traits>

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "madsfm's .npy reader assumes a little-endian host");

namespace madsfm {
namespace {

constexpr size_t kMaxHeaderLength = size_t{1} << 20;  // NumPy itself refuses headers above 10000 bytes
constexpr size_t kMaxNumDims = 64;                      // NPY_MAXDIMS of NumPy 2
constexpr int kMaxNestingDepth = 16;                    // of the header's Python literal

[[noreturn]] void Fail(const std::string& what, const std::string& name, const std::string& problem) {
  throw std::runtime_error(what + " '" + name + "': " + problem);
}

// ---------------------------------------------------------------------------------------------------------------
// Byte sources: a file (read on demand) or a buffer in memory.

class ByteSource {
 public:
  virtual ~ByteSource() = default;
  virtual size_t Size() const = 0;
  // Copies bytes [offset, offset + n) to dst; the caller has checked the range against Size().
  virtual void Read(size_t offset, size_t n, void* dst) = 0;
};

class MemorySource : public ByteSource {
 public:
  MemorySource(const void* bytes, size_t size) : bytes_(static_cast<const unsigned char*>(bytes)), size_(size) {}
  size_t Size() const override { return size_; }
  void Read(size_t offset, size_t n, void* dst) override {
    if (n > 0) std::memcpy(dst, bytes_ + offset, n);
  }

 private:
  const unsigned char* bytes_;
  size_t size_;
};

class FileSource : public ByteSource {
 public:
  FileSource(const std::string& path, const std::string& what) : path_(path), what_(what) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status)) Fail(what, path, "file does not exist");
    if (std::filesystem::is_directory(status)) Fail(what, path, "is a directory, not a file");
    file_ = std::fopen(path.c_str(), "rb");
    if (file_ == nullptr) Fail(what, path, std::string("cannot open: ") + std::strerror(errno));
    if (std::fseek(file_, 0, SEEK_END) != 0) Fail(what, path, "cannot determine the file size");
    const long size = std::ftell(file_);
    if (size < 0) Fail(what, path, "cannot determine the file size");
    size_ = static_cast<size_t>(size);
  }
  ~FileSource() override {
    if (file_ != nullptr) std::fclose(file_);
  }
  FileSource(const FileSource&) = delete;
  FileSource& operator=(const FileSource&) = delete;

  size_t Size() const override { return size_; }
  void Read(size_t offset, size_t n, void* dst) override {
    if (n == 0) return;
    if (std::fseek(file_, static_cast<long>(offset), SEEK_SET) != 0 || std::fread(dst, 1, n, file_) != n) {
      Fail(what_, path_, "read error");
    }
  }

 private:
  std::string path_, what_;
  std::FILE* file_ = nullptr;
  size_t size_ = 0;
};

// ---------------------------------------------------------------------------------------------------------------
// A parser for the Python literal in the header: {'descr': '<f4', 'fortran_order': False, 'shape': (3, 4), }

struct PyValue {
  enum class Kind { kString, kBool, kNone, kInt, kSequence, kDict };
  Kind kind = Kind::kNone;
  std::string str;
  bool boolean = false;
  bool negative = false;
  uint64_t integer = 0;  // absolute value
  bool overflow = false;
  std::vector<PyValue> items;                          // sequence items
  std::vector<std::pair<std::string, PyValue>> dict;   // dict entries with string keys
};

class PyLiteralParser {
 public:
  PyLiteralParser(const std::string& text, const std::string& what, const std::string& name)
      : text_(text), what_(what), name_(name) {}

  PyValue ParseTop() {
    PyValue value = ParseValue(0);
    SkipSpace();
    if (pos_ != text_.size()) Error("unexpected trailing characters");
    return value;
  }

 private:
  [[noreturn]] void Error(const std::string& problem) {
    Fail(what_, name_, "malformed header (" + problem + " at offset " + std::to_string(pos_) + ")");
  }

  void SkipSpace() {
    while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\t' || text_[pos_] == '\n' ||
                                   text_[pos_] == '\r')) {
      ++pos_;
    }
  }
  bool Peek(char c) {
    SkipSpace();
    return pos_ < text_.size() && text_[pos_] == c;
  }
  void Expect(char c) {
    if (!Peek(c)) Error(std::string("expected '") + c + "'");
    ++pos_;
  }

  PyValue ParseValue(int depth) {
    if (depth > kMaxNestingDepth) Error("nesting too deep");
    SkipSpace();
    if (pos_ >= text_.size()) Error("unexpected end");
    const char c = text_[pos_];
    if (c == '{') return ParseDict(depth);
    if (c == '(' || c == '[') return ParseSequence(depth, c == '(' ? ')' : ']');
    if (c == '\'' || c == '"') {
      PyValue v;
      v.kind = PyValue::Kind::kString;
      v.str = ParseString();
      return v;
    }
    if (c == '-' || c == '+' || (c >= '0' && c <= '9')) return ParseInt();
    if (IsAlpha(c)) {
      const size_t start = pos_;
      while (pos_ < text_.size() && (IsAlpha(text_[pos_]) || (text_[pos_] >= '0' && text_[pos_] <= '9'))) ++pos_;
      const std::string word = text_.substr(start, pos_ - start);
      PyValue v;
      if (word == "True" || word == "False") {
        v.kind = PyValue::Kind::kBool;
        v.boolean = word == "True";
      } else if (word == "None") {
        v.kind = PyValue::Kind::kNone;
      } else {
        pos_ = start;
        Error("unexpected identifier '" + word.substr(0, 32) + "'");
      }
      return v;
    }
    Error(std::string("unexpected character 0x") + HexByte(c));
  }

  static bool IsAlpha(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
  static std::string HexByte(char c) {
    static const char* kDigits = "0123456789abcdef";
    const unsigned char u = static_cast<unsigned char>(c);
    return std::string{kDigits[u >> 4], kDigits[u & 15]};
  }

  std::string ParseString() {
    const char quote = text_[pos_++];
    std::string out;
    while (true) {
      if (pos_ >= text_.size()) Error("unterminated string");
      const char c = text_[pos_++];
      if (c == quote) break;
      if (c == '\\') {
        if (pos_ >= text_.size()) Error("unterminated string");
        out.push_back(text_[pos_++]);
      } else {
        out.push_back(c);
      }
    }
    return out;
  }

  PyValue ParseInt() {
    PyValue v;
    v.kind = PyValue::Kind::kInt;
    if (text_[pos_] == '-' || text_[pos_] == '+') v.negative = text_[pos_++] == '-';
    const size_t start = pos_;
    while (pos_ < text_.size() && text_[pos_] >= '0' && text_[pos_] <= '9') {
      const uint64_t digit = static_cast<uint64_t>(text_[pos_] - '0');
      if (v.integer > (std::numeric_limits<uint64_t>::max() - digit) / 10) v.overflow = true;
      v.integer = v.integer * 10 + digit;
      ++pos_;
    }
    if (pos_ == start) Error("expected a digit");
    if (pos_ < text_.size() && (text_[pos_] == 'L' || text_[pos_] == 'l')) ++pos_;  // Python 2 long suffix
    return v;
  }

  PyValue ParseSequence(int depth, char close) {
    PyValue v;
    v.kind = PyValue::Kind::kSequence;
    ++pos_;
    while (!Peek(close)) {
      v.items.push_back(ParseValue(depth + 1));
      if (Peek(',')) {
        ++pos_;
      } else if (!Peek(close)) {
        Error(std::string("expected ',' or '") + close + "'");
      }
    }
    ++pos_;
    return v;
  }

  PyValue ParseDict(int depth) {
    PyValue v;
    v.kind = PyValue::Kind::kDict;
    ++pos_;
    while (!Peek('}')) {
      SkipSpace();
      if (pos_ >= text_.size() || (text_[pos_] != '\'' && text_[pos_] != '"')) Error("expected a string key");
      std::string key = ParseString();
      Expect(':');
      v.dict.emplace_back(std::move(key), ParseValue(depth + 1));
      if (Peek(',')) {
        ++pos_;
      } else if (!Peek('}')) {
        Error("expected ',' or '}'");
      }
    }
    ++pos_;
    return v;
  }

  const std::string& text_;
  const std::string& what_;
  const std::string& name_;
  size_t pos_ = 0;
};

// ---------------------------------------------------------------------------------------------------------------
// The header.

struct Dtype {
  char kind = 'f';  // 'f' float, 'i' signed, 'u' unsigned, 'b' bool
  int size = 4;     // bytes per element
  bool big_endian = false;
  std::string name;
};

struct Header {
  Dtype dtype;
  bool fortran_order = false;
  std::vector<size_t> shape;
  size_t num_elements = 1;
  size_t data_offset = 0;
  size_t data_bytes = 0;
};

Dtype ParseDescr(const std::string& descr, const std::string& what, const std::string& name) {
  const std::string quoted = "(descr '" + descr.substr(0, 40) + "')";
  size_t pos = 0;
  Dtype dtype;
  if (!descr.empty() && (descr[0] == '<' || descr[0] == '>' || descr[0] == '|' || descr[0] == '=')) {
    dtype.big_endian = descr[0] == '>';
    pos = 1;
  }
  if (pos >= descr.size()) Fail(what, name, "empty dtype " + quoted);
  dtype.kind = descr[pos++];
  const std::string size_text = descr.substr(pos);
  int size = 0;
  bool size_ok = !size_text.empty() && size_text.size() <= 3;
  for (size_t i = 0; size_ok && i < size_text.size(); ++i) {  // at most 3 digits: no overflow
    const char c = size_text[i];
    if (c < '0' || c > '9') size_ok = false;
    else size = size * 10 + (c - '0');
  }
  if (!size_ok) size = -1;
  dtype.size = size;
  auto unsupported = [&](const std::string& type_name) {
    Fail(what, name, "unsupported dtype '" + type_name + "' " + quoted +
                         "; expected float16/32/64, (u)int8/16/32/64 or bool");
  };
  switch (dtype.kind) {
    case 'f':
      if (size == 2 || size == 4 || size == 8) {
        dtype.name = "float" + std::to_string(8 * size);
        return dtype;
      }
      unsupported(size > 0 ? "float" + std::to_string(8 * size) : "float");
      break;
    case 'i':
    case 'u':
      if (size == 1 || size == 2 || size == 4 || size == 8) {
        dtype.name = std::string(dtype.kind == 'u' ? "uint" : "int") + std::to_string(8 * size);
        return dtype;
      }
      unsupported(dtype.kind == 'u' ? "uint" : "int");
      break;
    case 'b':
      if (size == 1) {
        dtype.name = "bool";
        return dtype;
      }
      unsupported("bool");
      break;
    case 'c':
      unsupported(size > 0 ? "complex" + std::to_string(8 * size) : "complex");
      break;
    case 'O':
      unsupported("object");
      break;
    case 'S':
    case 'a':
      unsupported("bytes");
      break;
    case 'U':
      unsupported("str");
      break;
    case 'V':
      unsupported("void");
      break;
    case 'M':
      unsupported("datetime64");
      break;
    case 'm':
      unsupported("timedelta64");
      break;
    default:
      break;
  }
  unsupported(descr.substr(0, 40));
  return dtype;  // unreachable
}

Header ReadHeader(ByteSource* src, const std::string& what, const std::string& name) {
  const size_t file_size = src->Size();
  unsigned char prefix[12];
  if (file_size < 10) {
    Fail(what, name, "not a .npy file (" + std::to_string(file_size) + " bytes, too short for the header)");
  }
  src->Read(0, std::min<size_t>(12, file_size), prefix);
  if (std::memcmp(prefix, "\x93NUMPY", 6) != 0) Fail(what, name, "not a .npy file (bad magic string)");
  const int major = prefix[6], minor = prefix[7];
  size_t header_length = 0, prefix_length = 0;
  if (major == 1) {
    header_length = prefix[8] | (size_t{prefix[9]} << 8);
    prefix_length = 10;
  } else if (major == 2 || major == 3) {
    if (file_size < 12) Fail(what, name, "truncated header");
    header_length = prefix[8] | (size_t{prefix[9]} << 8) | (size_t{prefix[10]} << 16) | (size_t{prefix[11]} << 24);
    prefix_length = 12;
  } else {
    Fail(what, name, "unsupported .npy format version " + std::to_string(major) + "." + std::to_string(minor));
  }
  if (header_length > kMaxHeaderLength) {
    Fail(what, name, "implausible header length " + std::to_string(header_length));
  }
  if (header_length > file_size - prefix_length) {
    Fail(what, name, "truncated header (header length " + std::to_string(header_length) + ", file has " +
                         std::to_string(file_size) + " bytes)");
  }
  std::string text(header_length, '\0');
  src->Read(prefix_length, header_length, text.data());
  // Version 1 and 2 headers are latin-1, version 3 UTF-8; the keys and values we need are ASCII either way, and a
  // NUL byte can only be garbage.
  if (text.find('\0') != std::string::npos) Fail(what, name, "malformed header (contains a NUL byte)");

  PyLiteralParser parser(text, what, name);
  const PyValue top = parser.ParseTop();
  if (top.kind != PyValue::Kind::kDict) Fail(what, name, "malformed header (not a dictionary)");
  const PyValue* descr = nullptr;
  const PyValue* fortran = nullptr;
  const PyValue* shape = nullptr;
  for (const auto& [key, value] : top.dict) {
    if (key == "descr") descr = &value;
    if (key == "fortran_order") fortran = &value;
    if (key == "shape") shape = &value;
  }
  if (descr == nullptr || fortran == nullptr || shape == nullptr) {
    Fail(what, name, "malformed header (needs the keys 'descr', 'fortran_order' and 'shape')");
  }
  Header header;
  if (descr->kind == PyValue::Kind::kSequence) {
    Fail(what, name, "unsupported dtype (structured array); expected a plain numeric array");
  }
  if (descr->kind != PyValue::Kind::kString) Fail(what, name, "malformed header ('descr' is not a string)");
  header.dtype = ParseDescr(descr->str, what, name);
  if (fortran->kind != PyValue::Kind::kBool) Fail(what, name, "malformed header ('fortran_order' is not a bool)");
  header.fortran_order = fortran->boolean;
  if (shape->kind != PyValue::Kind::kSequence) Fail(what, name, "malformed header ('shape' is not a tuple)");
  if (shape->items.size() > kMaxNumDims) {
    Fail(what, name, "malformed header (" + std::to_string(shape->items.size()) + " dimensions)");
  }
  // Element and byte counts, with overflow checks; a dimension of 0 makes the array empty.
  bool overflow = false;
  bool empty = false;
  size_t count = 1;
  for (const PyValue& item : shape->items) {
    if (item.kind != PyValue::Kind::kInt || item.negative || item.overflow ||
        item.integer > std::numeric_limits<size_t>::max()) {
      Fail(what, name, "malformed header ('shape' must hold non-negative integers)");
    }
    const size_t dim = static_cast<size_t>(item.integer);
    header.shape.push_back(dim);
    if (dim == 0) empty = true;
    if (dim != 0 && count > std::numeric_limits<size_t>::max() / dim) overflow = true;
    if (!overflow) count *= dim;
  }
  if (empty) count = 0;
  const size_t item_size = static_cast<size_t>(header.dtype.size);
  if (count != 0 && (overflow || count > std::numeric_limits<size_t>::max() / item_size)) {
    Fail(what, name, "truncated data: shape " + FormatNpyShape(header.shape) + " is larger than the file (" +
                         std::to_string(file_size) + " bytes)");
  }
  header.num_elements = count;
  header.data_offset = prefix_length + header_length;
  header.data_bytes = count * item_size;
  if (header.data_bytes > file_size - header.data_offset) {
    Fail(what, name, "truncated data: shape " + FormatNpyShape(header.shape) + " of " + header.dtype.name +
                         " needs " + std::to_string(header.data_bytes) + " bytes, the file has " +
                         std::to_string(file_size - header.data_offset) + " after the header");
  }
  return header;
}

// ---------------------------------------------------------------------------------------------------------------
// Conversion.

float HalfToFloat(uint16_t h) {
  const uint32_t sign = static_cast<uint32_t>(h & 0x8000u) << 16;
  const uint32_t exponent = (h >> 10) & 0x1fu;
  uint32_t mantissa = h & 0x3ffu;
  uint32_t bits;
  if (exponent == 0x1fu) {
    bits = sign | 0x7f800000u | (mantissa << 13);  // inf or nan (payload kept)
  } else if (exponent != 0) {
    bits = sign | ((exponent + 112u) << 23) | (mantissa << 13);  // normal: rebias 15 -> 127
  } else if (mantissa == 0) {
    bits = sign;  // signed zero
  } else {
    // Subnormal half: mantissa * 2^-24; normalise into a float32 normal number.
    int e = -1;
    do {
      ++e;
      mantissa <<= 1;
    } while ((mantissa & 0x400u) == 0);
    bits = sign | static_cast<uint32_t>(112 - e) << 23 | ((mantissa & 0x3ffu) << 13);
  }
  float f;
  std::memcpy(&f, &bits, sizeof(f));
  return f;
}

template <typename U>
inline U Load(const unsigned char* p, bool swap) {
  unsigned char b[sizeof(U)];
  std::memcpy(b, p, sizeof(U));
  if (swap) std::reverse(b, b + sizeof(U));
  U v;
  std::memcpy(&v, b, sizeof(U));
  return v;
}

template <typename U, typename T>
void ConvertLoop(const unsigned char* raw, size_t n, bool swap, T* out) {
  for (size_t i = 0; i < n; ++i) out[i] = static_cast<T>(Load<U>(raw + i * sizeof(U), swap));
}

template <typename T>
void Convert(const unsigned char* raw, size_t n, const Dtype& dtype, T* out) {
  const bool swap = dtype.big_endian;
  switch (dtype.kind) {
    case 'f':
      if (dtype.size == 2) {
        for (size_t i = 0; i < n; ++i) out[i] = static_cast<T>(HalfToFloat(Load<uint16_t>(raw + 2 * i, swap)));
      } else if (dtype.size == 4) {
        ConvertLoop<float>(raw, n, swap, out);
      } else {
        ConvertLoop<double>(raw, n, swap, out);
      }
      return;
    case 'i':
      if (dtype.size == 1) ConvertLoop<int8_t>(raw, n, false, out);
      if (dtype.size == 2) ConvertLoop<int16_t>(raw, n, swap, out);
      if (dtype.size == 4) ConvertLoop<int32_t>(raw, n, swap, out);
      if (dtype.size == 8) ConvertLoop<int64_t>(raw, n, swap, out);
      return;
    case 'u':
      if (dtype.size == 1) ConvertLoop<uint8_t>(raw, n, false, out);
      if (dtype.size == 2) ConvertLoop<uint16_t>(raw, n, swap, out);
      if (dtype.size == 4) ConvertLoop<uint32_t>(raw, n, swap, out);
      if (dtype.size == 8) ConvertLoop<uint64_t>(raw, n, swap, out);
      return;
    case 'b':
      for (size_t i = 0; i < n; ++i) out[i] = static_cast<T>(raw[i] != 0 ? 1 : 0);
      return;
    default:
      return;  // ParseDescr admits nothing else
  }
}

// Reorders `data` (Fortran order: first index fastest) into C order (last index fastest).
template <typename T>
void FortranToC(const std::vector<size_t>& shape, std::vector<T>* data) {
  const size_t ndim = shape.size();
  if (ndim < 2 || data->empty()) return;
  std::vector<T> out(data->size());
  const T* in = data->data();
  if (ndim == 2) {
    const size_t rows = shape[0], cols = shape[1];
    for (size_t r = 0; r < rows; ++r) {
      for (size_t c = 0; c < cols; ++c) out[r * cols + c] = in[c * rows + r];
    }
  } else {
    std::vector<size_t> fortran_stride(ndim), index(ndim, 0);
    size_t stride = 1;
    for (size_t j = 0; j < ndim; ++j) {
      fortran_stride[j] = stride;
      stride *= shape[j];
    }
    size_t offset = 0;
    for (size_t c = 0; c < out.size(); ++c) {
      out[c] = in[offset];
      for (size_t j = ndim; j-- > 0;) {  // increment the C-order multi-index, last index fastest
        offset += fortran_stride[j];
        if (++index[j] < shape[j]) break;
        offset -= fortran_stride[j] * shape[j];
        index[j] = 0;
      }
    }
  }
  data->swap(out);
}

template <typename T>
BasicNpyArray<T> ReadArray(ByteSource* src, const std::string& what, const std::string& name) {
  const Header header = ReadHeader(src, what, name);
  BasicNpyArray<T> array;
  array.shape = header.shape;
  array.dtype = header.dtype.name;
  array.data.resize(header.num_elements);
  const bool same_type = header.dtype.kind == 'f' && static_cast<size_t>(header.dtype.size) == sizeof(T);
  if (same_type && !header.dtype.big_endian) {
    src->Read(header.data_offset, header.data_bytes, array.data.data());
  } else {
    // Convert chunk by chunk through a small buffer (the item sizes 1, 2, 4, 8 divide the chunk size).
    constexpr size_t kChunkBytes = size_t{1} << 16;
    const size_t item_size = static_cast<size_t>(header.dtype.size);
    std::unique_ptr<unsigned char[]> raw(new unsigned char[kChunkBytes]);
    for (size_t done = 0; done < header.data_bytes; done += kChunkBytes) {
      const size_t n = std::min(kChunkBytes, header.data_bytes - done);
      src->Read(header.data_offset + done, n, raw.get());
      Convert(raw.get(), n / item_size, header.dtype, array.data.data() + done / item_size);
    }
  }
  if (header.fortran_order) FortranToC(array.shape, &array.data);
  return array;
}

template <typename T, typename S>
void WriteNpyImpl(const std::string& path, const std::vector<size_t>& shape, const S* data, NpyWriteType type) {
  const std::string what = "npy file";
  if (shape.size() > kMaxNumDims) Fail(what, path, "too many dimensions to write");
  size_t count = 1;
  for (const size_t d : shape) count *= d;
  if (count > 0 && data == nullptr) Fail(what, path, "no data to write for shape " + FormatNpyShape(shape));
  std::string header = std::string("{'descr': '") + (type == NpyWriteType::kFloat32 ? "<f4" : "<f8") +
                       "', 'fortran_order': False, 'shape': " + FormatNpyShape(shape) + ", }";
  // Pad with spaces and a final newline so that magic + length + header is a multiple of 64 bytes.
  const size_t unpadded = 10 + header.size() + 1;
  header.append((64 - unpadded % 64) % 64, ' ');
  header.push_back('\n');
  std::string bytes = std::string("\x93NUMPY\x01\x00", 8);
  bytes.push_back(static_cast<char>(header.size() & 0xff));
  bytes.push_back(static_cast<char>((header.size() >> 8) & 0xff));
  bytes += header;

  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) Fail(what, path, std::string("cannot open for writing: ") + std::strerror(errno));
  bool ok = std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size();
  constexpr size_t kChunk = 1 << 14;
  std::vector<T> buffer(std::min(count, kChunk));
  for (size_t start = 0; ok && start < count; start += kChunk) {
    const size_t n = std::min(kChunk, count - start);
    if constexpr (std::is_same<S, T>::value) {
      ok = std::fwrite(data + start, sizeof(T), n, file) == n;
    } else {
      for (size_t i = 0; i < n; ++i) buffer[i] = static_cast<T>(data[start + i]);
      ok = std::fwrite(buffer.data(), sizeof(T), n, file) == n;
    }
  }
  ok = (std::fclose(file) == 0) && ok;
  if (!ok) Fail(what, path, "write error");
}

template <typename S>
void WriteNpyDispatch(const std::string& path, const std::vector<size_t>& shape, const S* data, NpyWriteType type) {
  if (type == NpyWriteType::kFloat32) {
    WriteNpyImpl<float>(path, shape, data, type);
  } else {
    WriteNpyImpl<double>(path, shape, data, type);
  }
}

}  // namespace

std::string FormatNpyShape(const std::vector<size_t>& shape) {
  std::string s = "(";
  for (size_t i = 0; i < shape.size(); ++i) {
    if (i > 0) s += ", ";
    s += std::to_string(shape[i]);
  }
  if (shape.size() == 1) s += ",";
  return s + ")";
}

NpyArray ReadNpy(const std::string& path, const std::string& what) {
  FileSource src(path, what);
  return ReadArray<double>(&src, what, path);
}

NpyArrayFloat ReadNpyFloat(const std::string& path, const std::string& what) {
  FileSource src(path, what);
  return ReadArray<float>(&src, what, path);
}

NpyArray ParseNpy(const void* bytes, size_t num_bytes, const std::string& name, const std::string& what) {
  MemorySource src(bytes, bytes == nullptr ? 0 : num_bytes);
  return ReadArray<double>(&src, what, name);
}

void WriteNpy(const std::string& path, const std::vector<size_t>& shape, const double* data, NpyWriteType type) {
  WriteNpyDispatch(path, shape, data, type);
}

void WriteNpy(const std::string& path, const std::vector<size_t>& shape, const float* data, NpyWriteType type) {
  WriteNpyDispatch(path, shape, data, type);
}

void WriteNpy(const std::string& path, const NpyArray& array, NpyWriteType type) {
  if (array.data.size() != array.NumElements()) {
    Fail("npy file", path, "array of shape " + FormatNpyShape(array.shape) + " holds " +
                               std::to_string(array.data.size()) + " values");
  }
  WriteNpyDispatch(path, array.shape, array.data.data(), type);
}

}  // namespace madsfm
