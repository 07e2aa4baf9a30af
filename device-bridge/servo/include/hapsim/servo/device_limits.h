// What a haptic device reports about its own limits (the HD API's nominal
// values, a vendor table). 0 means the device does not say: the safety
// chain then uses its configured value alone.
#pragma once

namespace hapsim::bridge {

struct DeviceLimits {
  double max_force_N = 0.0;             // peak force the motors may be asked for [N]
  double max_continuous_force_N = 0.0;  // force it may hold indefinitely without overheating [N]
  double max_stiffness_N_per_m = 0.0;   // stiffest spring it renders stably [N/m]
  double max_damping_Ns_per_m = 0.0;    // largest damping it renders stably [N·s/m]
  double max_velocity_m_per_s = 0.0;    // above this stylus speed its own safety faults [m/s]
};

// Throws std::invalid_argument naming the field when a limit is negative or
// not finite (a backend read garbage from its device).
void ValidateDeviceLimits(const DeviceLimits& limits);

}  // namespace hapsim::bridge
