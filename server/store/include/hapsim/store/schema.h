// The results database's schema, as an ordered list of migration steps:
// step N takes a file from schema version N-1 to N (PRAGMA user_version),
// applied in one transaction each, so a crash mid-migration leaves the file
// at the last completed version. Version 0 is an empty file. Steps are only
// ever appended: a released step is never edited (files in the field went
// through it). A file newer than the last step is refused, never downgraded.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace hapsim::service {

struct SchemaStep {
  int to_version = 0;  // the file's version after this step: the previous step's + 1
  std::string sql;     // one or more statements
};

// This build's steps, oldest first.
const std::vector<SchemaStep>& SchemaSteps();

// The file header's application_id ("HAPS"): tells a hapsim results database
// from any other SQLite file.
inline constexpr std::int32_t kStoreApplicationId = 0x48415053;

}  // namespace hapsim::service
