// Vertex positions handed from the stream's thread to the render thread
// without copying them: a frame's positions are written once into a buffer
// that copies of the scene then share read-only. The writer takes a buffer
// no copy holds any more (PositionBuffers), so a steady stream cycles
// through three: the newest, the one being drawn, the one being written.
#pragma once
#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

namespace hapsim::gui {

// 3 floats per vertex slot [m]; empty before the first keyframe.
class SharedPositions {
 public:
  SharedPositions() = default;
  explicit SharedPositions(std::shared_ptr<const std::vector<float>> values) : values_(std::move(values)) {}

  std::size_t size() const { return values_ ? values_->size() : 0; }
  bool empty() const { return size() == 0; }
  float operator[](std::size_t i) const { return (*values_)[i]; }
  const float* data() const { return values_ ? values_->data() : nullptr; }
  const std::vector<float>& values() const;

 private:
  std::shared_ptr<const std::vector<float>> values_;
};

// The writer's side. LiveScene calls Writable under the mutex it also holds
// while a view copies or replaces its SharedPositions, so a buffer no copy
// holds was last read before that lock was taken.
class PositionBuffers {
 public:
  // A buffer no SharedPositions holds (else a new one), to fill and share.
  std::shared_ptr<std::vector<float>> Writable();

 private:
  static constexpr std::size_t kKept = 3;  // buffers kept for reuse; more copies alive: fresh ones
  std::vector<std::shared_ptr<std::vector<float>>> buffers_;
};

}  // namespace hapsim::gui
