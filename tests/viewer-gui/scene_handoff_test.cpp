// Handing the scene to the render thread shares what is large instead of
// copying it: a frame's positions are one buffer every copy reads, and the
// force history's full chunks are shared. Sharing must never let a later
// frame change what a copy already holds.
#include <gtest/gtest.h>

#include "hapsim/gui/force_history.h"
#include "hapsim/gui/live_scene.h"
#include "render_test_util.h"

namespace hapsim::gui {
namespace {

using testing::GridKeyframe;

hapsim::v1::Frame MoveCentre(std::uint64_t seq, int dq) {
  hapsim::v1::Frame delta;
  delta.set_seq(seq);
  delta.set_sim_time_s(0.01 * static_cast<double>(seq));
  delta.mutable_delta()->add_index_gaps(4);  // the centre vertex of a 3 x 3 grid
  for (const int v : {0, 0, dq}) delta.mutable_delta()->add_position_dq(v);
  return delta;
}

TEST(SceneHandoff, CopiesOfOneFrameShareItsPositionsAndKeepThemAsLaterFramesCome) {
  viewer::MeshCache cache;
  LiveScene live;
  const auto key = GridKeyframe(3, 0.01, "skin");
  ASSERT_EQ(cache.Apply(key), viewer::ApplyResult::kApplied);
  live.OnFrame(key, cache);
  SceneView a, b;
  ASSERT_TRUE(live.CopyIfNewer(&a));
  ASSERT_TRUE(live.CopyIfNewer(&b));
  EXPECT_EQ(a.positions_m.data(), b.positions_m.data()) << "one buffer, not a copy per view";
  for (std::uint64_t seq = 1; seq <= 5; ++seq) {
    const auto delta = MoveCentre(seq, -100);
    ASSERT_EQ(cache.Apply(delta), viewer::ApplyResult::kApplied);
    live.OnFrame(delta, cache);
  }
  EXPECT_EQ(a.positions_m[3 * 4 + 2], 0.0f) << "a copy keeps the frame it took";
  ASSERT_TRUE(live.CopyIfNewer(&b));
  EXPECT_NEAR(b.positions_m[3 * 4 + 2], -5e-3, 1e-7);
  EXPECT_NE(a.positions_m.data(), b.positions_m.data());
}

TEST(ForceHistory, ACopyHasEverySampleAndStaysAsTheSourceGrows) {
  ForceHistory source;
  for (int i = 0; i < 1234; ++i) source.push_back({0.001 * i, 1.0 * i, 0.0});
  const ForceHistory copy = source;
  ASSERT_EQ(copy.size(), 1234u);
  for (std::size_t i = 0; i < copy.size(); ++i) ASSERT_EQ(copy[i].force_N, source[i].force_N);
  EXPECT_EQ(&copy[0], &source[0]) << "a full chunk is shared";
  EXPECT_NE(&copy.back(), &source.back()) << "the chunk still filling is the copy's own";
  for (int i = 1234; i < 2000; ++i) source.push_back({0.001 * i, 1.0 * i, 0.0});
  EXPECT_EQ(copy.size(), 1234u);
  EXPECT_EQ(copy.back().force_N, 1233.0);
}

TEST(ForceHistory, DroppingTheOldestKeepsTheNewestInOrder) {
  ForceHistory h;
  for (int i = 0; i < 3000; ++i) h.push_back({1.0 * i, 0.0, 0.0});
  h.DropOldest(750);
  ASSERT_EQ(h.size(), 2250u);
  for (std::size_t i = 0; i < h.size(); ++i) ASSERT_EQ(h[i].t_s, 750.0 + static_cast<double>(i));
  h.push_back({3000.0, 0.0, 0.0});
  EXPECT_EQ(h.back().t_s, 3000.0);
  h.DropOldest(h.size());
  EXPECT_TRUE(h.empty());
}

}  // namespace
}  // namespace hapsim::gui
