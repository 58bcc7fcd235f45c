#include "colmap_ext/shard/fingerprint.h"

#include <sqlite3.h>

#include <cstdio>
#include <stdexcept>

#include "colmap_ext/database/database.h"

namespace madsfm::colmap {
namespace {

uint64_t Avalanche(uint64_t x) {
  x ^= x >> 33;
  x *= 0xff51afd7ed558ccdull;
  x ^= x >> 33;
  x *= 0xc4ceb9fe1a85ec53ull;
  return x ^ (x >> 33);
}

// Hashes every row of a query, column by column with type tags.
void AddQuery(const Database& db, const char* sql, Fingerprinter* fp) {
  sqlite3_stmt* st = nullptr;
  if (sqlite3_prepare_v2(db.handle(), sql, -1, &st, nullptr) != SQLITE_OK) {
    const std::string msg = sqlite3_errmsg(db.handle());
    sqlite3_finalize(st);
    throw std::runtime_error("database '" + db.path() + "': " + msg);
  }
  int rc;
  while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
    for (int c = 0; c < sqlite3_column_count(st); ++c) {
      const int type = sqlite3_column_type(st, c);
      fp->Add(type);
      if (type == SQLITE_INTEGER) {
        fp->Add(static_cast<int64_t>(sqlite3_column_int64(st, c)));
      } else if (type == SQLITE_FLOAT) {
        const double v = sqlite3_column_double(st, c);
        fp->Add(&v, sizeof(v));
      } else if (type == SQLITE_TEXT || type == SQLITE_BLOB) {
        const void* p = type == SQLITE_TEXT ? static_cast<const void*>(sqlite3_column_text(st, c))
                                            : sqlite3_column_blob(st, c);
        const int n = sqlite3_column_bytes(st, c);
        fp->Add(n);
        if (n > 0) fp->Add(p, static_cast<size_t>(n));
      }
    }
  }
  const std::string msg = sqlite3_errmsg(db.handle());
  sqlite3_finalize(st);
  if (rc != SQLITE_DONE) throw std::runtime_error("database '" + db.path() + "': " + msg);
}

}  // namespace

void Fingerprinter::Add(const void* data, size_t size) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < size; ++i) {
    a_ = (a_ ^ p[i]) * 0x100000001b3ull;
    b_ = (b_ ^ p[i]) * 0x00000100000001b3ull + 0x9E3779B97F4A7C15ull;
  }
  size_ += size;
}

void Fingerprinter::Add(const std::string& s) {
  Add(static_cast<int64_t>(s.size()));
  Add(s.data(), s.size());
}

void Fingerprinter::Add(int64_t v) {
  unsigned char bytes[8];
  for (int i = 0; i < 8; ++i) bytes[i] = static_cast<unsigned char>(static_cast<uint64_t>(v) >> (8 * i));
  Add(bytes, 8);
}

std::string Fingerprinter::Hex() const {
  char out[33];
  std::snprintf(out, sizeof(out), "%016llx%016llx", static_cast<unsigned long long>(Avalanche(a_ ^ size_)),
                static_cast<unsigned long long>(Avalanche(b_ + 0x632BE59BD9B4E019ull * size_)));
  return out;
}

std::string DatabaseFingerprint(const Database& db) {
  Fingerprinter fp;
  fp.Add(SchemaVersionName(db.schema()));
  AddQuery(db, "SELECT camera_id, model, width, height, params, prior_focal_length FROM cameras ORDER BY camera_id",
           &fp);
  AddQuery(db, "SELECT image_id, name, camera_id FROM images ORDER BY image_id", &fp);
  AddQuery(db, "SELECT image_id, rows, cols FROM keypoints ORDER BY image_id", &fp);
  AddQuery(db, "SELECT pair_id, rows FROM matches WHERE rows > 0 ORDER BY pair_id", &fp);
  return fp.Hex();
}

}  // namespace madsfm::colmap
