// SharedSnapshot<T>: the current version of an immutable T, published by
// writers and read by anyone (copy-on-write). Readers get a shared_ptr that
// keeps their version alive however long they hold it; a writer replaces the
// pointer and never waits for readers.
//
// A mutex guards only the pointer copy (nanoseconds); no one holds it while
// doing anything else, so a reader on a real-time path waits at most for
// another pointer copy — never for the work that produced the new version.
// (libstdc++ 12's std::atomic<std::shared_ptr> unlocks its internal spin
// lock with a relaxed store after a load, which ThreadSanitizer rightly
// reports as a race with the next store.)
#pragma once
#include <memory>
#include <mutex>
#include <utility>

namespace hapsim::common {

template <class T>
class SharedSnapshot {
 public:
  explicit SharedSnapshot(std::shared_ptr<const T> initial) : current_(std::move(initial)) {}

  std::shared_ptr<const T> Load() const {
    std::lock_guard lock(mutex_);
    return current_;
  }
  void Store(std::shared_ptr<const T> next) {
    {
      std::lock_guard lock(mutex_);
      current_.swap(next);
    }
    // `next` (the old version) is released here, outside the lock.
  }

 private:
  mutable std::mutex mutex_;
  std::shared_ptr<const T> current_;
};

}  // namespace hapsim::common
