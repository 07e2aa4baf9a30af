// The force samples a window plots, since the last reset (up to 30 000), in
// chunks of kChunk: a full chunk never changes again and copies of the
// history share it, so handing the history to the render thread every frame
// copies at most the one chunk still filling, not every sample.
#pragma once
#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

namespace hapsim::gui {

struct PlotSample {
  double t_s = 0.0, force_N = 0.0, depth_m = 0.0;
};

class ForceHistory {
 public:
  static constexpr std::size_t kChunk = 500;  // samples per chunk

  ForceHistory() = default;
  ForceHistory(const ForceHistory& other) { *this = other; }
  ForceHistory& operator=(const ForceHistory& other);
  ForceHistory(ForceHistory&& other) noexcept { *this = std::move(other); }
  ForceHistory& operator=(ForceHistory&& other) noexcept;  // leaves `other` empty

  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  const PlotSample& operator[](std::size_t i) const {
    const std::size_t at = first_ + i;
    return (*chunks_[at / kChunk])[at % kChunk];
  }
  const PlotSample& back() const { return (*this)[size_ - 1]; }

  void push_back(const PlotSample& sample);
  void clear();
  void DropOldest(std::size_t n);  // n <= size()

 private:
  // Every chunk is full (shared with copies, never written again) but the
  // last, which this history alone owns.
  std::vector<std::shared_ptr<std::vector<PlotSample>>> chunks_;
  std::size_t first_ = 0;  // samples of chunks_[0] already dropped
  std::size_t size_ = 0;
};

}  // namespace hapsim::gui
