// libFuzzer target: the blob parsing of madsfm::colmap::Database on a COLMAP 3.8 database whose rows come from the
// input. Layout (little-endian, a short input is zero-padded to the 60-byte header):
//   int32 camera model id, int64 width, int64 height, int32 prior_focal_length,
//   int64 keypoints rows, int64 keypoints cols, int64 matches rows, int64 matches cols,
//   uint16 params blob size, uint16 keypoints blob size (0xFFFF: NULL blob; sizes are clamped to what is left),
//   then the params blob, the keypoints blob, and the rest is the matches blob.
// The database holds camera 1, images 1 and 2 (camera 1; image 1 has the keypoints row) and the matches row of the
// pair (1, 2). A std::exception is a clean rejection; anything else is a finding.
#include <sqlite3.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>

#include "colmap_ext/database/database.h"
#include "colmap_ext/database/database_schema.h"
#include "fuzz_util.h"

namespace {

// The bytes of an empty 3.8 database, created once.
const std::string& EmptyDatabaseBytes() {
  static const std::string bytes = [] {
    const std::string path = madsfm::fuzz::ScratchDir() + "/template.db";
    madsfm::colmap::CreateColmap38Database(path);
    std::ifstream in(path, std::ios::binary);
    std::string b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::remove(path.c_str());
    return b;
  }();
  return bytes;
}

void Check(int rc, sqlite3* db, const char* what) {
  if (rc != SQLITE_OK && rc != SQLITE_DONE) {
    std::fprintf(stderr, "harness error: %s: %s\n", what, sqlite3_errmsg(db));
    std::abort();
  }
}

// Runs sql with the given bindings (int64 or blob; a null blob pointer with size -1 binds NULL).
struct Binding {
  bool is_blob;
  int64_t value;
  const uint8_t* blob;
  int blob_size;
};
void Run(sqlite3* db, const char* sql, std::initializer_list<Binding> bindings) {
  sqlite3_stmt* st = nullptr;
  Check(sqlite3_prepare_v2(db, sql, -1, &st, nullptr), db, sql);
  int i = 1;
  for (const Binding& b : bindings) {
    if (!b.is_blob) {
      Check(sqlite3_bind_int64(st, i, b.value), db, "bind");
    } else if (b.blob_size < 0) {
      Check(sqlite3_bind_null(st, i), db, "bind");
    } else {
      Check(sqlite3_bind_blob(st, i, b.blob_size ? b.blob : reinterpret_cast<const uint8_t*>(""), b.blob_size,
                              SQLITE_TRANSIENT), db, "bind");
    }
    ++i;
  }
  Check(sqlite3_step(st), db, sql);
  sqlite3_finalize(st);
}

Binding Int(int64_t v) { return {false, v, nullptr, 0}; }
Binding Blob(const uint8_t* p, int n) { return {true, 0, p, n}; }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  constexpr size_t kHeader = 60;
  uint8_t header[kHeader] = {};
  std::memcpy(header, data, std::min(size, kHeader));
  const uint8_t* rest = data + std::min(size, kHeader);
  size_t left = size - std::min(size, kHeader);
  size_t pos = 0;
  auto take = [&](size_t n) {
    uint64_t v = 0;
    for (size_t k = 0; k < n; ++k) v |= static_cast<uint64_t>(header[pos + k]) << (8 * k);
    pos += n;
    return v;
  };
  const int64_t model = static_cast<int32_t>(take(4));
  const int64_t width = static_cast<int64_t>(take(8));
  const int64_t height = static_cast<int64_t>(take(8));
  const int64_t prior = static_cast<int32_t>(take(4));
  const int64_t kp_rows = static_cast<int64_t>(take(8));
  const int64_t kp_cols = static_cast<int64_t>(take(8));
  const int64_t m_rows = static_cast<int64_t>(take(8));
  const int64_t m_cols = static_cast<int64_t>(take(8));
  const uint64_t sizes[2] = {take(2), take(2)};
  Binding blobs[3];
  for (int k = 0; k < 3; ++k) {
    if (k < 2 && sizes[k] == 0xFFFF) {
      blobs[k] = Blob(nullptr, -1);
      continue;
    }
    const size_t n = k < 2 ? std::min<size_t>(sizes[k], left) : left;
    blobs[k] = Blob(rest, static_cast<int>(n));
    rest += n;
    left -= n;
  }

  const std::string path = madsfm::fuzz::ScratchDir() + "/fuzz.db";
  const std::string& empty = EmptyDatabaseBytes();
  madsfm::fuzz::WriteFile(path, reinterpret_cast<const uint8_t*>(empty.data()), empty.size());
  {
    sqlite3* db = nullptr;
    Check(sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE, nullptr), db, "open");
    Run(db, "INSERT INTO cameras (camera_id, model, width, height, params, prior_focal_length) VALUES (1,?,?,?,?,?)",
        {Int(model), Int(width), Int(height), blobs[0], Int(prior)});
    Run(db, "INSERT INTO images (image_id, name, camera_id) VALUES (1, 'a.jpg', 1)", {});
    Run(db, "INSERT INTO images (image_id, name, camera_id) VALUES (2, 'b.jpg', 1)", {});
    Run(db, "INSERT INTO keypoints (image_id, rows, cols, data) VALUES (1,?,?,?)", {Int(kp_rows), Int(kp_cols), blobs[1]});
    Run(db, "INSERT INTO matches (pair_id, rows, cols, data) VALUES (?,?,?,?)",
        {Int(static_cast<int64_t>(madsfm::colmap::ImagePairToPairId(1, 2))), Int(m_rows), Int(m_cols), blobs[2]});
    sqlite3_close(db);
  }

  try {
    const std::unique_ptr<madsfm::colmap::Database> database = madsfm::colmap::Database::Open(path, true);
    try {
      (void)database->ReadCameras();
    } catch (const std::exception&) {
    }
    try {
      (void)database->ReadImages();
    } catch (const std::exception&) {
    }
    for (const madsfm::colmap::image_t id : {1u, 2u}) {
      try {
        const auto keypoints = database->ReadKeypoints(id);
        if (id == 2 && !keypoints.empty()) __builtin_trap();
      } catch (const std::exception&) {
      }
    }
    try {
      for (const auto& [pair_id, n] : database->ReadMatchedPairs()) {
        const auto matches = database->ReadMatches(pair_id);
        if (static_cast<int64_t>(matches.size()) != n) __builtin_trap();  // count and contents must agree
      }
    } catch (const std::exception&) {
    }
    try {
      (void)database->ReadMatches(madsfm::colmap::ImagePairToPairId(1, 2));
    } catch (const std::exception&) {
    }
  } catch (const std::exception&) {
  }
  return 0;
}
