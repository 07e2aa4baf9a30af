// The instructor's class view (WatchClass): one compact status per session
// of a class, built from each session's counters and the newest snapshot the
// frame pump took (so reading it never touches a tick). One builder per
// stream: it remembers which events the stream has already sent.
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "hapsim/api/class_status_events.h"
#include "hapsim/classroom/score_book.h"
#include "hapsim/runtime/session_registry.h"
#include "hapsim/streaming/viewer_hub.h"
#include "hapsim/v1/session.pb.h"

namespace hapsim::service {

class ClassStatusBuilder {
 public:
  ClassStatusBuilder(const SessionRegistry* registry, const ViewerHub* hub, const ScoreBook* scores)
      : registry_(registry), hub_(hub), scores_(scores) {}

  // `session_ids`: the class's sessions (nullptr: every session of the
  // server). Sessions of the class that do not run now are listed in
  // missing_sessions. Events are those since this builder's previous Fill,
  // as many as the status's byte budget takes (class_status_events.h).
  void Fill(const std::vector<std::string>* session_ids, hapsim::v1::ClassStatus* out);

 private:
  // Everything but the events; the session's unsent events go to *pending.
  void Describe(const std::shared_ptr<Session>& session, hapsim::v1::SessionStatus* out,
                std::vector<PendingEvents>* pending);

  const SessionRegistry* registry_;
  const ViewerHub* hub_;
  const ScoreBook* scores_;
  std::uint64_t seq_ = 0;
  struct Cursor {
    std::shared_ptr<Session> session;  // a session re-created under the same id starts afresh
    std::uint64_t events_sent = 0;
  };
  std::map<std::string, Cursor> cursors_;
  std::vector<std::shared_ptr<const SceneSnapshot>> held_snapshots_;  // during a Fill
};

}  // namespace hapsim::service
