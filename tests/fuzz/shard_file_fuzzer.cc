// libFuzzer target: the result blobs of madsfm's shard files (colmap_ext/shard/shard_file.h), as merge_shards reads
// them. Input: uint16 little-endian size of the geometry blob (0xFFFF: NULL; clamped to what is left), the geometry
// blob, and the rest is the madsfm blob, stored as the one result row of a valid shard file. Opening the file,
// listing its pairs and decoding every result must either work or throw a std::exception naming the file.
#include <sqlite3.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>

#include "colmap_ext/shard/shard_file.h"
#include "fuzz_util.h"

namespace {

// The bytes of a valid shard file with one assigned pair and no result, made once.
const std::string& TemplateBytes() {
  static const std::string bytes = [] {
    const std::string p = madsfm::fuzz::ScratchDir() + "/template.sqlite";
    madsfm::colmap::ShardInfo info;
    info.database_fingerprint = info.split_fingerprint = "00";
    info.options_fingerprint = "fuzz";
    madsfm::colmap::ShardFile::Create(p, info, {madsfm::colmap::ImagePairToPairId(1, 2)});
    return madsfm::fuzz::ReadFile(p);
  }();
  return bytes;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = madsfm::fuzz::ScratchDir() + "/input.sqlite";
  // Not std::filesystem::copy_file: its sendfile() fails with EINTR when one of libFuzzer's timer signals arrives.
  const std::string& templ = TemplateBytes();
  madsfm::fuzz::WriteFile(path, reinterpret_cast<const uint8_t*>(templ.data()), templ.size());
  size_t geometry_size = size >= 2 ? (data[0] | (data[1] << 8)) : 0xFFFF;
  const uint8_t* rest = data + (size >= 2 ? 2 : size);
  size_t left = size >= 2 ? size - 2 : 0;
  const bool null_geometry = geometry_size == 0xFFFF;
  if (null_geometry) geometry_size = 0;
  if (geometry_size > left) geometry_size = left;

  sqlite3* db = nullptr;
  if (sqlite3_open(path.c_str(), &db) != SQLITE_OK) std::abort();
  sqlite3_stmt* st = nullptr;
  if (sqlite3_prepare_v2(db, "INSERT INTO madsfm_shard_results(pair_id, geometry, madsfm) VALUES(?, ?, ?)", -1, &st,
                         nullptr) != SQLITE_OK) {
    std::abort();
  }
  sqlite3_bind_int64(st, 1, static_cast<sqlite3_int64>(madsfm::colmap::ImagePairToPairId(1, 2)));
  if (null_geometry) sqlite3_bind_null(st, 2);
  else sqlite3_bind_blob(st, 2, rest, static_cast<int>(geometry_size), SQLITE_TRANSIENT);
  sqlite3_bind_blob(st, 3, rest + geometry_size, static_cast<int>(left - geometry_size), SQLITE_TRANSIENT);
  if (sqlite3_step(st) != SQLITE_DONE) std::abort();
  sqlite3_finalize(st);
  sqlite3_close(db);

  try {
    auto shard = madsfm::colmap::ShardFile::Open(path, /*read_only=*/true);
    shard->AssignedPairs();
    shard->ResultPairs();
    size_t n = 0;
    shard->ForEachResult([&](const madsfm::colmap::ShardResult& r) { n += r.madsfm.pair_id != 0; });
  } catch (const std::exception&) {
    // A clean rejection.
  }
  return 0;
}
