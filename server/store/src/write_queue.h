// The store's bounded write queue: callers push without blocking (a full
// queue drops the write), the writer thread takes everything queued as one
// batch, at most every batch interval, sooner when Flush or Stop asks.
#pragma once
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <variant>
#include <vector>

#include "hapsim/store/stored_rows.h"

namespace hapsim::service::store_internal {

struct RemoveSessionWrite {
  std::string id;
};
struct NoteRosterWrite {
  StoredRosterEntry entry;  // first_seen == last_seen == the time noted
};
struct MarkRecordingDeletedWrite {
  std::string path;
};
using StoreWrite = std::variant<StoredSession, RemoveSessionWrite, StoredTrial, StoredScoreSheet, NoteRosterWrite,
                                StoredRecording, MarkRecordingDeletedWrite>;

class WriteQueue {
 public:
  using Clock = std::chrono::steady_clock;
  WriteQueue(std::size_t capacity, Clock::duration batch_interval)
      : capacity_(capacity), batch_interval_(batch_interval) {}

  // Any thread. False: full (or stopped); the write is dropped and counted.
  bool Push(StoreWrite write);
  // Writer thread: waits for a batch; false once stopped and drained.
  // `*last_seq`: the sequence number of the batch's last write.
  bool Take(std::vector<StoreWrite>* batch, std::uint64_t* last_seq);
  // Writer thread: every write up to `seq` is committed (or failed).
  void Done(std::uint64_t seq);
  // Any thread: waits until every write pushed before the call is Done.
  void Flush();
  // Takes what is left at once, then makes Take return false.
  void Stop();
  std::uint64_t dropped() const;

 private:
  const std::size_t capacity_;
  const Clock::duration batch_interval_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;  // the writer: work, a flush or a stop
  std::condition_variable done_;  // flushers
  std::vector<StoreWrite> items_;
  std::uint64_t pushed_seq_ = 0, done_seq_ = 0, flush_seq_ = 0, dropped_ = 0;
  Clock::time_point next_take_{};
  bool stopping_ = false;
};

}  // namespace hapsim::service::store_internal
