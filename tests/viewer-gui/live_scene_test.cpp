// LiveScene: what the render thread gets from the frame stream.
#include <gtest/gtest.h>

#include "hapsim/gui/live_scene.h"
#include "render_test_util.h"

namespace hapsim::gui {
namespace {

using testing::GridKeyframe;

TEST(LiveScene, AKeyframeGivesPositionsTrianglesAndTheBox) {
  viewer::MeshCache cache;
  LiveScene live;
  const auto key = GridKeyframe(3, 0.01, "skin");
  ASSERT_EQ(cache.Apply(key), viewer::ApplyResult::kApplied);
  live.OnFrame(key, cache);
  SceneView view;
  ASSERT_TRUE(live.CopyIfNewer(&view));
  ASSERT_TRUE(view.triangles);
  EXPECT_EQ(view.triangles->parts.size(), 8u);
  EXPECT_EQ(view.positions_m.size(), 27u);
  EXPECT_NEAR(view.lo_m.x(), -0.01, 1e-9);
  EXPECT_NEAR(view.hi_m.y(), 0.01, 1e-9);
  EXPECT_FALSE(live.CopyIfNewer(&view)) << "nothing new";
}

TEST(LiveScene, ADeltaMovesVerticesAndKeepsTheSameTriangleList) {
  viewer::MeshCache cache;
  LiveScene live;
  const auto key = GridKeyframe(3, 0.01, "skin");
  ASSERT_EQ(cache.Apply(key), viewer::ApplyResult::kApplied);
  live.OnFrame(key, cache);
  SceneView view;
  live.CopyIfNewer(&view);
  const auto triangles = view.triangles;
  hapsim::v1::Frame delta;
  delta.set_seq(1);
  delta.mutable_delta()->add_index_gaps(4);  // the centre vertex
  for (const int dq : {0, 0, -150}) delta.mutable_delta()->add_position_dq(dq);  // 1.5 mm down
  ASSERT_EQ(cache.Apply(delta), viewer::ApplyResult::kApplied);
  live.OnFrame(delta, cache);
  ASSERT_TRUE(live.CopyIfNewer(&view));
  EXPECT_EQ(view.triangles, triangles) << "no topology edit: the same list is shared";
  EXPECT_NEAR(view.positions_m[3 * 4 + 2], -1.5e-3, 1e-7);
  EXPECT_NEAR(view.lo_m.z(), -1.5e-3, 1e-9);
}

// A paused session keeps streaming frames that change nothing: they are
// counted, but give the window nothing new to draw; the first frame that
// moves the tool does.
TEST(LiveScene, AFrameThatChangesNothingIsCountedButNotNew) {
  viewer::MeshCache cache;
  LiveScene live;
  auto key = GridKeyframe(3, 0.01, "skin");
  key.set_sim_time_s(2.0);
  key.set_paused(true);
  for (const double v : {0.001, 0.0, 0.003}) key.mutable_tool()->add_tip_m(v);
  ASSERT_EQ(cache.Apply(key), viewer::ApplyResult::kApplied);
  live.OnFrame(key, cache);
  SceneView view;
  ASSERT_TRUE(live.CopyIfNewer(&view));
  hapsim::v1::Frame same;
  same.set_seq(1);
  same.set_sim_time_s(2.0);
  same.set_paused(true);
  same.mutable_delta();
  *same.mutable_tool() = key.tool();
  for (std::uint64_t seq = 1; seq <= 5; ++seq) {
    same.set_seq(seq);
    ASSERT_EQ(cache.Apply(same), viewer::ApplyResult::kApplied);
    live.OnFrame(same, cache);
    EXPECT_FALSE(live.CopyIfNewer(&view)) << "frame " << seq << " changes nothing drawn";
  }
  EXPECT_EQ(live.FramesReceived(), 6u);
  EXPECT_EQ(live.LastSeq(), 5u);
  auto moved = same;
  moved.set_seq(6);
  moved.mutable_tool()->set_tip_m(2, 0.002);  // the stylus moves while the session is paused
  ASSERT_EQ(cache.Apply(moved), viewer::ApplyResult::kApplied);
  live.OnFrame(moved, cache);
  ASSERT_TRUE(live.CopyIfNewer(&view));
  EXPECT_NEAR(view.tool.tip_m.z(), 0.002, 1e-12);
}

// The device stops: frames carry no tool pose any more, and the force they
// carry (the scene's, 0) replaces the last one felt — the panel and the plot
// must not keep showing 0.5 N.
TEST(LiveScene, WhenTheDeviceStopsTheToolGoesAndItsLastForceWithIt) {
  viewer::MeshCache cache;
  LiveScene live;
  auto key = GridKeyframe(3, 0.01, "skin");
  key.set_sim_time_s(1.0);
  for (const double v : {0.0, 0.0, -0.001}) key.mutable_tool()->add_tip_m(v);
  for (const double v : {0.0, 0.0, 0.5}) key.mutable_tool()->add_force_n(v);
  ASSERT_EQ(cache.Apply(key), viewer::ApplyResult::kApplied);
  live.OnFrame(key, cache);
  hapsim::v1::Frame gone;
  gone.set_seq(1);
  gone.set_sim_time_s(1.1);
  gone.mutable_delta();
  for (const double v : {0.0, 0.0, 0.0}) gone.mutable_tool()->add_force_n(v);
  ASSERT_EQ(cache.Apply(gone), viewer::ApplyResult::kApplied);
  live.OnFrame(gone, cache);
  SceneView view;
  ASSERT_TRUE(live.CopyIfNewer(&view));
  EXPECT_FALSE(view.tool.valid);
  EXPECT_EQ(view.tool.force_N.norm(), 0.0);
  ASSERT_EQ(view.history.size(), 2u);
  EXPECT_EQ(view.history.back().force_N, 0.0);
}

TEST(LiveScene, ToolEventsAndHistoryFollowTheFrames) {
  viewer::MeshCache cache;
  LiveScene live;
  auto key = GridKeyframe(3, 0.01, "skin");
  key.set_sim_time_s(1.0);
  auto* tool = key.mutable_tool();
  for (const double v : {0.001, 0.0, -0.002}) tool->add_tip_m(v);
  for (const double v : {1.0, 0.0, 0.0, 0.0}) tool->add_orientation_wxyz(v);
  for (const double v : {0.0, 0.3, 0.4}) tool->add_force_n(v);
  tool->set_contact_state("punctured");
  key.set_tip_depth_m(0.002);
  key.set_current_layer(0);
  auto* e = key.add_events();
  e->set_kind("puncture");
  e->set_layer(0);
  for (const double v : {0.001, 0.0, -0.0026}) e->add_where_m(v);
  ASSERT_EQ(cache.Apply(key), viewer::ApplyResult::kApplied);
  live.OnFrame(key, cache);
  SceneView view;
  live.CopyIfNewer(&view);
  ASSERT_TRUE(view.tool.valid);
  EXPECT_NEAR(view.tool.force_N.norm(), 0.5, 1e-12);
  EXPECT_EQ(view.LayerName(view.current_layer), "skin");
  ASSERT_EQ(view.events.size(), 1u);
  EXPECT_EQ(view.events[0].layer, "skin");
  EXPECT_NEAR(view.events[0].where_m.z(), -0.0026, 1e-12);
  ASSERT_EQ(view.history.size(), 1u);
  EXPECT_NEAR(view.history[0].depth_m, 0.002, 1e-12);

  hapsim::v1::Frame reset;
  reset.set_seq(1);
  reset.set_sim_time_s(1.5);
  reset.mutable_delta();
  reset.add_events()->set_kind("reset");
  ASSERT_EQ(cache.Apply(reset), viewer::ApplyResult::kApplied);
  live.OnFrame(reset, cache);
  live.CopyIfNewer(&view);
  EXPECT_EQ(view.history.size(), 1u) << "a reset starts the force-depth curve again";
  EXPECT_FALSE(view.tool.valid) << "a frame without a tool pose";
}

TEST(LiveScene, EventsAreCappedOldestFirst) {
  viewer::MeshCache cache;
  LiveScene live;
  auto key = GridKeyframe(2, 0.01, "skin");
  for (std::size_t i = 0; i < LiveScene::kMaxEvents + 10; ++i) {
    auto* e = key.add_events();
    e->set_kind("contact_begin");
    e->set_t_s(static_cast<double>(i));
  }
  ASSERT_EQ(cache.Apply(key), viewer::ApplyResult::kApplied);
  live.OnFrame(key, cache);
  SceneView view;
  live.CopyIfNewer(&view);
  ASSERT_EQ(view.events.size(), LiveScene::kMaxEvents);
  EXPECT_EQ(view.events.front().t_s, 10.0);
}

TEST(LiveScene, AConnectionChangeIsCopiedWithoutANewFrame) {
  LiveScene live;
  SceneView view;
  live.SetConnection("lost: UNAVAILABLE — retrying");
  ASSERT_TRUE(live.CopyIfNewer(&view));
  EXPECT_EQ(view.connection, "lost: UNAVAILABLE — retrying");
}

}  // namespace
}  // namespace hapsim::gui
