// Thin RAII over the SQLite C API for the store: a connection, a prepared
// statement, and cursors that bind and read a row's columns in order.
#pragma once
#include <sqlite3.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace hapsim::service::store_internal {

struct DbCloser {
  void operator()(sqlite3* db) const { sqlite3_close_v2(db); }
};
using DbHandle = std::unique_ptr<sqlite3, DbCloser>;

// "results database 'PATH': WHAT: sqlite's message" (every store error names the file).
std::string StoreErrorText(const std::string& path, std::string_view what, std::string_view detail);

// Opens `path` with `flags` and the busy timeout. Throws std::runtime_error.
DbHandle OpenDb(const std::string& path, int flags, int busy_timeout_ms);

// Runs one or more statements; SQLITE_OK or the error code (sqlite3_errmsg has the text).
int ExecSql(sqlite3* db, const std::string& sql);

class Statement {
 public:
  Statement(sqlite3* db, std::string_view sql);  // throws std::runtime_error (with sqlite's message)
  ~Statement() { sqlite3_finalize(stmt_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  int Step() { return sqlite3_step(stmt_); }  // SQLITE_ROW, SQLITE_DONE or an error
  void Reset() {                              // ready for new bindings (its error, if any, was Step's)
    sqlite3_reset(stmt_);
    sqlite3_clear_bindings(stmt_);
  }
  sqlite3_stmt* get() const { return stmt_; }

 private:
  sqlite3_stmt* stmt_ = nullptr;
};

// Binds parameters 1, 2, ... in call order. Text is copied (SQLITE_TRANSIENT).
class Binder {
 public:
  explicit Binder(Statement& s) : stmt_(s.get()) {}
  Binder& Int(std::int64_t v);
  Binder& Uint(std::uint64_t v) { return Int(static_cast<std::int64_t>(v)); }  // < 2^63 in practice
  Binder& Real(double v);                                                      // NaN binds NULL
  Binder& Text(std::string_view v);
  Binder& OptInt(const std::optional<std::int64_t>& v);

 private:
  sqlite3_stmt* stmt_;
  int index_ = 1;
};

// Reads columns 0, 1, ... of the current row in call order.
class Cursor {
 public:
  explicit Cursor(const Statement& s) : stmt_(s.get()) {}
  std::int64_t Int() { return sqlite3_column_int64(stmt_, index_++); }
  std::uint64_t Uint() { return static_cast<std::uint64_t>(Int()); }
  double Real();  // NULL reads NaN
  std::string Text();
  std::optional<std::int64_t> OptInt();

 private:
  sqlite3_stmt* stmt_;
  int index_ = 0;
};

}  // namespace hapsim::service::store_internal
