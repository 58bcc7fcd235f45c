// Test helpers for COLMAP databases: a builder that overwrites, raw SQL, integrity checks and table dumps.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "colmap_ext/database/database_builder.h"

namespace madsfm::testing {

// colmap::DatabaseBuilder that replaces an existing file (tests rebuild their projects in fixed temp paths).
class ColmapDatabaseBuilder : public colmap::DatabaseBuilder {
 public:
  explicit ColmapDatabaseBuilder(const std::string& path);
};

// Executes SQL on an existing database file (throws on error).
void ExecSql(const std::string& path, const std::string& sql);
// Runs PRAGMA integrity_check; returns its first result row ("ok" when healthy).
std::string IntegrityCheck(const std::string& path);
// Dumps a table (all columns, blobs as hex) sorted by its first column, to compare databases.
std::string DumpTable(const std::string& path, const std::string& table);

}  // namespace madsfm::testing
