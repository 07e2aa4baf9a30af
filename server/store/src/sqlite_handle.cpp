#include "sqlite_handle.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace hapsim::service::store_internal {

std::string StoreErrorText(const std::string& path, std::string_view what, std::string_view detail) {
  std::string text = "results database '" + path + "': ";
  text += what;
  if (!detail.empty()) {
    text += ": ";
    text += detail;
  }
  return text;
}

DbHandle OpenDb(const std::string& path, int flags, int busy_timeout_ms) {
  sqlite3* raw = nullptr;
  const int rc = sqlite3_open_v2(path.c_str(), &raw, flags, nullptr);
  DbHandle db(raw);  // sqlite hands back a handle even on failure: close it either way
  if (rc != SQLITE_OK) {
    std::string detail = db ? sqlite3_errmsg(db.get()) : sqlite3_errstr(rc);
    if (rc == SQLITE_CANTOPEN) detail += " (does its directory exist, and may this user write there?)";
    throw std::runtime_error(StoreErrorText(path, "cannot open", detail));
  }
  sqlite3_extended_result_codes(db.get(), 1);
  sqlite3_busy_timeout(db.get(), busy_timeout_ms);
  return db;
}

int ExecSql(sqlite3* db, const std::string& sql) { return sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr); }

Statement::Statement(sqlite3* db, std::string_view sql) {
  if (sqlite3_prepare_v3(db, sql.data(), static_cast<int>(sql.size()), SQLITE_PREPARE_PERSISTENT, &stmt_, nullptr) !=
      SQLITE_OK) {
    const std::string message = sqlite3_errmsg(db);
    sqlite3_finalize(stmt_);
    throw std::runtime_error(message + " (in: " + std::string(sql.substr(0, 80)) + ")");
  }
}

Binder& Binder::Int(std::int64_t v) {
  sqlite3_bind_int64(stmt_, index_++, v);
  return *this;
}

Binder& Binder::Real(double v) {
  if (std::isnan(v)) {
    sqlite3_bind_null(stmt_, index_++);
  } else {
    sqlite3_bind_double(stmt_, index_++, v);
  }
  return *this;
}

Binder& Binder::Text(std::string_view v) {
  sqlite3_bind_text64(stmt_, index_++, v.data() ? v.data() : "", v.size(),  // null data would bind NULL
                      SQLITE_TRANSIENT, SQLITE_UTF8);
  return *this;
}

Binder& Binder::OptInt(const std::optional<std::int64_t>& v) {
  if (v) return Int(*v);
  sqlite3_bind_null(stmt_, index_++);
  return *this;
}

double Cursor::Real() {
  const int i = index_++;
  if (sqlite3_column_type(stmt_, i) == SQLITE_NULL) return std::numeric_limits<double>::quiet_NaN();
  return sqlite3_column_double(stmt_, i);
}

std::string Cursor::Text() {
  const int i = index_++;
  const auto* text = sqlite3_column_text(stmt_, i);
  if (!text) return {};
  return std::string(reinterpret_cast<const char*>(text), static_cast<std::size_t>(sqlite3_column_bytes(stmt_, i)));
}

std::optional<std::int64_t> Cursor::OptInt() {
  const int i = index_++;
  if (sqlite3_column_type(stmt_, i) == SQLITE_NULL) return std::nullopt;
  return sqlite3_column_int64(stmt_, i);
}

}  // namespace hapsim::service::store_internal
