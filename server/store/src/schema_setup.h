// Readies a freshly opened writer connection: checks the file is a hapsim
// results database (or empty), refuses a schema newer than `steps` know,
// sets the pragmas (WAL, synchronous, foreign keys) and migrates.
#pragma once
#include <sqlite3.h>

#include <string>
#include <vector>

#include "hapsim/store/schema.h"

namespace hapsim::service::store_internal {

// Returns the file's schema version afterwards. Throws std::runtime_error
// naming `path`; a refused file is left untouched.
int SetUpDatabase(sqlite3* db, const std::string& path, const std::vector<SchemaStep>& steps, bool fsync_every_commit);

}  // namespace hapsim::service::store_internal
