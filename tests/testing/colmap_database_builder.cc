#include "testing/colmap_database_builder.h"

#include <sqlite3.h>

#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace madsfm::testing {
namespace {
const std::string& RemoveFirst(const std::string& path) {
  std::remove(path.c_str());
  return path;
}
}  // namespace

ColmapDatabaseBuilder::ColmapDatabaseBuilder(const std::string& path) : colmap::DatabaseBuilder(RemoveFirst(path)) {}

void ExecSql(const std::string& path, const std::string& sql) {
  sqlite3* db;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE, nullptr) != SQLITE_OK) {
    sqlite3_close(db);
    throw std::runtime_error("cannot open " + path);
  }
  char* err = nullptr;
  const int rc = sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &err);
  const std::string msg = err ? err : "";
  sqlite3_free(err);
  sqlite3_close(db);
  if (rc != SQLITE_OK) throw std::runtime_error("sql: " + msg);
}

std::string IntegrityCheck(const std::string& path) {
  sqlite3* db;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) return "cannot open";
  sqlite3_stmt* st;
  std::string result = "no result";
  if (sqlite3_prepare_v2(db, "PRAGMA integrity_check", -1, &st, nullptr) == SQLITE_OK) {
    if (sqlite3_step(st) == SQLITE_ROW) result = reinterpret_cast<const char*>(sqlite3_column_text(st, 0));
    sqlite3_finalize(st);
  }
  sqlite3_close(db);
  return result;
}

std::string DumpTable(const std::string& path, const std::string& table) {
  sqlite3* db;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) return "cannot open";
  sqlite3_stmt* st;
  std::ostringstream out;
  if (sqlite3_prepare_v2(db, ("SELECT * FROM " + table + " ORDER BY 1").c_str(), -1, &st, nullptr) == SQLITE_OK) {
    while (sqlite3_step(st) == SQLITE_ROW) {
      for (int c = 0; c < sqlite3_column_count(st); ++c) {
        if (sqlite3_column_type(st, c) == SQLITE_BLOB) {
          const auto* b = static_cast<const unsigned char*>(sqlite3_column_blob(st, c));
          char hex[3];
          for (int i = 0; i < sqlite3_column_bytes(st, c); ++i) {
            std::snprintf(hex, sizeof(hex), "%02x", b[i]);
            out << hex;
          }
        } else if (sqlite3_column_type(st, c) == SQLITE_NULL) {
          out << "NULL";
        } else {
          out << sqlite3_column_text(st, c);
        }
        out << '|';
      }
      out << '\n';
    }
    sqlite3_finalize(st);
  } else {
    out << "no table " << table;
  }
  sqlite3_close(db);
  return out.str();
}

}  // namespace madsfm::testing
