#include "hapsim/recording/session_recorder.h"

namespace hapsim::service {

void SessionRecorder::OnTick(const TickOutcome& tick) {
  const TickInput& in = tick.input;
  if (in.reset) trial_first_tick_ = in.tick;  // a reset starts the next trial (and its own file)
  TickRecord record;
  record.input = in;
  if ((in.tick - trial_first_tick_ + 1) % checkpoint_every_ == 0) {
    record.has_hash = true;
    record.state_hash = tick.scene.StateHash();
    record.sim_time_s = tick.scene.SimTime_s();
  }
  if (!ring_.Push(record)) lost_.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace hapsim::service
