// What a class status carries of its sessions' events: within its byte
// budget, each event once and in order, no session crowding out another,
// and a stream that starts late begins with the newest few.
#include "hapsim/api/class_status_events.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace hapsim::service {
namespace {

constexpr int kTrainees = 16;
constexpr std::size_t kSnapshotHolds = 64;  // as a session's snapshot keeps them

// A session that has logged `total` events; event number n happened at
// sim time n ms (so an event names itself), at a realistic needle position.
SceneSnapshot SnapshotWithEvents(std::uint64_t total) {
  SceneSnapshot s;
  s.events_total = total;
  const std::uint64_t held = std::min<std::uint64_t>(total, kSnapshotHolds);
  for (std::uint64_t n = total - held; n < total; ++n) {
    core::SceneEvent e;
    e.t_s = 1e-3 * static_cast<double>(n);
    e.kind = n % 2 ? core::SceneEventKind::kPuncture : core::SceneEventKind::kContactBegin;
    e.layer = static_cast<int>(n % 3);
    e.where_W_m = {0.0123 + 1e-5 * static_cast<double>(n), -0.0071, -0.0042};
    s.recent_events.push_back(e);
  }
  return s;
}

// A status as the server fills it for an acupuncture trainee mid-trial,
// without events.
void DescribeTrainee(int i, hapsim::v1::SessionStatus* s) {
  char id[16];
  std::snprintf(id, sizeof id, "t%02d", i);
  s->set_session_id(id);
  s->set_trainee(std::string("trainee") + id);
  s->set_scene("acupuncture");
  s->set_sim_time_s(123.456 + i);
  s->set_tip_depth_m(0.0087);
  s->set_current_layer(1);
  s->set_layer_name("fat");
  s->set_force_n(1.234);
  s->set_contact_state("punctured");
  s->set_late_ticks(3);
  s->set_max_tick_lateness_s(0.00042);
  s->set_device_streaming(true);
  s->set_ticks(123456);
  s->set_peak_tool_force_n(2.5);
  s->set_viewers(1);
}

struct Class {
  std::vector<SceneSnapshot> snapshots;
  std::vector<std::uint64_t> cursors;
  std::vector<std::vector<double>> received_t_s;  // per session, in arrival order

  // One status: the bytes it took, and each session's events are recorded.
  std::size_t Status(std::size_t budget_bytes, hapsim::v1::ClassStatus* out = nullptr) {
    hapsim::v1::ClassStatus status;
    std::vector<PendingEvents> pending;
    for (std::size_t i = 0; i < snapshots.size(); ++i) {
      auto* s = status.add_sessions();
      DescribeTrainee(static_cast<int>(i), s);
      s->set_events_total(snapshots[i].events_total);
    }
    for (std::size_t i = 0; i < snapshots.size(); ++i) {
      pending.push_back({status.mutable_sessions(static_cast<int>(i)), &snapshots[i], &cursors[i]});
    }
    AddEventsWithinBudget(pending, budget_bytes, &status);
    received_t_s.resize(snapshots.size());
    for (int i = 0; i < status.sessions_size(); ++i) {
      for (const auto& e : status.sessions(i).events()) received_t_s[static_cast<std::size_t>(i)].push_back(e.t_s());
    }
    if (out) *out = status;
    return status.ByteSizeLong();
  }
};

Class ClassWithPendingEvents(const std::vector<std::uint64_t>& totals) {
  Class c;
  for (const std::uint64_t total : totals) {
    c.snapshots.push_back(SnapshotWithEvents(total));
    c.cursors.push_back(0);
  }
  return c;
}

TEST(ClassStatusEventsTest, SixteenTraineesStatusesStayWithinTwoKilobytesAndEveryEventGoesOutOnceInOrder) {
  // Every trainee has 20 events unsent: 320 in all, ~19 kB, a burst no single
  // status may carry.
  Class c = ClassWithPendingEvents(std::vector<std::uint64_t>(kTrainees, 20));
  const std::size_t budget = ClassStatusBudgetBytes(kTrainees);
  ASSERT_EQ(budget, 2000u);
  std::vector<std::size_t> bytes;
  auto all_sent = [&] {
    for (const auto cursor : c.cursors)
      if (cursor != 20) return false;
    return true;
  };
  while (bytes.size() < 200 && !all_sent()) bytes.push_back(c.Status(budget));
  ASSERT_TRUE(all_sent());
  for (const std::size_t b : bytes) EXPECT_LE(b, budget);
  // Every status but the last was full: not even one more event (~55 B)
  // would have fitted.
  for (std::size_t k = 0; k + 1 < bytes.size(); ++k) EXPECT_LT(budget - bytes[k], 64u) << "status " << k;
  for (int i = 0; i < kTrainees; ++i) {
    std::vector<double> expected;
    for (int n = 0; n < 20; ++n) expected.push_back(1e-3 * n);
    EXPECT_EQ(c.received_t_s[static_cast<std::size_t>(i)], expected) << "session " << i;
  }
  // And once everything went out, a status carries nothing more.
  hapsim::v1::ClassStatus quiet;
  c.Status(budget, &quiet);
  for (const auto& s : quiet.sessions()) EXPECT_EQ(s.events_size(), 0);
}

TEST(ClassStatusEventsTest, OneSessionsFloodDoesNotHoldBackAnotherSessionsEvent) {
  std::vector<std::uint64_t> totals(kTrainees, 0);
  totals[0] = 64;  // chattering contact: a snapshot's worth of events
  totals[9] = 1;   // one puncture
  Class c = ClassWithPendingEvents(totals);
  hapsim::v1::ClassStatus first;
  c.Status(ClassStatusBudgetBytes(kTrainees), &first);
  ASSERT_EQ(first.sessions(9).events_size(), 1);
  EXPECT_EQ(first.sessions(9).events(0).t_s(), 0.0);
  EXPECT_EQ(first.sessions(9).events(0).kind(), "contact_begin");
  EXPECT_GE(first.sessions(0).events_size(), 1);
}

TEST(ClassStatusEventsTest, EventsTheSnapshotNoLongerHoldsArePassedOver) {
  // 100 logged, the snapshot holds the newest 64 (36..99); the stream had sent 10.
  Class c = ClassWithPendingEvents({100});
  c.cursors[0] = 10;
  for (int i = 0; i < 100 && c.cursors[0] < 100; ++i) c.Status(1u << 20);
  ASSERT_EQ(c.received_t_s[0].size(), 64u);
  EXPECT_DOUBLE_EQ(c.received_t_s[0].front(), 0.036);
  EXPECT_DOUBLE_EQ(c.received_t_s[0].back(), 0.099);
}

TEST(ClassStatusEventsTest, AStatusAlreadyOverItsBudgetStillCarriesOneEventEach) {
  Class c = ClassWithPendingEvents({3, 3});
  hapsim::v1::ClassStatus status;
  c.Status(10, &status);  // the statuses alone are ~200 B
  EXPECT_EQ(status.sessions(0).events_size() + status.sessions(1).events_size(), 1);
  for (int i = 0; i < 5; ++i) c.Status(10);
  EXPECT_EQ(c.cursors[0] + c.cursors[1], 6u) << "one event per status drains both";
}

TEST(ClassStatusEventsTest, AStreamStartsWithTheNewestFewEventsOfASession) {
  EXPECT_EQ(FirstEventToSend(0), 0u);
  EXPECT_EQ(FirstEventToSend(kClassStatusBacklogEvents), 0u);
  EXPECT_EQ(FirstEventToSend(57), 57u - kClassStatusBacklogEvents);
  Class c = ClassWithPendingEvents({57});
  c.cursors[0] = FirstEventToSend(57);
  c.Status(1u << 20);
  ASSERT_EQ(c.received_t_s[0].size(), kClassStatusBacklogEvents);
  EXPECT_DOUBLE_EQ(c.received_t_s[0].back(), 0.056);
}

}  // namespace
}  // namespace hapsim::service
