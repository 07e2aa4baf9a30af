// SnapshotRing: a fixed set of SceneSnapshot buffers the tick reuses, so
// publishing a viewer snapshot allocates nothing. A buffer is free for
// rewriting when the ring holds the only reference to it: readers (the
// mailbox to the frame pump, the session's latest snapshot, a GetSnapshot in
// progress) hold shared_ptr copies, and nobody can make a new copy of a
// buffer the ring alone owns. Used by the tick only (one thread at a time).
#pragma once
#include <array>
#include <atomic>
#include <cstddef>
#include <memory>

#include "hapsim/runtime/scene_snapshot.h"

namespace hapsim::service {

class SnapshotRing {
 public:
  static constexpr std::size_t kBuffers = 8;  // mailbox (3) + latest (1) + readers in flight

  struct Sizes {
    std::size_t vertices = 0, triangles = 0;  // the scene's slot capacities
    std::size_t events = 0;                   // recent events carried
    std::size_t edits = 0;                    // topology edits carried (the log capacity)
  };
  explicit SnapshotRing(const Sizes& sizes) {
    for (auto& b : buffers_) {
      b = std::make_shared<SceneSnapshot>();
      b->vertices_m.setZero(3, static_cast<Eigen::Index>(sizes.vertices));
      b->vertex_live.assign(sizes.vertices, 0);
      b->triangles.assign(sizes.triangles, {0, 0, 0});
      b->triangle_parts.assign(sizes.triangles, 0);
      b->triangle_live.assign(sizes.triangles, 0);
      b->recent_events.reserve(sizes.events);
      b->topology_edits.reserve(sizes.edits);
    }
  }

  // A buffer nobody else holds, or nullptr if every one is still being read
  // (then the caller skips this snapshot; a newer one follows).
  std::shared_ptr<SceneSnapshot> Acquire() {
    for (std::size_t i = 0; i < kBuffers; ++i) {
      auto& b = buffers_[(next_ + i) % kBuffers];
      if (b.use_count() == 1) {
        // Pairs with the readers' release of their last reference.
        std::atomic_thread_fence(std::memory_order_acquire);
        next_ = (next_ + i + 1) % kBuffers;
        return b;
      }
    }
    return nullptr;
  }

 private:
  std::array<std::shared_ptr<SceneSnapshot>, kBuffers> buffers_;
  std::size_t next_ = 0;
};

}  // namespace hapsim::service
