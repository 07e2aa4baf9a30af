#include "hapsim/servo/model_delay.h"

#include <cmath>
#include <stdexcept>

namespace hapsim::bridge {

ModelDelay::ModelDelay(double delay_s, std::size_t capacity)
    : delay_ns_(static_cast<std::int64_t>(std::llround(delay_s * 1e9))) {
  if (!(delay_s >= 0.0 && delay_s <= 1.0)) throw std::invalid_argument("model delay must be in [0, 1] s");
  if (delay_ns_ > 0) ring_.resize(capacity);
}

bool ModelDelay::Take(common::LatestValue<ReceivedModel>& inbox, std::int64_t now_ns, ReceivedModel* out) {
  ReceivedModel incoming;
  if (inbox.TakeIfNew(&incoming)) {
    if (size_ == ring_.size()) {  // full: the oldest goes
      head_ = (head_ + 1) % ring_.size();
      --size_;
      ++dropped_;
    }
    incoming.received_ns += delay_ns_;  // when it "arrives"
    ring_[(head_ + size_) % ring_.size()] = incoming;
    ++size_;
  }
  bool found = false;
  while (size_ > 0 && ring_[head_].received_ns <= now_ns) {  // release in order; the newest due wins
    *out = ring_[head_];
    head_ = (head_ + 1) % ring_.size();
    --size_;
    found = true;
  }
  return found;
}

}  // namespace hapsim::bridge
