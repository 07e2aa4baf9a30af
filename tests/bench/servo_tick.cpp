// One servo tick of the bridge (ServoChannel: read the device, take the
// newest model, evaluate the local force model, the safety chain, command
// the device) with the whole device-grade chain against the chain as it was
// before it (non-finite, clamp, watchdog, rise limit; see BasicChainOnly),
// side by side. The
// device is the synthetic one pressing 2 mm into a 500 N/m contact; a new
// model arrives every tick, as at 1 kHz from the server.
//   build/bin/bench_servo_tick --benchmark_min_time=0.5
#include <benchmark/benchmark.h>

#include "backends/synthetic_device.h"
#include "hapsim/common/clock.h"
#include "hapsim/servo/servo_channel.h"

namespace {

using namespace hapsim::bridge;

// The basic chain's behaviour: the new limits set where they never act
// (their checks still run), the passivity controller and the jump
// transition off.
SafetyConfig BasicChainOnly() {
  SafetyConfig c;
  c.max_stiffness_N_per_m = 1e5;
  c.max_damping_Ns_per_m = 1e3;
  c.max_velocity_m_per_s = 10.0;
  c.max_continuous_force_N = 10.0;
  c.ramp_in_s = 0.0;
  c.passivity_control = false;
  c.model_transition_ticks = 0;
  return c;
}

void RunServoTicks(benchmark::State& state, const SafetyConfig& safety) {
  SyntheticScript script;
  script.kind = "hold";
  script.start_height_m = 0.0;
  script.entry_W_m = Eigen::Vector3d(0, 0, -0.002);
  SyntheticDevice device(script);
  ChannelConfig config;
  config.safety = safety;
  ServoChannel channel(&device, config);
  hapsim::common::LatestValue<ReceivedModel> inbox;
  ReceivedModel model;
  model.model.state = hapsim::core::ContactState::kContact;
  model.model.stiffness_N_per_m = 500.0;
  model.model.damping_Ns_per_m = 2.0;
  double t_s = 0.0;
  for (auto _ : state) {
    channel.Sense(t_s);
    model.echo_pose_seq = channel.pose().seq;
    model.received_ns = hapsim::common::SteadyNowNs();
    inbox.Publish(model);
    benchmark::DoNotOptimize(channel.Actuate(inbox).force_W_N);
    t_s += 0.001;
  }
}

void BM_ServoTick_DeviceGradeChain(benchmark::State& state) { RunServoTicks(state, SafetyConfig{}); }
void BM_ServoTick_BasicChain(benchmark::State& state) { RunServoTicks(state, BasicChainOnly()); }

BENCHMARK(BM_ServoTick_BasicChain);
BENCHMARK(BM_ServoTick_DeviceGradeChain);

}  // namespace

BENCHMARK_MAIN();
