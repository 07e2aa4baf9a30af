// What follows a session's ticks from outside the runtime — the classroom's
// trial metrics today, a recorder tomorrow — without the session knowing it.
// A session holds at most one listener, given at creation and called on the
// tick worker: it must not block, and after its first tick it must not
// allocate (the 1 kHz loop allocates nothing).
#pragma once
#include <memory>
#include <vector>

#include "hapsim/core/haptics/local_force_model.h"
#include "hapsim/core/scenes/scene.h"
#include "hapsim/runtime/tick_input.h"

namespace hapsim::service {

// One tick as it ended: its input and the scene just stepped.
struct TickOutcome {
  const TickInput& input;
  const core::Scene& scene;
  core::ContactState contact = core::ContactState::kFree;  // the step's force model state
  double tool_force_N = 0.0;                               // |force of the tissue on the tool|
};

class TickListener {
 public:
  virtual ~TickListener() = default;
  // Tick worker, after every step (also paused ticks).
  virtual void OnTick(const TickOutcome& tick) = 0;
  // Tick worker, right after the session published a snapshot for viewers
  // (at the frame rate): the moment to publish what the listener keeps.
  virtual void OnSnapshotPublished() {}
};

// Several listeners behind one session (the trials and the recorder), called
// in order.
class TickListenerList final : public TickListener {
 public:
  explicit TickListenerList(std::vector<std::shared_ptr<TickListener>> listeners) : listeners_(std::move(listeners)) {}
  void OnTick(const TickOutcome& tick) override {
    for (const auto& l : listeners_) l->OnTick(tick);
  }
  void OnSnapshotPublished() override {
    for (const auto& l : listeners_) l->OnSnapshotPublished();
  }
  const std::vector<std::shared_ptr<TickListener>>& listeners() const { return listeners_; }

 private:
  std::vector<std::shared_ptr<TickListener>> listeners_;
};

// The listener of type T a session follows its ticks with: `listener`
// itself, or one in its list; nullptr when there is none.
template <typename T>
T* FindTickListener(TickListener* listener) {
  if (auto* found = dynamic_cast<T*>(listener)) return found;
  if (auto* list = dynamic_cast<TickListenerList*>(listener)) {
    for (const auto& l : list->listeners()) {
      if (auto* found = dynamic_cast<T*>(l.get())) return found;
    }
  }
  return nullptr;
}

}  // namespace hapsim::service
