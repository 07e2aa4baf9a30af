// The two topics' bodies survive the trip through the wire and back, every
// field; a field added to the IDL or to the core types without the
// converters fails the size pins below first.
#include "hapsim/wire/topics_wire.h"

#include <gtest/gtest.h>

namespace hapsim::wire {
namespace {

// A new field changes these sizes (x86-64): add it to Pack/Unpack and to
// the round trips below, then re-pin.
static_assert(sizeof(hapsim_dds_LocalForceModel) == 368, "a field was added: convert it and test it here");
static_assert(sizeof(core::LocalForceModel) == 232, "a field was added: convert it and test it here");
static_assert(sizeof(hapsim_dds_StylusPose) == 176, "a field was added: convert it and test it here");
static_assert(sizeof(core::ToolInput) == 96, "a field was added: convert it and test it here");

// Distinct values, so a field copied into its neighbour shows.
Eigen::Vector3d V(double base) { return {base + 0.1, base + 0.2, base + 0.3}; }

TEST(TopicsWire, EveryFieldOfAForceModelSurvivesTheRoundTrip) {
  for (const auto state : {core::ContactState::kFree, core::ContactState::kContact, core::ContactState::kPunctured,
                           core::ContactState::kCutting}) {
    core::LocalForceModel m;
    m.state = state;
    m.anchor_W_m = V(1);
    m.normal_W = V(2).normalized();
    m.stiffness_N_per_m = 3.5;
    m.damping_Ns_per_m = 4.5;
    m.feedforward_W_N = V(5);
    m.drag_direction_W = V(6).normalized();
    m.drag_N = 7.5;
    m.drag_damping_Ns_per_m = 8.5;
    m.stick_W_m = V(9);
    m.stick_stiffness_N_per_m = 10.5;
    m.tip_anchor_W_m = V(11);
    m.tip_stiffness_N_per_m = 12.5;
    m.release_penetration_m = 14.5;
    m.release_stiffness_N_per_m = 15.5;
    m.release_damping_Ns_per_m = 16.5;
    m.tip_release_penetration_m = 17.5;
    hapsim_dds_LocalForceModel wire{};
    PackForceModel(m, V(13), &wire);
    const core::LocalForceModel back = UnpackForceModel(wire);
    EXPECT_EQ(back.state, m.state);
    EXPECT_EQ(back.anchor_W_m, m.anchor_W_m);
    EXPECT_EQ(back.normal_W, m.normal_W);
    EXPECT_EQ(back.stiffness_N_per_m, m.stiffness_N_per_m);
    EXPECT_EQ(back.damping_Ns_per_m, m.damping_Ns_per_m);
    EXPECT_EQ(back.feedforward_W_N, m.feedforward_W_N);
    EXPECT_EQ(back.drag_direction_W, m.drag_direction_W);
    EXPECT_EQ(back.drag_N, m.drag_N);
    EXPECT_EQ(back.drag_damping_Ns_per_m, m.drag_damping_Ns_per_m);
    EXPECT_EQ(back.stick_W_m, m.stick_W_m);
    EXPECT_EQ(back.stick_stiffness_N_per_m, m.stick_stiffness_N_per_m);
    EXPECT_EQ(back.tip_anchor_W_m, m.tip_anchor_W_m);
    EXPECT_EQ(back.tip_stiffness_N_per_m, m.tip_stiffness_N_per_m);
    EXPECT_EQ(back.release_penetration_m, m.release_penetration_m);
    EXPECT_EQ(back.release_stiffness_N_per_m, m.release_stiffness_N_per_m);
    EXPECT_EQ(back.release_damping_Ns_per_m, m.release_damping_Ns_per_m);
    EXPECT_EQ(back.tip_release_penetration_m, m.tip_release_penetration_m);
    EXPECT_EQ(UnpackToolForce_W_N(wire), V(13));
  }
}

TEST(TopicsWire, PackingLeavesTheEndpointsHeaderAlone) {
  hapsim_dds_LocalForceModel wire{};
  wire.device_id = 7;
  wire.server_instance = 0xABCDEF;
  wire.seq = 11;
  wire.echo_pose_seq = 12;
  wire.t_server_ns = 13;
  std::snprintf(wire.session, sizeof wire.session, "t1");
  PackForceModel(core::LocalForceModel{}, Eigen::Vector3d::Zero(), &wire);
  EXPECT_EQ(wire.device_id, 7u);
  EXPECT_EQ(wire.server_instance, 0xABCDEFu);
  EXPECT_EQ(wire.seq, 11u);
  EXPECT_EQ(wire.echo_pose_seq, 12u);
  EXPECT_EQ(wire.t_server_ns, 13);
  EXPECT_STREQ(wire.session, "t1");
}

TEST(TopicsWire, AnUnknownContactStateReadsAsFree) {
  hapsim_dds_LocalForceModel wire{};
  for (const int state : {4, 7, 255}) {
    wire.state = static_cast<std::uint8_t>(state);
    EXPECT_EQ(UnpackForceModel(wire).state, core::ContactState::kFree) << state;
  }
}

TEST(TopicsWire, EveryFieldOfAPoseSurvivesTheRoundTrip) {
  core::ToolInput tool;
  tool.valid = true;
  tool.tip_W_m = V(1);
  tool.orientation_W = Eigen::Quaterniond(0.5, -0.5, 0.5, 0.5);
  tool.velocity_W_m_per_s = V(2);
  tool.buttons = 0x5;
  hapsim_dds_StylusPose wire{};
  PackPose(tool, &wire);
  const core::ToolInput back = UnpackPose(wire);
  EXPECT_TRUE(back.valid);
  EXPECT_EQ(back.tip_W_m, tool.tip_W_m);
  EXPECT_EQ(back.orientation_W.coeffs(), tool.orientation_W.coeffs());
  EXPECT_EQ(back.velocity_W_m_per_s, tool.velocity_W_m_per_s);
  EXPECT_EQ(back.buttons, tool.buttons);
}

}  // namespace
}  // namespace hapsim::wire
