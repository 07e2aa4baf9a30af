// The store's one writer thread: takes the queued writes a batch at a time
// and commits each batch as one transaction on its own connection. Errors
// are logged and counted, never thrown: the server must not crash because
// its database did.
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "sqlite_handle.h"
#include "write_queue.h"

namespace hapsim::service::store_internal {

class StoreWriter {
 public:
  // Prepares the statements (throws std::runtime_error), then starts the thread.
  StoreWriter(DbHandle db, std::string path, WriteQueue& queue, std::function<void()> before_batch);
  ~StoreWriter();  // stops the queue (what is queued is committed first) and joins

  std::uint64_t errors() const { return errors_.load(std::memory_order_relaxed); }
  std::uint64_t committed() const { return committed_.load(std::memory_order_relaxed); }

 private:
  void Run();
  void Commit(const std::vector<StoreWrite>& batch);
  bool Apply(const StoreWrite& write);
  bool Step(Statement& s, const char* what);  // runs a bound statement, resets it
  void Error(const std::string& what);

  DbHandle db_;  // first: outlives the statements
  std::string path_;
  WriteQueue& queue_;
  std::function<void()> before_batch_;
  Statement begin_, commit_, rollback_;
  Statement upsert_session_, remove_session_, upsert_trial_, save_score_sheet_, note_roster_, upsert_recording_,
      mark_recording_deleted_;
  std::atomic<std::uint64_t> errors_{0}, committed_{0};
  std::thread thread_;  // last: starts once everything above exists
};

// Log only the first few of a repeating problem, then every power of two.
inline bool WorthLogging(std::uint64_t count) { return count <= 10 || (count & (count - 1)) == 0; }

}  // namespace hapsim::service::store_internal
