// Which events a class status carries. A status is meant to stay small
// (a browser or a laptop on a lab's Wi-Fi reads one every 100 ms) however
// many events a class logs at once, and no session's events may crowd out
// another's. So a status takes each session's unsent events oldest first,
// one session at a time in turn, while the whole status stays within a byte
// budget; what does not fit goes out in the next status, in order. A stream
// that meets a session for the first time starts with its newest few events
// only: the tile counts the rest from events_total, and the full record is
// in the trials.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "hapsim/runtime/scene_snapshot.h"
#include "hapsim/v1/session.pb.h"

namespace hapsim::service {

// The events a stream's first status gives of a session it has not seen.
inline constexpr std::uint64_t kClassStatusBacklogEvents = 4;
// What a status may grow to with its events (bytes, serialized): 2 kB for a
// class of up to 16 trainees, 125 B per session beyond. A session's status
// takes ~100 B without events; an event ~55 B.
inline constexpr std::size_t kClassStatusBudgetBytes = 2000;
inline constexpr std::size_t kClassStatusBytesPerSession = 125;
inline std::size_t ClassStatusBudgetBytes(std::size_t sessions) {
  return std::max(kClassStatusBudgetBytes, kClassStatusBytesPerSession * sessions);
}

// The events_sent a stream starts from for a session that has logged
// `events_total` events so far.
inline std::uint64_t FirstEventToSend(std::uint64_t events_total) {
  return events_total > kClassStatusBacklogEvents ? events_total - kClassStatusBacklogEvents : 0;
}

struct PendingEvents {
  hapsim::v1::SessionStatus* status;  // the session's entry in the class status
  const SceneSnapshot* snapshot;      // its newest snapshot: recent_events and events_total
  std::uint64_t* events_sent;         // the stream's cursor: events before it were sent (or lost)
};

// Adds the sessions' unsent events to their statuses (all inside *class_status)
// within budget_bytes, advancing each cursor past what it added. Events the
// snapshot no longer holds are skipped (lost: the session logged more than
// its snapshot keeps since this stream's last status). At least one event is
// added per call when any is pending, so a status over budget without events
// still drains them.
void AddEventsWithinBudget(const std::vector<PendingEvents>& sessions, std::size_t budget_bytes,
                           hapsim::v1::ClassStatus* class_status);

}  // namespace hapsim::service
