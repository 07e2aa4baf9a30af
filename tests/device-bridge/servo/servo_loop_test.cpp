// The servo loop end to end in one process, with the DDS side replaced by
// direct mailbox access: the watchdog must take the force to zero when the
// force model stops coming, whatever the model last said.
#include "hapsim/servo/servo_loop.h"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "backends/synthetic_device.h"
#include "hapsim/common/clock.h"

namespace hapsim::bridge {
namespace {

TEST(ServoLoop, StaleModelIsFadedToZeroAndDisarmed) {
  SyntheticScript script;
  script.kind = "hold";
  script.start_height_m = 0.0;
  script.entry_W_m = Eigen::Vector3d(0, 0, -0.002);  // held 2 mm into the tissue: the contact model pushes
  SyntheticDevice device(script);
  common::LatestValue<SensedPose> poses;
  common::LatestValue<ReceivedModel> models;
  ServoConfig config;
  config.run_seconds = 0.4;
  config.trace_capacity = 1000;
  config.safety.ramp_in_s = 0.0;  // the peak below is the rise limit's (arming_test.cpp tests the ramp-in)
  // One contact model (k = 500 N/m at the surface -> 1 N at 2 mm), then
  // silence. It arrives in the first tick, where the I/O wake-up runs, so its
  // age counts from the loop's start however long the start takes (seconds
  // under ThreadSanitizer).
  ReceivedModel m;
  m.model.state = core::ContactState::kContact;
  m.model.normal_W = Eigen::Vector3d::UnitZ();
  m.model.stiffness_N_per_m = 500.0;
  m.echo_pose_seq = 0;
  bool model_sent = false;
  ServoLoop loop(&device, config, &poses, &models, [&] {
    if (model_sent) return;
    m.received_ns = common::SteadyNowNs();
    models.Publish(m);
    model_sent = true;
  });
  std::atomic<bool> stop{false};
  const ServoReport r = loop.Run(stop);

  ASSERT_GT(r.trace.size(), 300u);
  EXPECT_EQ(r.channel.models_taken, 1u);
  // Before the fade (model younger than 50 ms) the force ramps at the rise
  // limit (50 N/s: 20 ms) up to the model's 1 N.
  double peak = 0.0;
  for (const auto& row : r.trace) {
    if (row.model_age_ms >= 0.0 && row.model_age_ms < 50.0) peak = std::max(peak, row.force_W_N.z());
  }
  EXPECT_NEAR(peak, 1.0, 0.05);
  // Late: the model is > 100 ms old, the force is exactly zero and the
  // watchdog has disarmed once.
  EXPECT_EQ(r.trace.back().force_W_N.norm(), 0.0);
  EXPECT_EQ(r.trace.back().watchdog, WatchdogState::kDisarmed);
  EXPECT_EQ(r.safety.disarms, 1u);
  // Never above the clamp.
  EXPECT_LE(r.channel.peak_force_N, config.safety.max_force_N + 1e-12);
  // The last device command leaves the motors at zero force.
  EXPECT_EQ(device.last_force_W_N().norm(), 0.0);
}

}  // namespace
}  // namespace hapsim::bridge
