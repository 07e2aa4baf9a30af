#include "hapsim/servo/device_limits.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace hapsim::bridge {

namespace {
void RequireKnownOrPositive(double value, const char* field) {
  if (!(std::isfinite(value) && value >= 0.0)) {
    char shown[32];
    std::snprintf(shown, sizeof shown, "%g", value);
    throw std::invalid_argument(std::string("device reports ") + field + " = " + shown +
                                ": a device limit must be finite and >= 0 (0: unknown); fix the backend's Limits()");
  }
}
}  // namespace

void ValidateDeviceLimits(const DeviceLimits& d) {
  RequireKnownOrPositive(d.max_force_N, "max_force_N");
  RequireKnownOrPositive(d.max_continuous_force_N, "max_continuous_force_N");
  RequireKnownOrPositive(d.max_stiffness_N_per_m, "max_stiffness_N_per_m");
  RequireKnownOrPositive(d.max_damping_Ns_per_m, "max_damping_Ns_per_m");
  RequireKnownOrPositive(d.max_velocity_m_per_s, "max_velocity_m_per_s");
}

}  // namespace hapsim::bridge
