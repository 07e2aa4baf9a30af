// ViewerLink sizes its ack window by the network's round trip: frames still
// on the wire do not count against ack_window, so a viewer 100 ms away gets
// every 60 Hz snapshot, while a viewer that is slow (and says so in its
// acks' held time) still gets at most ack_window frames of backlog.
#include <gtest/gtest.h>

#include <cstdint>
#include <deque>
#include <memory>

#include "fuzz/grid_session.h"
#include "hapsim/streaming/viewer_link.h"

namespace hapsim::service {
namespace {

constexpr std::int64_t kFramePeriodNs = 16'666'667;  // the pump's 60 Hz

// gRPC's side: a write completes at once (the bytes are in the transport).
class InstantStream final : public ViewerLink::Stream {
 public:
  void StartFrameWrite(const hapsim::v1::Frame* frame) override { last_seq = frame->seq(); }
  void FinishStream(const grpc::Status&) override {}
  std::uint64_t last_seq = 0;
};

struct PendingAck {
  std::int64_t at_ns;
  std::uint64_t seq;
  std::uint64_t held_us;
};

// A viewer round_trip_ns away that works hold_ns on each frame before acking
// (and says so in its acks, or not, or lies): the frames it got in `seconds` of 60 Hz
// snapshots, and the most frames ever unacknowledged.
struct FarViewerRun {
  int frames = 0;
  std::uint64_t most_unacked = 0;
  double measured_round_trip_s = -1.0;
};

enum class Hold { kReported, kNotReported, kClaimsTheWholeTrip };

FarViewerRun RunViewer(std::int64_t round_trip_ns, std::int64_t hold_ns, Hold hold, double seconds) {
  fuzz::GridSession session;
  ViewerLink link("far", /*max_rate_hz=*/0.0, /*quantum_m=*/1e-5, /*ack_window=*/2);
  InstantStream stream;
  link.Attach(&stream);
  std::deque<PendingAck> acks;
  std::int64_t viewer_free_ns = 0;  // a slow viewer works on one frame at a time
  FarViewerRun run;
  std::uint64_t sent = 0, acked = 0;
  const auto total_ns = static_cast<std::int64_t>(seconds * 1e9);
  for (std::int64_t now_ns = kFramePeriodNs; now_ns <= total_ns; now_ns += kFramePeriodNs) {
    while (!acks.empty() && acks.front().at_ns <= now_ns) {
      link.OnAck(acks.front().seq, acks.front().held_us, acks.front().at_ns);
      acked = acks.front().seq + 1;
      acks.pop_front();
    }
    auto snapshot = session.Publish();
    session.history.Absorb(*snapshot);
    if (link.Offer(snapshot, session.history, now_ns) != ViewerLink::OfferResult::kSent) continue;
    link.OnWriteDone(true);
    ++sent;
    ++run.frames;
    run.most_unacked = std::max(run.most_unacked, sent - acked);
    // Half the trip there, the viewer's work (queued behind earlier frames), half the trip back.
    const std::int64_t arrives_ns = now_ns + round_trip_ns / 2;
    const std::int64_t starts_ns = std::max(arrives_ns, viewer_free_ns);
    viewer_free_ns = starts_ns + hold_ns;
    const std::int64_t held_ns = viewer_free_ns - arrives_ns;
    std::uint64_t held_us = 0;
    if (hold == Hold::kReported) held_us = static_cast<std::uint64_t>(held_ns / 1000);
    if (hold == Hold::kClaimsTheWholeTrip) held_us = static_cast<std::uint64_t>((held_ns + round_trip_ns) / 1000);
    acks.push_back({viewer_free_ns + round_trip_ns / 2, stream.last_seq, held_us});
  }
  run.measured_round_trip_s = link.link_round_trip_s();
  return run;
}

TEST(ViewerLinkRoundTrip, AViewerOneHundredMillisecondsAwayGetsEverySnapshot) {
  const FarViewerRun run = RunViewer(100'000'000, 0, Hold::kReported, 10.0);
  // 600 snapshots in 10 s; only the first round trip, before any ack, is held to ack_window.
  EXPECT_GE(run.frames, 590);
  EXPECT_NEAR(run.measured_round_trip_s, 0.100, 1e-6);
  // In flight: one round trip of frames (6) plus the window, never more.
  EXPECT_LE(run.most_unacked, 6u + 2u + 1u);
}

TEST(ViewerLinkRoundTrip, WithoutMeasuringTheTripAFarViewerWouldGetTwoFramesPerRoundTrip) {
  // The baseline the measurement removes: the same viewer, its acks claiming
  // it held each frame for the whole trip, so the link sees no network and
  // counts every unacknowledged frame against the window of 2.
  const FarViewerRun blind = RunViewer(100'000'000, 0, Hold::kClaimsTheWholeTrip, 10.0);
  const FarViewerRun measured = RunViewer(100'000'000, 0, Hold::kReported, 10.0);
  EXPECT_NEAR(blind.measured_round_trip_s, 0.0, 1e-9);
  // Two frames per trip: the acks land just before the sixth 60 Hz offer, so 2 in 6 offers of 600.
  EXPECT_NEAR(blind.frames, 200, 2);
  EXPECT_GE(measured.frames, 590);
}

TEST(ViewerLinkRoundTrip, ASlowViewerThatReportsItsWorkStillLagsAtMostTheWindow) {
  // Near (1 ms trip) but 100 ms per frame: the trip is measured as 1 ms, so
  // only ~2 frames wait at the viewer, as with a fixed window of 2.
  const FarViewerRun run = RunViewer(1'000'000, 100'000'000, Hold::kReported, 10.0);
  EXPECT_NEAR(run.measured_round_trip_s, 0.001, 1e-6);
  EXPECT_LE(run.most_unacked, 3u);
  EXPECT_NEAR(run.frames, 100, 5);  // the viewer's own 10 frames per second
}

TEST(ViewerLinkRoundTrip, NeverMoreThanTheCapInFlight) {
  // A 10 s round trip would allow 600 frames in flight: the cap holds it to 128.
  const FarViewerRun run = RunViewer(10'000'000'000, 0, Hold::kReported, 30.0);
  EXPECT_EQ(run.most_unacked, ViewerLink::kMaxFramesInFlight);
}

}  // namespace
}  // namespace hapsim::service
