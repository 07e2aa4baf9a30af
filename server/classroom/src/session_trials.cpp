#include "hapsim/classroom/session_trials.h"

#include <algorithm>

namespace hapsim::service {

void SessionTrials::OnTick(const TickOutcome& tick) {
  const TickInput& in = tick.input;
  const core::Scene& scene = tick.scene;
  if (in.reset) finished_outbox_.Publish(tracker_.StartNext());  // a reset ends the trial
  TrialTick t;
  t.sim_time_s = scene.SimTime_s();
  t.force_N = tick.tool_force_N;
  t.current_layer = scene.Status().current_layer;
  t.tip_depth_m = scene.Status().tip_depth_m;
  t.contact = tick.contact;
  t.tip_W_m = in.tool.tip_W_m;
  t.tool_present = in.tool.valid && !in.paused;
  // The events logged since the previous tick (as many as the scene still holds).
  const auto events = scene.Events();
  const std::uint64_t total = scene.EventsTotal();
  const std::size_t fresh =
      static_cast<std::size_t>(std::min<std::uint64_t>(total > events_seen_ ? total - events_seen_ : 0, events.size()));
  t.new_events = std::span<const core::SceneEvent>(events.data() + (events.size() - fresh), fresh);
  events_seen_ = total;
  tracker_.OnTick(t);
}

SessionTrials* TrialsOf(const Session& session) { return FindTickListener<SessionTrials>(session.tick_listener()); }

TickListenerFactory FollowTrials(const AccessPolicy* policy) {
  return [policy](const SessionConfig& config) -> std::shared_ptr<TickListener> {
    const ClassDef* cls = policy ? policy->ClassOf(config.id) : nullptr;
    return std::make_shared<SessionTrials>(cls ? cls->targets : TrialTargets{});
  };
}

}  // namespace hapsim::service
