#include "hapsim/gui/force_history.h"

namespace hapsim::gui {

ForceHistory& ForceHistory::operator=(const ForceHistory& other) {
  if (this == &other) return *this;
  chunks_ = other.chunks_;
  if (!chunks_.empty() && chunks_.back()->size() < kChunk) {
    // The chunk still filling is the source's to append to: take a copy of it.
    auto own = std::make_shared<std::vector<PlotSample>>();
    own->reserve(kChunk);
    own->assign(other.chunks_.back()->begin(), other.chunks_.back()->end());
    chunks_.back() = std::move(own);
  }
  first_ = other.first_;
  size_ = other.size_;
  return *this;
}

ForceHistory& ForceHistory::operator=(ForceHistory&& other) noexcept {
  if (this == &other) return *this;
  chunks_ = std::move(other.chunks_);
  first_ = std::exchange(other.first_, 0);
  size_ = std::exchange(other.size_, 0);
  other.chunks_.clear();
  return *this;
}

void ForceHistory::push_back(const PlotSample& sample) {
  if (chunks_.empty() || chunks_.back()->size() == kChunk) {
    chunks_.push_back(std::make_shared<std::vector<PlotSample>>());
    chunks_.back()->reserve(kChunk);
  }
  chunks_.back()->push_back(sample);
  ++size_;
}

void ForceHistory::clear() {
  chunks_.clear();
  first_ = size_ = 0;
}

void ForceHistory::DropOldest(std::size_t n) {
  if (n >= size_) {
    clear();
    return;
  }
  first_ += n;
  size_ -= n;
  const std::size_t whole = first_ / kChunk;
  chunks_.erase(chunks_.begin(), chunks_.begin() + static_cast<std::ptrdiff_t>(whole));
  first_ -= whole * kChunk;
}

}  // namespace hapsim::gui
