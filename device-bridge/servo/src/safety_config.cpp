#include "hapsim/servo/safety_config.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace hapsim::bridge {

namespace {
std::string ShortNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

// lo < value <= hi (open below) or lo <= value <= hi; NaN fails both.
void RequireIn(double value, double lo, bool lo_open, double hi, const std::string& what) {
  const bool above = lo_open ? value > lo : value >= lo;
  if (!(above && value <= hi)) {
    throw std::invalid_argument(what + " must be in " + (lo_open ? "(" : "[") + ShortNumber(lo) + ", " +
                                ShortNumber(hi) + "], got " + ShortNumber(value));
  }
}

void ValidateNewLimits(const SafetyConfig& c) {
  RequireIn(c.max_stiffness_N_per_m, 0.0, true, 1e5, "stiffness cap max_stiffness_N_per_m [N/m]");
  RequireIn(c.max_damping_Ns_per_m, 0.0, true, 1e3, "damping cap max_damping_Ns_per_m [N·s/m]");
  RequireIn(c.max_velocity_m_per_s, 0.0, true, 10.0, "stylus velocity limit max_velocity_m_per_s [m/s]");
  // Not tied to max_force_N: lowering the clamp below it must stay possible
  // (a continuous limit above the clamp never acts).
  RequireIn(c.max_continuous_force_N, 0.0, true, 10.0, "continuous-force limit max_continuous_force_N [N]");
  RequireIn(c.continuous_window_s, 0.0, true, 600.0, "continuous-force window continuous_window_s [s]");
  RequireIn(c.ramp_in_s, 0.0, false, 10.0, "force ramp-in ramp_in_s [s] (0: off)");
  RequireIn(c.model_transition_ticks, 0.0, false, 1000.0, "model-jump transition model_transition_ticks (0: off)");
  RequireIn(c.jnd_fraction, 0.0, false, 1.0, "model-jump step jnd_fraction");
  RequireIn(c.jnd_floor_N, 0.0, true, 1.0, "model-jump step floor jnd_floor_N [N]");
}
}  // namespace

void ValidateSafetyConfig(const SafetyConfig& c) {
  if (!(c.max_force_N > 0.0 && c.max_force_N <= 10.0)) throw std::invalid_argument("max force must be in (0, 10] N");
  if (!(c.max_rise_N_per_s > 0.0)) throw std::invalid_argument("force rise limit must be > 0 N/s");
  if (!(c.warn_age_s > 0.0 && c.warn_age_s <= c.fade_start_age_s && c.fade_start_age_s < c.disarm_age_s)) {
    throw std::invalid_argument("watchdog ages must satisfy 0 < warn <= fade start < disarm");
  }
  if (!(c.delay_warn_age_s > 0.0 && c.delay_warn_age_s <= c.delay_fade_start_age_s &&
        c.delay_fade_start_age_s < c.delay_disarm_age_s && c.delay_disarm_age_s <= 60.0)) {
    throw std::invalid_argument(
        "watchdog physics ages must satisfy 0 < delay warn <= delay fade start < delay disarm <= 60 s");
  }
  ValidateNewLimits(c);
}

namespace {
// The lower of the two, a reported 0 meaning "the device does not say".
double LowerOfKnown(double configured, double reported) {
  return reported > 0.0 ? std::min(configured, reported) : configured;
}
}  // namespace

EffectiveLimits CombineLimits(const SafetyConfig& c, const DeviceLimits& d) {
  EffectiveLimits e;
  e.max_force_N = LowerOfKnown(c.max_force_N, d.max_force_N);
  e.max_continuous_force_N = d.max_continuous_force_N > 0.0 ? d.max_continuous_force_N : c.max_continuous_force_N;
  e.max_stiffness_N_per_m = LowerOfKnown(c.max_stiffness_N_per_m, d.max_stiffness_N_per_m);
  e.max_damping_Ns_per_m = LowerOfKnown(c.max_damping_Ns_per_m, d.max_damping_Ns_per_m);
  e.max_velocity_m_per_s = LowerOfKnown(c.max_velocity_m_per_s, d.max_velocity_m_per_s);
  return e;
}

}  // namespace hapsim::bridge
