#include "loop/haptic_loop.h"

#include <deque>
#include <memory>
#include <utility>

#include "hapsim/core/scenes/scene.h"

namespace hapsim::test {
namespace {

constexpr std::int64_t kPeriodNs = 1'000'000;  // the servo's and the session's tick
constexpr std::int64_t kT0Ns = 1'000'000'000;  // simulated steady clock at the first tick

template <class T>
struct InFlight {
  std::int64_t due_ns;
  T message;
};

// The session's port: each model it writes leaves for the device.
class LinkPort : public service::SessionPort {
 public:
  explicit LinkPort(std::deque<InFlight<service::ForceModelMessage>>* out, const std::int64_t* now_ns,
                    std::int64_t delay_ns)
      : out_(out), now_ns_(now_ns), delay_ns_(delay_ns) {}
  bool WriteForceModel(const service::ForceModelMessage& m) override {
    out_->push_back({*now_ns_ + delay_ns_, m});
    return true;
  }

 private:
  std::deque<InFlight<service::ForceModelMessage>>* out_;
  const std::int64_t* now_ns_;
  std::int64_t delay_ns_;
};

}  // namespace

HapticLoopRun RunHapticLoop(const HapticLoopConfig& config) {
  const std::int64_t delay_ns = config.one_way_delay_ticks * kPeriodNs;
  std::int64_t now_ns = kT0Ns;
  std::deque<InFlight<service::PoseSample>> poses;
  std::deque<InFlight<service::ForceModelMessage>> models;
  service::SessionConfig session_config = config.session;
  session_config.tick_period_s = kPeriodNs * 1e-9;
  service::Session session(session_config, core::MakeScene({config.scene, config.params}),
                           std::make_shared<LinkPort>(&models, &now_ns, delay_ns));
  bridge::SyntheticDevice device(config.script);
  bridge::ChannelConfig channel_config = config.channel;
  channel_config.period_s = kPeriodNs * 1e-9;
  bridge::ServoChannel channel(&device, channel_config);
  common::LatestValue<bridge::ReceivedModel> inbox;

  HapticLoopRun run;
  std::uint64_t passivity_acts = 0;
  const auto ticks = static_cast<std::int64_t>(config.seconds * 1e9 / kPeriodNs);
  run.ticks.reserve(static_cast<std::size_t>(ticks));
  for (std::int64_t k = 0; k < ticks; ++k, now_ns += kPeriodNs) {
    LoopTick record;
    const bridge::DeviceReading& reading = channel.Sense(static_cast<double>(k * kPeriodNs) * 1e-9, now_ns);
    record.phase = reading.phase;
    if (channel.pose_due()) {
      const bridge::SensedPose& p = channel.pose();
      poses.push_back({now_ns + delay_ns, {p.tool, p.device_id, p.seq, now_ns + delay_ns}});
      record.pose_sent = true;
      ++run.poses_sent;
    }
    while (!poses.empty() && poses.front().due_ns <= now_ns) {
      session.OfferPose(poses.front().message);
      poses.pop_front();
    }
    session.RunTick(now_ns, now_ns);
    while (!models.empty() && models.front().due_ns <= now_ns) {
      const service::ForceModelMessage& m = models.front().message;
      inbox.Publish(
          {m.model, m.seq, m.echo_pose_seq, /*server_instance=*/1, now_ns, m.echo_pose_held_ns, m.next_model_within_s});
      ++run.models_received;
      models.pop_front();
    }
    const bridge::ChannelTick& tick = channel.Actuate(inbox);
    record.force_W_N = tick.force_W_N;
    record.requested_W_N = tick.requested_W_N;
    record.passivity_energy_J = channel.passivity_energy_J();
    const std::uint64_t acted =
        channel.safety_counters().passivity_corrected + channel.safety_counters().passivity_bounded;
    record.passivity_acted = acted != passivity_acts;
    passivity_acts = acted;
    record.model_taken = tick.took_model;
    run.ticks.push_back(std::move(record));
  }
  run.safety = channel.safety_counters();
  return run;
}

}  // namespace hapsim::test
