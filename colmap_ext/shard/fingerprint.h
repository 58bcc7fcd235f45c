// Content fingerprints that tie shard files to the database and options they were made from (issue 7).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace madsfm::colmap {

class Database;

// A 128-bit non-cryptographic hash (two independent 64-bit FNV-1a style lanes with a final avalanche), written as
// 32 hex digits. Detects accidental mix-ups of files, not adversaries.
class Fingerprinter {
 public:
  void Add(const void* data, size_t size);
  void Add(const std::string& s);  // length-prefixed, so ("ab", "c") != ("a", "bc")
  void Add(int64_t v);
  std::string Hex() const;

 private:
  uint64_t a_ = 0xcbf29ce484222325ull, b_ = 0x84222325cbf29ce4ull;
  uint64_t size_ = 0;
};

// What two_view_estimator reads from a database, hashed: the schema version, every camera row (model, size, params,
// prior flag), every image (id, name, camera), keypoint counts per image and the (pair_id, number of matches) of
// every matched pair. Keypoint coordinates and match indices are not read (that would mean reading the whole
// database); two_view_geometries and madsfm's own tables are left out, as merging changes them.
std::string DatabaseFingerprint(const Database& db);

}  // namespace madsfm::colmap
