// Small RAII helpers over SQLite's C API shared by the database layer and the shard files: every error becomes a
// std::runtime_error naming the file.
#pragma once

#include <sqlite3.h>
#include <sys/stat.h>

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

namespace madsfm::colmap::sqlite {

[[noreturn]] inline void ThrowSqlite(const std::string& path, sqlite3* db, const std::string& what) {
  std::string message = "'" + path + "': " + what;
  if (db != nullptr) message += ": " + std::string(sqlite3_errmsg(db));
  throw std::runtime_error(message);
}

// RAII prepared statement bound to one database; every error becomes a std::runtime_error naming the file.
class Statement {
 public:
  Statement(sqlite3* db, const std::string& path, const std::string& sql) : db_(db), path_(path), sql_(sql) {
    if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &stmt_, nullptr) != SQLITE_OK) {
      ThrowSqlite(path_, db_, "cannot prepare \"" + sql_ + "\"");
    }
  }
  ~Statement() { sqlite3_finalize(stmt_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  void BindInt64(int i, int64_t value) { Check(sqlite3_bind_int64(stmt_, i, value), "bind"); }
  void BindDouble(int i, double value) { Check(sqlite3_bind_double(stmt_, i, value), "bind"); }
  void BindNull(int i) { Check(sqlite3_bind_null(stmt_, i), "bind"); }
  void BindText(int i, const std::string& text) {
    Check(sqlite3_bind_text(stmt_, i, text.data(), static_cast<int>(text.size()), SQLITE_TRANSIENT), "bind");
  }
  // An empty blob is bound as a zero-length blob (not NULL).
  void BindBlob(int i, const void* data, size_t num_bytes) {
    if (num_bytes == 0) {
      Check(sqlite3_bind_zeroblob(stmt_, i, 0), "bind");
    } else {
      Check(sqlite3_bind_blob64(stmt_, i, data, num_bytes, SQLITE_TRANSIENT), "bind");
    }
  }

  // Returns true while there is a row.
  bool Step() {
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    ThrowSqlite(path_, db_, "\"" + sql_ + "\" failed");
  }
  // Ready for the next execution with new bindings.
  void Reset() {
    sqlite3_reset(stmt_);
    sqlite3_clear_bindings(stmt_);
  }
  void Run() {
    while (Step()) {
    }
  }

  bool IsNull(int col) const { return sqlite3_column_type(stmt_, col) == SQLITE_NULL; }
  int64_t Int64(int col) const { return sqlite3_column_int64(stmt_, col); }
  // NULL reads as NaN (SQLite stores NaN as NULL).
  double Double(int col) const {
    return IsNull(col) ? std::numeric_limits<double>::quiet_NaN() : sqlite3_column_double(stmt_, col);
  }
  std::string Text(int col) const {
    const unsigned char* text = sqlite3_column_text(stmt_, col);
    const int n = sqlite3_column_bytes(stmt_, col);
    return text == nullptr ? std::string() : std::string(reinterpret_cast<const char*>(text), n);
  }
  // Pointer and size of a blob column (nullptr / 0 for NULL or empty blobs).
  const void* Blob(int col, size_t* num_bytes) const {
    const void* data = sqlite3_column_blob(stmt_, col);
    *num_bytes = static_cast<size_t>(sqlite3_column_bytes(stmt_, col));
    return data;
  }

 private:
  void Check(int rc, const char* what) {
    if (rc != SQLITE_OK) ThrowSqlite(path_, db_, std::string(what) + " in \"" + sql_ + "\"");
  }
  sqlite3* db_;
  const std::string& path_;
  std::string sql_;
  sqlite3_stmt* stmt_ = nullptr;
};

inline void Exec(sqlite3* db, const std::string& path, const std::string& sql) {
  char* error = nullptr;
  if (sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error) != SQLITE_OK) {
    const std::string message = error != nullptr ? error : sqlite3_errmsg(db);
    sqlite3_free(error);
    throw std::runtime_error("'" + path + "': \"" + sql + "\" failed: " + message);
  }
}

// A writer killed inside a transaction leaves a hot rollback journal, which only a read-write connection can roll
// back; a read-only connection then fails. Called before opening `path` read-only: rolls the journal back (as the
// next writer would), or throws saying what is wrong when the file is read-only.
inline void RollBackHotJournal(const std::string& path, int busy_timeout_ms) {
  struct stat js, st;
  const std::string journal = path + "-journal";
  if (::stat(journal.c_str(), &js) != 0 || js.st_size == 0 || ::stat(path.c_str(), &st) != 0) return;
  if ((st.st_mode & (S_IWUSR | S_IWGRP | S_IWOTH)) == 0) {
    throw std::runtime_error("'" + path + "' has an unfinished transaction ('" + journal +
                             "') from an interrupted write, and the file is read-only: make it writable "
                             "so that SQLite can roll the transaction back");
  }
  sqlite3* recover = nullptr;
  if (sqlite3_open_v2(path.c_str(), &recover, SQLITE_OPEN_READWRITE, nullptr) == SQLITE_OK) {
    sqlite3_busy_timeout(recover, busy_timeout_ms);
    sqlite3_exec(recover, "SELECT count(*) FROM sqlite_master", nullptr, nullptr, nullptr);
  }
  sqlite3_close(recover);
}

}  // namespace madsfm::colmap::sqlite
