// Shared set-ups for the force-safety tests: chains with every stage but the
// one under test out of the way, and a device held still wherever a test
// puts it.
#pragma once
#include <string>

#include "hapsim/servo/device.h"
#include "hapsim/servo/force_safety.h"
#include "hapsim/servo/servo_messages.h"

namespace hapsim::bridge::test {

// The defaults without the ramp-in after arming (arming_test.cpp tests it):
// tests written before it expect the full clamp or the rise limit's 0.05 N
// from the first tick.
inline SafetyConfig WithoutRampIn() {
  SafetyConfig c;
  c.ramp_in_s = 0.0;
  return c;
}

// Only the stages that cannot be switched off act: non-finite, the clamp
// (2.5 N) and the watchdog. Each test turns on what it tests.
inline SafetyConfig QuietChain() {
  SafetyConfig c = WithoutRampIn();
  c.max_rise_N_per_s = 1e9;
  c.max_velocity_m_per_s = 10.0;
  c.max_continuous_force_N = c.max_force_N;  // an average never exceeds the clamp
  c.passivity_control = false;
  c.model_transition_ticks = 0;
  return c;
}

// A contact model as the DDS side hands it over (k = 500 N/m at z = 0,
// pushing up), answering pose echo_pose_seq and arrived at received_ns.
inline ReceivedModel ContactModel(std::uint64_t echo_pose_seq, std::int64_t received_ns) {
  ReceivedModel m;
  m.model.state = core::ContactState::kContact;
  m.model.normal_W = Eigen::Vector3d::UnitZ();
  m.model.stiffness_N_per_m = 500.0;
  m.echo_pose_seq = echo_pose_seq;
  m.received_ns = received_ns;
  return m;
}

// A device whose reading and limits the test sets; it records the force.
class StillDevice final : public HapticDevice {
 public:
  std::string Name() const override { return "still"; }
  DeviceReading Read(double) override { return reading; }
  void CommandForce(const Eigen::Vector3d& force_W_N) override { last_force_W_N = force_W_N; }
  DeviceLimits Limits() const override { return limits; }

  DeviceReading reading;
  DeviceLimits limits;
  Eigen::Vector3d last_force_W_N = Eigen::Vector3d::Zero();
};

}  // namespace hapsim::bridge::test
