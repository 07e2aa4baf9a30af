// Each table's columns, and how a row struct binds to them and reads back
// from them: one column list per table, shared by the writer's upserts and
// the reader's selects so the two cannot disagree on the order.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "hapsim/store/stored_rows.h"
#include "sqlite_handle.h"

namespace hapsim::service::store_internal {

struct TableSpec {
  std::string_view name;
  std::vector<std::string_view> columns;  // in bind/read order
  std::vector<std::string_view> key;      // the primary key's columns
};

extern const TableSpec kSessionsTable;
extern const TableSpec kTrialsTable;
extern const TableSpec kRecordingsTable;

// INSERT ... ON CONFLICT (key) DO UPDATE SET every other column.
std::string UpsertSql(const TableSpec& table);
// SELECT the columns FROM the table, then `tail` (WHERE / ORDER BY).
std::string SelectSql(const TableSpec& table, std::string_view tail);

void BindSession(Statement& s, const StoredSession& row);
StoredSession ReadSession(const Statement& s);  // throws std::invalid_argument on a malformed params text
void BindTrial(Statement& s, const StoredTrial& row);
StoredTrial ReadTrial(const Statement& s);
void BindRecording(Statement& s, const StoredRecording& row);
StoredRecording ReadRecording(const Statement& s);

}  // namespace hapsim::service::store_internal
