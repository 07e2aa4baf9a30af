// Where a session's tick inputs come from when not from a device: a trial
// recording being replayed. The session still owns the tick count, the pause
// and the resets; the source gives what the device would have (the tool,
// device id, pose seq) and the recorded controls. Called on the tick worker:
// it must not block, and after its first call it must not allocate.
#pragma once
#include "hapsim/runtime/tick_input.h"

namespace hapsim::service {

class TickInputSource {
 public:
  virtual ~TickInputSource() = default;
  // Fills the next recorded input into *in (all but `tick`); false when
  // there is none left (the session then holds, paused).
  virtual bool Next(TickInput* in) = 0;
  // Back to the first input (the session was reset: its scene is fresh again).
  virtual void Rewind() = 0;
  // While the session is paused: true if a single step was asked for (the
  // tick then takes one input and steps).
  virtual bool TakeStep() { return false; }
};

}  // namespace hapsim::service
