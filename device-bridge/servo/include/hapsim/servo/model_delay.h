// A measurement aid: holds every force model the bridge receives for a set
// time before the servo sees it, as a longer link would — the model then
// "arrives" late, so its age and the round trip count from its release.
// It shows how the local force model and the safety chain (the passivity
// controller above all) cope with a link of 0-200 ms without building one.
// The ring is sized once (capacity models, dropping the oldest when full);
// Take never allocates.
#pragma once
#include <cstdint>
#include <vector>

#include "hapsim/common/latest_value.h"
#include "hapsim/servo/servo_messages.h"

namespace hapsim::bridge {

class ModelDelay {
 public:
  // delay_s in [0, 1]; capacity: models held at once (at 1 kHz, 1 per ms).
  ModelDelay(double delay_s, std::size_t capacity = 1024);
  bool enabled() const { return delay_ns_ > 0; }
  // Moves a new model from the inbox into the ring, then hands out the
  // newest model whose release time (arrival + delay) has come by now_ns,
  // with received_ns set to that release time. False when none is due.
  bool Take(common::LatestValue<ReceivedModel>& inbox, std::int64_t now_ns, ReceivedModel* out);
  std::uint64_t dropped() const { return dropped_; }  // pushed out of a full ring before release

 private:
  std::int64_t delay_ns_;
  std::vector<ReceivedModel> ring_;
  std::size_t head_ = 0, size_ = 0;  // oldest at head_
  std::uint64_t dropped_ = 0;
};

}  // namespace hapsim::bridge
