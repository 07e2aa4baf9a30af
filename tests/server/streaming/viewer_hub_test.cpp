// ViewerHub's bookkeeping of streams (what the frame pump's poll period and
// each session's viewer count follow) and its snapshots of unwatched
// sessions (kept, though no stream is offered them).
#include "hapsim/streaming/viewer_hub.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "hapsim/runtime/session.h"

namespace hapsim::service {
namespace {

class DiscardingPort final : public SessionPort {
 public:
  bool WriteForceModel(const ForceModelMessage&) override { return true; }
};

std::shared_ptr<Session> MakeHubTestSession(const std::string& id) {
  SessionConfig config;
  config.id = id;
  config.scene = "tissue_block";
  return std::make_shared<Session>(config, core::MakeScene({config.scene, {}}), std::make_shared<DiscardingPort>());
}

// Ticks the session through one frame's worth of ticks and more (the
// frame rate is at most the tick rate, and 60 Hz at 1 kHz ticks by default):
// at least one new snapshot.
void TickOneFrame(Session& session, std::int64_t& now_ns) {
  for (int k = 0; k < 20; ++k) {
    now_ns += 1'000'000;
    session.RunTick(now_ns, now_ns);
  }
}

std::shared_ptr<ViewerLink> MakeLink(const std::string& name) {
  return std::make_shared<ViewerLink>(name, /*max_rate_hz=*/0.0, /*quantum_m=*/1e-5, /*ack_window=*/0);
}

TEST(ViewerHubStreams, AnyViewersFollowsStreamsJoiningLeavingAndTheirSessionsClosing) {
  ViewerHub hub;
  auto a = MakeHubTestSession("a");
  auto b = MakeHubTestSession("b");
  EXPECT_FALSE(hub.AnyViewers());
  auto a1 = MakeLink("a1"), a2 = MakeLink("a2"), b1 = MakeLink("b1");
  hub.Add(a, a1);
  EXPECT_TRUE(hub.AnyViewers());
  hub.Add(a, a2);
  hub.Add(b, b1);
  EXPECT_EQ(a->counters().viewers.connected.load(), 2u);
  EXPECT_EQ(b->counters().viewers.connected.load(), 1u);
  hub.Remove(*a, a1.get());
  hub.Remove(*a, a2.get());
  EXPECT_EQ(a->counters().viewers.connected.load(), 0u);
  EXPECT_TRUE(hub.AnyViewers()) << "b still has its stream";
  hub.Remove(*a, a2.get());  // removing twice changes nothing
  EXPECT_TRUE(hub.AnyViewers());
  hub.OnSessionClosed(*b, CloseReason::kClosed);
  EXPECT_FALSE(hub.AnyViewers());
  EXPECT_EQ(b->counters().viewers.connected.load(), 0u);
}

TEST(ViewerHubStreams, AStreamOfASessionGoneFromTheTableEndsAtTheNextPassAndCountsNoMore) {
  ViewerHub hub;
  auto gone = MakeHubTestSession("gone");
  hub.Add(gone, MakeLink("late"));  // joined after its session left the table
  EXPECT_TRUE(hub.AnyViewers());
  const SessionTable empty;
  hub.Pump(empty, 0);
  EXPECT_FALSE(hub.AnyViewers());
}

TEST(ViewerHubSnapshots, AnUnwatchedSessionsNewSnapshotIsKeptAndAPassWithNothingNewKeepsIt) {
  ViewerHub hub;
  auto s = MakeHubTestSession("unwatched");
  SessionTable table;
  table.emplace(s->id(), s);
  EXPECT_EQ(hub.LatestSnapshot(*s), nullptr);
  std::int64_t now_ns = 0;
  TickOneFrame(*s, now_ns);
  hub.Pump(table, now_ns);
  const auto first = hub.LatestSnapshot(*s);
  ASSERT_NE(first, nullptr);
  hub.Pump(table, now_ns);  // nothing new, nobody watching
  EXPECT_EQ(hub.LatestSnapshot(*s), first);
  TickOneFrame(*s, now_ns);
  hub.Pump(table, now_ns);
  const auto second = hub.LatestSnapshot(*s);
  ASSERT_NE(second, nullptr);
  EXPECT_NE(second, first);
  EXPECT_GT(second->sim_time_s, first->sim_time_s);
}

}  // namespace
}  // namespace hapsim::service
