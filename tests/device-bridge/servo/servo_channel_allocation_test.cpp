// The servo tick's no-allocation rule: once constructed, a ServoChannel's
// Sense + Actuate allocate nothing, whatever the script and with models
// arriving (hapsim-load runs N of them per millisecond on one thread).
#include <gtest/gtest.h>

#include "backends/synthetic_device.h"
#include "core/allocation_counter.h"
#include "hapsim/common/clock.h"
#include "hapsim/servo/servo_channel.h"

namespace hapsim::bridge {
namespace {

class ServoChannelAllocation : public ::testing::TestWithParam<const char*> {};

TEST_P(ServoChannelAllocation, ATickAllocatesNothing) {
  SyntheticScript script;
  script.kind = GetParam();
  SyntheticDevice device(script);
  common::LatestValue<ReceivedModel> inbox;
  ServoChannel channel(&device, ChannelConfig{});
  ReceivedModel model;
  model.model.state = core::ContactState::kContact;
  model.model.normal_W = Eigen::Vector3d::UnitZ();
  model.model.stiffness_N_per_m = 500.0;

  hapsim::test::ScopedAllocationCount allocations;
  for (int tick = 0; tick < 200; ++tick) {
    channel.Sense(tick * 1e-3);
    model.echo_pose_seq = channel.pose().seq;
    model.received_ns = common::SteadyNowNs();
    if (tick % 2 == 0) inbox.Publish(model);
    channel.Actuate(inbox);
  }
  EXPECT_EQ(allocations.Count(), 0u);
  EXPECT_EQ(channel.counters().models_taken, 100u);
}

INSTANTIATE_TEST_SUITE_P(EveryScript, ServoChannelAllocation,
                         ::testing::Values("insertion", "constant_speed", "random_walk", "hold"));

}  // namespace
}  // namespace hapsim::bridge
