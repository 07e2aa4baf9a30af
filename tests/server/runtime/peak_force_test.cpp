// The peak |tool force| a frame carries: over every tick since its stream's
// previous frame, however many snapshots the stream skipped.
#include <gtest/gtest.h>

#include "hapsim/runtime/scene_snapshot.h"

namespace hapsim::service {
namespace {

// Snapshot `id` after intervals whose peak is peak_of(k) for snapshot k.
template <class PeakOf>
SceneSnapshot SnapshotAfter(std::uint64_t id, PeakOf peak_of) {
  SceneSnapshot s;
  s.id = id;
  for (std::uint64_t k = 1; k <= id; ++k) s.interval_peak_N[k % SceneSnapshot::kPeakIntervals] = peak_of(k);
  return s;
}

TEST(PeakForceSince, AFrameAfterTheLastCoversExactlyTheIntervalsBetween) {
  const auto s = SnapshotAfter(100, [](std::uint64_t k) { return k == 98 ? 1.0 : 0.1 * static_cast<double>(k % 3); });
  EXPECT_DOUBLE_EQ(PeakForceSince(s, 99), 0.1);  // interval 100 only (100 % 3 = 1)
  EXPECT_DOUBLE_EQ(PeakForceSince(s, 97), 1.0);  // a viewer that skipped 98 still sees its peak
  EXPECT_DOUBLE_EQ(PeakForceSince(s, 0), 0.1);   // a new stream: this interval
}

TEST(PeakForceSince, AStreamBehindByMoreThanTheKeptIntervalsGetsAllKept) {
  const std::uint64_t n = SceneSnapshot::kPeakIntervals;
  const auto s = SnapshotAfter(200, [](std::uint64_t k) { return static_cast<double>(k); });
  EXPECT_DOUBLE_EQ(PeakForceSince(s, 10), 200.0);
  const auto early = SnapshotAfter(200, [&](std::uint64_t k) { return k == 200 - n + 1 ? 9.0 : 1.0; });
  EXPECT_DOUBLE_EQ(PeakForceSince(early, 10), 9.0) << "the oldest kept interval counts";
  const auto dropped = SnapshotAfter(200, [&](std::uint64_t k) { return k == 200 - n ? 9.0 : 1.0; });
  EXPECT_DOUBLE_EQ(PeakForceSince(dropped, 10), 1.0) << "overwritten: older than the ring";
}

}  // namespace
}  // namespace hapsim::service
