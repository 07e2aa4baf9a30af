#include "hapsim/servo/arming.h"

#include <algorithm>

namespace hapsim::bridge {

bool Arming::Update(std::uint32_t buttons, bool watchdog_passes, double dt_s) {
  const std::uint32_t pressed = buttons & ~previous_buttons_ & mask_;
  previous_buttons_ = buttons;
  if (pressed != 0) armed_ = !armed_;
  const bool was_live = live_;
  live_ = armed_ && watchdog_passes;
  if (live_ && !was_live) live_for_s_ = 0.0;
  if (live_) live_for_s_ += dt_s;
  return pressed != 0;
}

double Arming::clamp_fraction() const {
  if (!live_ || ramp_in_s_ <= 0.0) return 1.0;
  return std::min(1.0, live_for_s_ / ramp_in_s_);
}

}  // namespace hapsim::bridge
