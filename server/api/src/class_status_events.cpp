#include "hapsim/api/class_status_events.h"

#include "hapsim/streaming/frame_encoder.h"

namespace hapsim::service {

namespace {

// The index in snapshot.recent_events of event number `n` (counted over the
// session's life), or -1 when the snapshot no longer holds it.
long SlotOf(const SceneSnapshot& snapshot, std::uint64_t n) {
  const std::uint64_t held = snapshot.recent_events.size();
  if (n >= snapshot.events_total || snapshot.events_total - n > held) return -1;
  return static_cast<long>(held - (snapshot.events_total - n));
}

}  // namespace

void AddEventsWithinBudget(const std::vector<PendingEvents>& sessions, std::size_t budget_bytes,
                           hapsim::v1::ClassStatus* class_status) {
  // Events lost from the snapshots' windows are passed over first.
  for (const PendingEvents& p : sessions) {
    const std::uint64_t held = p.snapshot->recent_events.size();
    const std::uint64_t oldest_held = p.snapshot->events_total > held ? p.snapshot->events_total - held : 0;
    if (*p.events_sent < oldest_held) *p.events_sent = oldest_held;
  }
  bool added_any = false;
  for (bool added_in_round = true; added_in_round;) {
    added_in_round = false;
    for (const PendingEvents& p : sessions) {
      const long slot = SlotOf(*p.snapshot, *p.events_sent);
      if (slot < 0) continue;  // nothing unsent
      auto* events = p.status->mutable_events();
      EncodeEvent(p.snapshot->recent_events[static_cast<std::size_t>(slot)], events->Add());
      // Sizes are recomputed whole: an event can lengthen its session's
      // length prefix as well. A status has tens of entries; this is cheap.
      if (class_status->ByteSizeLong() > budget_bytes && added_any) {
        events->RemoveLast();
        return;  // full: the rest go out with the next status, in order
      }
      ++*p.events_sent;
      added_any = added_in_round = true;
    }
  }
}

}  // namespace hapsim::service
