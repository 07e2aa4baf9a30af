#include "hapsim/streaming/viewer_hub.h"

#include <algorithm>
#include <utility>

namespace hapsim::service {

namespace {

grpc::Status ClosedStatus(const Session& s, CloseReason why) {
  if (why == CloseReason::kServerStopping) return {grpc::StatusCode::UNAVAILABLE, "server shutting down"};
  return {grpc::StatusCode::NOT_FOUND, "session '" + s.id() + "' was closed"};
}

void EndAll(const std::shared_ptr<const std::vector<std::shared_ptr<ViewerLink>>>& links, const grpc::Status& why) {
  if (!links) return;
  for (const auto& link : *links) link->Close(why);
}

}  // namespace

ViewerHub::Entry& ViewerHub::EntryLocked(const std::shared_ptr<Session>& session) {
  Entry& e = entries_[session.get()];
  if (!e.session) e.session = session;
  return e;
}

void ViewerHub::SetLinksLocked(Entry& e, std::shared_ptr<const Links> links) {
  streams_.store(streams_.load(std::memory_order_relaxed) - e.links->size() + links->size(), std::memory_order_relaxed);
  e.links = std::move(links);
  e.session->counters().viewers.connected.store(static_cast<std::uint32_t>(e.links->size()));
}

void ViewerHub::Add(const std::shared_ptr<Session>& session, std::shared_ptr<ViewerLink> link) {
  std::lock_guard lock(mutex_);
  Entry& e = EntryLocked(session);
  auto links = std::make_shared<Links>(*e.links);
  links->push_back(std::move(link));
  SetLinksLocked(e, std::move(links));
}

void ViewerHub::Remove(const Session& session, const ViewerLink* link) {
  std::lock_guard lock(mutex_);
  const auto it = entries_.find(&session);
  if (it == entries_.end()) return;
  auto links = std::make_shared<Links>(*it->second.links);
  std::erase_if(*links, [link](const auto& l) { return l.get() == link; });
  SetLinksLocked(it->second, std::move(links));
}

std::shared_ptr<const SceneSnapshot> ViewerHub::LatestSnapshot(const Session& session) const {
  std::lock_guard lock(mutex_);
  const auto it = entries_.find(&session);
  return it == entries_.end() ? nullptr : it->second.latest;
}

void ViewerHub::Pump(const SessionTable& sessions, std::int64_t now_ns) {
  for (const auto& [id, session] : sessions) PumpSession(session, now_ns);
  EndStreamsOfClosedSessions(sessions);
}

void ViewerHub::PumpSession(const std::shared_ptr<Session>& session, std::int64_t now_ns) {
  std::shared_ptr<const SceneSnapshot> fresh;
  const bool is_new = session->TakeSnapshot(&fresh);
  // Nothing new and nobody watching: nothing to keep or to offer. (The pump
  // passes every few milliseconds over every session; most have no viewer.)
  if (!is_new && session->counters().viewers.connected.load(std::memory_order_relaxed) == 0) return;
  std::shared_ptr<const SceneSnapshot> latest;
  std::shared_ptr<const Links> links;
  std::shared_ptr<TopologyHistory> history;
  {
    std::lock_guard lock(mutex_);
    Entry& e = EntryLocked(session);
    if (is_new) e.latest = std::move(fresh);
    latest = e.latest;
    links = e.links;
    history = e.history;
  }
  // Without its mesh (nobody watched when it was taken) a snapshot still
  // serves the class's tiles; streams wait for the next one, which has it
  // now that they are connected. Its edits stay in the scene's log for that one.
  if (!latest || !latest->has_mesh) return;
  if (is_new) {
    history->Absorb(*latest);
    session->MarkTopologyTaken(history->End());
  }
  OfferToLinks(*session, latest, *links, *history, now_ns);  // outside the lock: may run a reaction inline
}

void ViewerHub::OfferToLinks(Session& session, const std::shared_ptr<const SceneSnapshot>& latest, const Links& links,
                             const TopologyHistory& history, std::int64_t now_ns) {
  for (const auto& link : links) {
    const ViewerLink::OfferResult result = link->Offer(latest, history, now_ns);
    SessionCounters& c = session.counters();
    if (result == ViewerLink::OfferResult::kCoalesced)
      c.viewers.frames_coalesced.fetch_add(1, std::memory_order_relaxed);
    if (result == ViewerLink::OfferResult::kSent) {
      c.viewers.frames_sent.fetch_add(1, std::memory_order_relaxed);
      c.viewers.bytes_sent.fetch_add(link->last_frame_bytes(), std::memory_order_relaxed);
    }
  }
}

// Sessions closed since their stream joined (Add after the close): end
// those streams now and forget the session.
void ViewerHub::EndStreamsOfClosedSessions(const SessionTable& sessions) {
  std::vector<Entry> gone;
  {
    std::lock_guard lock(mutex_);
    for (auto it = entries_.begin(); it != entries_.end();) {
      const auto found = sessions.find(it->second.session->id());
      if (found != sessions.end() && found->second == it->second.session) {
        ++it;
      } else {
        streams_.fetch_sub(it->second.links->size(), std::memory_order_relaxed);
        gone.push_back(std::move(it->second));
        it = entries_.erase(it);
      }
    }
  }
  for (const Entry& e : gone) EndAll(e.links, ClosedStatus(*e.session, CloseReason::kClosed));
}

void ViewerHub::OnSessionClosed(Session& session, CloseReason why) {
  Entry gone;
  {
    std::lock_guard lock(mutex_);
    const auto it = entries_.find(&session);
    if (it == entries_.end()) return;
    streams_.fetch_sub(it->second.links->size(), std::memory_order_relaxed);
    gone = std::move(it->second);
    entries_.erase(it);
  }
  EndAll(gone.links, ClosedStatus(session, why));
  session.counters().viewers.connected.store(0);
}

}  // namespace hapsim::service
