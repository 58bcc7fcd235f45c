// Creating an empty COLMAP database (the exact 3.8 schema of `colmap database_creator`, ../shared/docs/colmap.md),
// for importing matches from other matchers (as hloc does) and for tests.
#pragma once

#include <string>

namespace madsfm::colmap {

// The CREATE statements of a COLMAP 3.8 database (and PRAGMA user_version = 3800).
const char* Colmap38SchemaSql();

// Creates `path` with the 3.8 schema; throws std::runtime_error if the file exists or cannot be created.
void CreateColmap38Database(const std::string& path);

}  // namespace madsfm::colmap
