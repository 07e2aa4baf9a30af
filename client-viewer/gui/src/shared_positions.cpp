#include "hapsim/gui/shared_positions.h"

namespace hapsim::gui {

const std::vector<float>& SharedPositions::values() const {
  static const std::vector<float> kNone;
  return values_ ? *values_ : kNone;
}

std::shared_ptr<std::vector<float>> PositionBuffers::Writable() {
  for (const auto& buffer : buffers_) {
    if (buffer.use_count() == 1) return buffer;
  }
  auto fresh = std::make_shared<std::vector<float>>();
  if (buffers_.size() < kKept) buffers_.push_back(fresh);
  return fresh;
}

}  // namespace hapsim::gui
