// The viewer's one decoder: a wire frame read once into a ViewerFrame, its
// events as kinds, and the tally of what happened to the tissue.
#include "hapsim/viewer/frame_decoder.h"

#include <gtest/gtest.h>

#include "hapsim/viewer/event_tally.h"

namespace hapsim::viewer {
namespace {

// One triangle of the part "skin" on layers "skin", "fat"; quantum 10 µm.
hapsim::v1::Frame TriangleKeyframe() {
  hapsim::v1::Frame frame;
  auto* key = frame.mutable_keyframe();
  key->set_quantum_m(1e-5);
  for (const int q : {0, 0, 0, 100, 0, 0, 0, 100, 0}) key->add_positions_q(q);
  for (const std::uint32_t v : {0u, 1u, 2u}) key->add_triangles(v);
  key->add_triangle_parts(0);
  key->add_part_names("skin");
  key->add_layer_names("skin");
  key->add_layer_names("fat");
  key->set_vertex_capacity(3);
  key->set_triangle_capacity(1);
  return frame;
}

hapsim::v1::SceneEvent* AddEvent(hapsim::v1::Frame* frame, const char* kind, int layer, double z_m, double value) {
  auto* e = frame->add_events();
  e->set_kind(kind);
  e->set_layer(layer);
  for (const double v : {0.0, 0.0, z_m}) e->add_where_m(v);
  e->set_value(value);
  return e;
}

TEST(EventKind, EveryKindRoundTripsThroughItsWireName) {
  for (std::size_t k = 0; k + 1 < kEventKindCount; ++k) {
    const auto kind = static_cast<EventKind>(k);
    EXPECT_EQ(ParseEventKind(ToString(kind)), kind) << ToString(kind);
  }
  EXPECT_EQ(ParseEventKind("cut_sideways"), EventKind::kUnknown);
  EXPECT_EQ(ParseEventKind(""), EventKind::kUnknown);
  EXPECT_TRUE(MarksTissue(EventKind::kPuncture));
  EXPECT_TRUE(MarksTissue(EventKind::kCutEnd));
  EXPECT_FALSE(MarksTissue(EventKind::kContactBegin));
}

TEST(FrameDecoder, AKeyframeNamesItsEventsLayersBeforeTheCacheHoldsThem) {
  auto wire = TriangleKeyframe();
  AddEvent(&wire, "puncture", 1, -0.0031, 0.0);
  FrameDecoder decoder;
  const ViewerFrame& frame = decoder.Decode(wire);
  ASSERT_EQ(frame.events.size(), 1u);
  EXPECT_EQ(frame.events[0].kind, EventKind::kPuncture);
  EXPECT_EQ(frame.events[0].layer, "fat");
  EXPECT_TRUE(frame.keyframe);
  EXPECT_FALSE(decoder.mesh().has_mesh()) << "decoding alone leaves the mesh";
  EXPECT_EQ(decoder.ApplyMesh(wire), ApplyResult::kApplied);
  EXPECT_EQ(decoder.mesh().live_vertex_count(), 3u);
}

TEST(FrameDecoder, ADeltaNamesLayersFromTheMeshHeldAndAnUnknownLayerStaysUnnamed) {
  FrameDecoder decoder;
  const auto key = TriangleKeyframe();
  decoder.Decode(key);
  ASSERT_EQ(decoder.ApplyMesh(key), ApplyResult::kApplied);
  hapsim::v1::Frame delta;
  delta.set_seq(1);
  delta.mutable_delta()->add_index_gaps(2);
  for (const int dq : {0, 0, -5}) delta.mutable_delta()->add_position_dq(dq);
  AddEvent(&delta, "contact_begin", 0, 0.0, 0.0);
  AddEvent(&delta, "puncture", 7, -0.001, 0.0);
  const ViewerFrame& frame = decoder.Decode(delta);
  EXPECT_EQ(frame.moved_vertices, 1u);
  ASSERT_EQ(frame.events.size(), 2u);
  EXPECT_EQ(frame.events[0].layer, "skin");
  EXPECT_EQ(frame.events[1].layer, "");
  EXPECT_EQ(frame.events[1].layer_index, 7);
}

TEST(FrameDecoder, TheToolIsDecodedWithAUnitOrientationAndThePeakIsNeverBelowTheForce) {
  auto wire = TriangleKeyframe();
  auto* tool = wire.mutable_tool();
  for (const double v : {0.001, 0.002, -0.003}) tool->add_tip_m(v);
  for (const double v : {2.0, 0.0, 0.0, 0.0}) tool->add_orientation_wxyz(v);
  for (const double v : {0.0, 0.3, 0.4}) tool->add_force_n(v);
  tool->set_contact_state("contact");
  FrameDecoder decoder;
  const ViewerFrame& frame = decoder.Decode(wire);
  ASSERT_TRUE(frame.tool.valid);
  EXPECT_EQ(frame.tool.tip_m, Eigen::Vector3d(0.001, 0.002, -0.003));
  EXPECT_NEAR(frame.tool.orientation.w(), 1.0, 1e-15);
  EXPECT_NEAR(frame.peak_force_N, 0.5, 1e-15) << "a server without peak_force_n: the frame's own force";
  wire.set_peak_force_n(1.25);
  EXPECT_EQ(decoder.Decode(wire).peak_force_N, 1.25) << "the 1 kHz peak since the previous frame";
  wire.clear_tool();
  EXPECT_FALSE(decoder.Decode(wire).tool.valid);
  EXPECT_EQ(decoder.Decode(wire).tool.force_N.norm(), 0.0);
}

TEST(EventTally, CountsKindsListsPuncturesByLayerAndDepthAndIncisions) {
  auto wire = TriangleKeyframe();
  AddEvent(&wire, "puncture", 0, -0.0012, 0.0);
  AddEvent(&wire, "puncture", 9, -0.0045, 0.0);
  AddEvent(&wire, "cut_end", -1, 0.0, 0.0123);
  AddEvent(&wire, "a_new_kind", -1, 0.0, 0.0);
  wire.mutable_topology();
  FrameDecoder decoder;
  EventTally tally;
  tally.Add(decoder.Decode(wire));
  EXPECT_EQ(tally.count(EventKind::kPuncture), 2u);
  EXPECT_EQ(tally.count(EventKind::kCutEnd), 1u);
  EXPECT_EQ(tally.count(EventKind::kUnknown), 1u);
  ASSERT_EQ(tally.punctures.size(), 2u);
  EXPECT_EQ(tally.punctures[0].layer, "skin");
  EXPECT_NEAR(tally.punctures[0].depth_mm, 1.2, 1e-12);
  EXPECT_EQ(tally.punctures[1].layer, "layer9");
  ASSERT_EQ(tally.incisions_mm.size(), 1u);
  EXPECT_NEAR(tally.incisions_mm[0], 12.3, 1e-12);
  EXPECT_EQ(tally.topology_frames, 1u);
}

}  // namespace
}  // namespace hapsim::viewer
