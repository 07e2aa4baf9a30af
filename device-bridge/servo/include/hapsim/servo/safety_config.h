// The force-safety chain's limits (force_safety.h says what each stage does
// with them), and how they combine with what a device reports about itself.
#pragma once
#include <cstdint>

#include "hapsim/servo/device_limits.h"

namespace hapsim::bridge {

struct SafetyConfig {
  double max_force_N = 2.5;        // magnitude clamp (device peak; Omni: 3.3 N)
  double max_rise_N_per_s = 50.0;  // 0 -> 2.5 N takes 50 ms
  // Stream gap: time since the newest model arrived (the stream stopped).
  double warn_age_s = 0.020;
  double fade_start_age_s = 0.050;
  double disarm_age_s = 0.100;
  // Physics age: time since the stylus was at the pose the held model
  // answers (the round trip plus the gap; bridge clock only, no clock
  // sync). A model describes the tissue as it was then, so this is how late
  // the trainee feels it. 50 ms: force-feedback delays from ~30-50 ms are
  // noticed, so the lag is reported; rendering from a local model stays
  // stable far beyond (model-mediated teleoperation: ~1 s round trip), so
  // force fades only from 1 s and is zero from 2 s — a link that slow
  // cannot show a trainee the tissue they are touching. Deadband coding
  // adds up to both keep-alives to this age.
  double delay_warn_age_s = 0.050;
  double delay_fade_start_age_s = 1.0;
  double delay_disarm_age_s = 2.0;

  // Caps on what a model may ask the device to render, applied to every
  // model taken. CHAI3D's device table (CPhantomDevices.cpp): PHANTOM Omni
  // 700 N/m and 5 N·s/m, Touch 400 N/m and 4 N·s/m. The damping cap also
  // bounds the passivity controller's damping.
  double max_stiffness_N_per_m = 700.0;
  double max_damping_Ns_per_m = 5.0;
  // Above this stylus speed the force is zero, like the HD API's software
  // velocity limit. 0.6 m/s is 60 times the scripted insertion and cutting
  // speed (10 mm/s) and above deliberate surgical hand moves, yet a dropped,
  // flung or kicked stylus exceeds it. Keep it under the driver's own limit
  // (HD_SOFTWARE_VELOCITY_LIMIT) so our force is zero before the driver
  // faults the device.
  double max_velocity_m_per_s = 0.6;
  // Continuous-force limit, used when the device does not report its own:
  // the PHANTOM Omni's nominal continuous force, 0.88 N. The average is an
  // exponential moving average with this time constant.
  double max_continuous_force_N = 0.88;
  double continuous_window_s = 1.0;
  // After each arming the clamp rises linearly from 0 to max_force_N over
  // this time, so a stylus that is inside an object when force returns is
  // eased out, not kicked (0: off).
  double ramp_in_s = 0.5;
  // A press of any of these buttons toggles armed; disarmed means zero
  // force. 0: no arm button, always armed.
  std::uint32_t arm_button_mask = 0;
  // Time-domain passivity controller (the observer always runs).
  bool passivity_control = true;
  // Model-jump transition: a new model whose force at the stylus differs
  // from the model it replaces by more than a just-noticeable step is
  // blended in over this many ticks (0: off), no tick changing the force by
  // more than jnd_fraction |F| + jnd_floor_N. 7 %: the just-noticeable
  // difference of force at the hand. The floor lets a transition leave zero
  // force (the relative term alone never would): 0.01 N per 1 ms tick is a
  // fifth of the rise limit and 0.4 % of the clamp.
  int model_transition_ticks = 10;
  double jnd_fraction = 0.07;
  double jnd_floor_N = 0.01;
};

// Throws std::invalid_argument naming the limit when a value is out of its
// range or the watchdog ages are not ordered.
void ValidateSafetyConfig(const SafetyConfig& c);

// The limits the chain enforces for one device: the lower of the
// configured and the reported value where the device reports one. The
// continuous force is the device's own rating when it has one (the
// configured value stands in for an unknown device).
struct EffectiveLimits {
  double max_force_N = 0.0;
  double max_continuous_force_N = 0.0;
  double max_stiffness_N_per_m = 0.0;
  double max_damping_Ns_per_m = 0.0;
  double max_velocity_m_per_s = 0.0;
};
EffectiveLimits CombineLimits(const SafetyConfig& config, const DeviceLimits& device);

}  // namespace hapsim::bridge
