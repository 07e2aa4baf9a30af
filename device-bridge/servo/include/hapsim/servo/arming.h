// Whether force may reach the stylus, and the clamp's ramp-in after each
// arming.
//
// Armed by the button: with an arm button mask, each press (rising edge of
// any masked button) toggles armed, starting disarmed - the trainee arms
// once the stylus is in hand. Without one, always armed.
//
// Live: armed and the watchdog passing force (a model fresh enough). Each
// time force goes live - the first model, a fresh model after the watchdog
// disarmed, a press that arms - the clamp ramps from 0 to its full value
// over ramp_in_s, as the HD API's force ramping does when forces are
// enabled: a stylus that is inside an object at that moment is eased out
// instead of kicked. Allocation-free.
#pragma once
#include <cstdint>

namespace hapsim::bridge {

class Arming {
 public:
  Arming(std::uint32_t button_mask, double ramp_in_s)
      : mask_(button_mask), ramp_in_s_(ramp_in_s), armed_(button_mask == 0) {}
  // Once per tick, before the force stages. Returns true when a press
  // toggled armed this tick.
  bool Update(std::uint32_t buttons, bool watchdog_passes, double dt_s);
  bool armed() const { return armed_; }
  bool live() const { return live_; }
  // The fraction of the full clamp allowed this tick, in (0, 1] while
  // live (1 when not ramping, or not live: the force is zeroed later).
  double clamp_fraction() const;

 private:
  std::uint32_t mask_;
  double ramp_in_s_;
  bool armed_;
  bool live_ = false;
  std::uint32_t previous_buttons_ = 0;
  double live_for_s_ = 0.0;  // since force last went live
};

}  // namespace hapsim::bridge
