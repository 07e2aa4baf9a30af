// The viewers of every session: which Subscribe streams watch which session,
// and each session's newest snapshot (what GetSnapshot answers and what the
// frame pump offers to the streams). Sessions know nothing of viewers: the
// frame pump feeds the hub their snapshots, and the registry tells it when a
// session closes so it can end that session's streams with a gRPC status.
//
// Threads: gRPC threads (Add, Remove, LatestSnapshot), the frame pump
// (Pump), the registry's control thread (OnSessionClosed). The hub's mutex
// is never held while a stream is written to or finished (a gRPC reaction
// may run inline and call back into the hub), and no tick ever takes it.
#pragma once
#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

#include "hapsim/runtime/scene_snapshot.h"
#include "hapsim/runtime/session_registry.h"
#include "hapsim/streaming/topology_history.h"
#include "hapsim/streaming/viewer_link.h"

namespace hapsim::service {

class ViewerHub final : public SessionListener {
 public:
  // A new stream of `session` (found in the registry's table). If the
  // session has already left the table, the next Pump ends the stream.
  void Add(const std::shared_ptr<Session>& session, std::shared_ptr<ViewerLink> link);
  // The stream ended (its reactor's OnDone).
  void Remove(const Session& session, const ViewerLink* link);
  // The newest snapshot the frame pump has taken of `session` (nullptr
  // before the first).
  std::shared_ptr<const SceneSnapshot> LatestSnapshot(const Session& session) const;

  // Frame pump, one pass: takes each session's new snapshot (and its
  // topology edits into the session's history), offers the newest to its
  // streams, and ends the streams of sessions no longer in `sessions`
  // (closed while a stream was joining).
  void Pump(const SessionTable& sessions, std::int64_t now_ns);

  // SessionListener: ends the session's streams (NOT_FOUND "closed", or
  // UNAVAILABLE when the server stops) and forgets it.
  void OnSessionClosed(Session& session, CloseReason why) override;

  // Any thread: whether any session has a stream (the frame pump polls
  // slower while none has).
  bool AnyViewers() const { return streams_.load(std::memory_order_relaxed) > 0; }

 private:
  using Links = std::vector<std::shared_ptr<ViewerLink>>;
  struct Entry {
    std::shared_ptr<Session> session;            // keeps the key's address from being reused
    std::shared_ptr<const SceneSnapshot> latest;
    std::shared_ptr<const Links> links = std::make_shared<const Links>();  // copy-on-write
    // The session's topology edits as taken from its snapshots; written and
    // read on the frame pump thread only.
    std::shared_ptr<TopologyHistory> history = std::make_shared<TopologyHistory>();
  };
  Entry& EntryLocked(const std::shared_ptr<Session>& session);
  // Pump's steps: one session's new snapshot to its streams, then the
  // streams of sessions no longer in the table ended.
  void PumpSession(const std::shared_ptr<Session>& session, std::int64_t now_ns);
  static void OfferToLinks(Session& session, const std::shared_ptr<const SceneSnapshot>& latest, const Links& links,
                           const TopologyHistory& history, std::int64_t now_ns);
  void EndStreamsOfClosedSessions(const SessionTable& sessions);
  // e's streams become `links`: its session's viewer count and streams_ follow.
  void SetLinksLocked(Entry& e, std::shared_ptr<const Links> links);

  mutable std::mutex mutex_;
  std::map<const Session*, Entry> entries_;
  std::atomic<std::size_t> streams_{0};  // streams over all entries (written under mutex_)
};

}  // namespace hapsim::service
