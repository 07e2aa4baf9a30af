// ViewerLink without an ack window (docs/reliability.md row 31): the HTTP/2
// flow control is the only backpressure then, so the link itself must never
// start a second write before gRPC reports the first done; what arrives in
// between is held (the newest snapshot wins) and sent after the write ends.
#include "hapsim/streaming/viewer_link.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>

#include "fuzz/grid_session.h"

namespace hapsim::service {
namespace {

// What gRPC's reactor would do with the link's calls: counts the writes it
// was asked to start and fails on a second one while one is in flight.
class OneWriteStream final : public ViewerLink::Stream {
 public:
  void StartFrameWrite(const hapsim::v1::Frame* frame) override {
    EXPECT_FALSE(in_flight) << "a second write started while one was in flight";
    in_flight = true;
    ++writes;
    last_seq = frame->seq();
  }
  void FinishStream(const grpc::Status&) override { finished = true; }
  bool in_flight = false, finished = false;
  int writes = 0;
  std::uint64_t last_seq = 0;
};

TEST(ViewerLinkWithoutAckWindow, HoldsEverySnapshotWhileAWriteIsInFlightAndSendsTheNewestAfter) {
  fuzz::GridSession session;
  ViewerLink link("v", /*max_rate_hz=*/0.0, /*quantum_m=*/1e-5, /*ack_window=*/0);
  OneWriteStream stream;
  link.Attach(&stream);
  std::int64_t now_ns = 0;
  const auto offer_next = [&] {
    auto snapshot = session.Publish();
    EXPECT_NE(snapshot, nullptr);
    session.history.Absorb(*snapshot);
    now_ns += 1'000'000;  // one tick of 1 ms
    return std::make_pair(link.Offer(snapshot, session.history, now_ns), snapshot);
  };
  EXPECT_EQ(offer_next().first, ViewerLink::OfferResult::kSent);  // the keyframe
  // 50 ticks while the keyframe is still being written (a slow client).
  EXPECT_EQ(offer_next().first, ViewerLink::OfferResult::kBusy);
  std::shared_ptr<const SceneSnapshot> newest;
  for (int k = 0; k < 49; ++k) {
    auto [result, snapshot] = offer_next();
    EXPECT_EQ(result, ViewerLink::OfferResult::kCoalesced);
    newest = snapshot;
  }
  EXPECT_EQ(stream.writes, 1);
  EXPECT_EQ(link.snapshots_coalesced(), 49u);
  // gRPC reports the write done: the next offer of the newest snapshot goes out.
  stream.in_flight = false;
  link.OnWriteDone(true);
  EXPECT_EQ(link.Offer(newest, session.history, now_ns + 1'000'000), ViewerLink::OfferResult::kSent);
  EXPECT_EQ(stream.writes, 2);
  EXPECT_EQ(stream.last_seq, 1u);
  EXPECT_EQ(link.frames_sent(), 2u);
  // A failed write ends the stream instead of retrying.
  stream.in_flight = false;
  link.OnWriteDone(false);
  EXPECT_TRUE(stream.finished);
  EXPECT_EQ(offer_next().first, ViewerLink::OfferResult::kNotNeeded);
  EXPECT_EQ(stream.writes, 2);
  link.Detach();
}

}  // namespace
}  // namespace hapsim::service
