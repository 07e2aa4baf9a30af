#include "write_queue.h"

namespace hapsim::service::store_internal {

bool WriteQueue::Push(StoreWrite write) {
  std::lock_guard lock(mutex_);
  if (items_.size() >= capacity_ || stopping_) {
    ++dropped_;
    return false;
  }
  items_.push_back(std::move(write));
  ++pushed_seq_;
  // Only the first write wakes the writer: later ones wait for its batch
  // deadline anyway, and waking it on each would cost a context switch.
  if (items_.size() == 1) wake_.notify_one();
  return true;
}

bool WriteQueue::Take(std::vector<StoreWrite>* batch, std::uint64_t* last_seq) {
  std::unique_lock lock(mutex_);
  for (;;) {
    if (items_.empty()) {
      if (stopping_) return false;
      wake_.wait(lock);
    } else if (stopping_ || flush_seq_ > done_seq_ || Clock::now() >= next_take_) {
      break;
    } else {
      wake_.wait_until(lock, next_take_);
    }
  }
  batch->clear();
  batch->swap(items_);
  *last_seq = pushed_seq_;
  next_take_ = Clock::now() + batch_interval_;
  return true;
}

void WriteQueue::Done(std::uint64_t seq) {
  {
    std::lock_guard lock(mutex_);
    done_seq_ = seq;
  }
  done_.notify_all();
}

void WriteQueue::Flush() {
  std::unique_lock lock(mutex_);
  const std::uint64_t target = pushed_seq_;
  if (done_seq_ >= target) return;
  if (flush_seq_ < target) flush_seq_ = target;
  wake_.notify_one();
  done_.wait(lock, [&] { return done_seq_ >= target; });
}

void WriteQueue::Stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_one();
}

std::uint64_t WriteQueue::dropped() const {
  std::lock_guard lock(mutex_);
  return dropped_;
}

}  // namespace hapsim::service::store_internal
