// A session's trials as its ticks run: the TickListener through which the
// classroom follows a session without the session knowing of classes. On
// the tick it feeds the TrialTracker; at each snapshot it publishes the
// running trial's metrics; a reset ends the trial and publishes it. The
// TrialBook takes both from the frame pump's thread.
#pragma once
#include <cstdint>
#include <memory>

#include "hapsim/classroom/access_policy.h"
#include "hapsim/classroom/trial_tracker.h"
#include "hapsim/common/latest_value.h"
#include "hapsim/runtime/session_registry.h"
#include "hapsim/runtime/tick_listener.h"

namespace hapsim::service {

class SessionTrials final : public TickListener {
 public:
  explicit SessionTrials(TrialTargets targets = {}, std::uint64_t first_trial = 0) : tracker_(targets, first_trial) {}

  // Tick worker.
  void OnTick(const TickOutcome& tick) override;
  void OnSnapshotPublished() override { running_outbox_.Publish(tracker_.stats()); }

  // Frame pump (the TrialBook): the running trial's newest metrics, and the
  // last trial a reset ended.
  bool TakeRunning(TrialStats* out) { return running_outbox_.TakeIfNew(out); }
  bool TakeFinished(TrialStats* out) { return finished_outbox_.TakeIfNew(out); }
  const TrialTargets& targets() const { return tracker_.targets(); }

 private:
  TrialTracker tracker_;           // tick worker only
  std::uint64_t events_seen_ = 0;  // tick worker only: the scene's event count at the previous tick
  common::LatestValue<TrialStats> running_outbox_;
  common::LatestValue<TrialStats> finished_outbox_;
};

// The trials of a session, or nullptr if it has none (created without the
// factory below).
SessionTrials* TrialsOf(const Session& session);

// For the SessionRegistry: every session gets its trials, measured against
// its class's targets (none for a session in no class, or without a policy).
TickListenerFactory FollowTrials(const AccessPolicy* policy);

}  // namespace hapsim::service
