// Safety between the force model and the motors. The haptic device can hurt
// someone, so every commanded force passes, in order:
//  1. non-finite force -> zero (counted);
//  2. magnitude clamp to max_force_N (device peak; Omni: 3.3 N, default 2.5);
//  3. staleness watchdog on the age of the newest force model (bridge clock):
//     fresh < warn_age; warn (logged) from warn_age; fade linearly from
//     fade_start_age to zero at disarm_age; disarmed (zero force) beyond,
//     until a fresh model arrives. No model yet: zero force. Entering warn,
//     fading or disarmed is counted as an event; a jump past a state (a
//     stall: fresh -> disarmed) counts every state the age went through;
//  4. rise-rate limit: the magnitude may grow by at most max_rise_N_per_s
//     per second (so re-arming or a sudden model jump never jolts the
//     stylus); decreases pass at once — dropping force is always safe.
// Pure and allocation-free: runs in the 1 kHz servo loop.
#pragma once
#include <cstdint>

#include <Eigen/Core>

namespace hapsim::bridge {

struct SafetyConfig {
  double max_force_N = 2.5;
  double max_rise_N_per_s = 50.0;  // 0 -> 2.5 N takes 50 ms
  double warn_age_s = 0.020;
  double fade_start_age_s = 0.050;
  double disarm_age_s = 0.100;
};

// Throws std::invalid_argument when the limits are not ordered/positive.
void ValidateSafetyConfig(const SafetyConfig& c);

enum class WatchdogState : std::uint8_t { kNoModel, kFresh, kWarn, kFading, kDisarmed };
const char* ToString(WatchdogState s);

struct SafetyCounters {
  std::uint64_t non_finite = 0;   // ticks whose requested force was NaN/inf
  std::uint64_t clamped = 0;      // ticks cut to max_force_N
  std::uint64_t rate_limited = 0; // ticks held back by the rise limit
  std::uint64_t warnings = 0;     // times the model age crossed warn_age (entered warn or beyond)
  std::uint64_t fades = 0;        // times it crossed fade_start_age (entered fading or beyond)
  std::uint64_t disarms = 0;      // times the watchdog disarmed
};

class ForceSafety {
 public:
  explicit ForceSafety(const SafetyConfig& config);
  // requested: what the local force model asks for; model_age_s: age of the
  // newest model, negative if none has arrived; dt_s: servo period.
  Eigen::Vector3d Apply(const Eigen::Vector3d& requested_W_N, double model_age_s, double dt_s);
  WatchdogState state() const { return state_; }
  const SafetyCounters& counters() const { return counters_; }

 private:
  // Apply's stages 1, 2 and 4 (in place) and 3: the watchdog's new state
  // (counted) and the factor it leaves of the force.
  void ZeroIfNonFinite(Eigen::Vector3d& f_W_N);
  void ClampMagnitude(Eigen::Vector3d& f_W_N);
  double WatchdogScale(double model_age_s);
  void LimitRise(Eigen::Vector3d& f_W_N, double dt_s);  // against last_W_N_
  void CountEscalation(WatchdogState next);

  SafetyConfig config_;
  WatchdogState state_ = WatchdogState::kNoModel;
  Eigen::Vector3d last_W_N_ = Eigen::Vector3d::Zero();
  SafetyCounters counters_;
};

}  // namespace hapsim::bridge
