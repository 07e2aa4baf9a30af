#include "hapsim/servo/force_safety.h"

#include <stdexcept>

namespace hapsim::bridge {

void ValidateSafetyConfig(const SafetyConfig& c) {
  if (!(c.max_force_N > 0.0 && c.max_force_N <= 10.0)) throw std::invalid_argument("max force must be in (0, 10] N");
  if (!(c.max_rise_N_per_s > 0.0)) throw std::invalid_argument("force rise limit must be > 0 N/s");
  if (!(c.warn_age_s > 0.0 && c.warn_age_s <= c.fade_start_age_s && c.fade_start_age_s < c.disarm_age_s)) {
    throw std::invalid_argument("watchdog ages must satisfy 0 < warn <= fade start < disarm");
  }
}

const char* ToString(WatchdogState s) {
  switch (s) {
    case WatchdogState::kNoModel: return "no-model";
    case WatchdogState::kFresh: return "fresh";
    case WatchdogState::kWarn: return "warn";
    case WatchdogState::kFading: return "fading";
    case WatchdogState::kDisarmed: return "disarmed";
  }
  return "unknown";
}

ForceSafety::ForceSafety(const SafetyConfig& config) : config_(config) { ValidateSafetyConfig(config_); }

namespace {
// 0 for no-model and fresh, then warn < fading < disarmed.
int Severity(WatchdogState s) {
  switch (s) {
    case WatchdogState::kNoModel:
    case WatchdogState::kFresh: return 0;
    case WatchdogState::kWarn: return 1;
    case WatchdogState::kFading: return 2;
    case WatchdogState::kDisarmed: return 3;
  }
  return 0;
}
}  // namespace

void ForceSafety::CountEscalation(WatchdogState next) {
  const int from = Severity(state_), to = Severity(next);
  if (from < 1 && to >= 1) ++counters_.warnings;
  if (from < 2 && to >= 2) ++counters_.fades;
  if (from < 3 && to >= 3) ++counters_.disarms;
}

// The stages in the order the header promises; each takes the previous
// stage's force.
Eigen::Vector3d ForceSafety::Apply(const Eigen::Vector3d& requested, double age_s, double dt_s) {
  Eigen::Vector3d f = requested;
  ZeroIfNonFinite(f);         // 1. garbage in -> nothing out
  ClampMagnitude(f);          // 2. magnitude clamp
  f *= WatchdogScale(age_s);  // 3. watchdog
  LimitRise(f, dt_s);         // 4. rise-rate limit (decreases pass at once)
  last_W_N_ = f;
  return f;
}

void ForceSafety::ZeroIfNonFinite(Eigen::Vector3d& f) {
  if (!f.allFinite()) {
    ++counters_.non_finite;
    f.setZero();
  }
}

void ForceSafety::ClampMagnitude(Eigen::Vector3d& f) {
  const double magnitude = f.norm();
  if (magnitude > config_.max_force_N) {
    ++counters_.clamped;
    f *= config_.max_force_N / magnitude;
  }
}

double ForceSafety::WatchdogScale(double age_s) {
  double scale = 1.0;
  WatchdogState next;
  if (age_s < 0.0) {
    next = WatchdogState::kNoModel;
    scale = 0.0;
  } else if (age_s < config_.warn_age_s) {
    next = WatchdogState::kFresh;
  } else if (age_s < config_.fade_start_age_s) {
    next = WatchdogState::kWarn;
  } else if (age_s < config_.disarm_age_s) {
    next = WatchdogState::kFading;
    scale = (config_.disarm_age_s - age_s) / (config_.disarm_age_s - config_.fade_start_age_s);
  } else {
    next = WatchdogState::kDisarmed;
    scale = 0.0;
  }
  // Once disarmed, stay at zero until a fresh model re-arms.
  if (state_ == WatchdogState::kDisarmed && next != WatchdogState::kFresh) {
    next = WatchdogState::kDisarmed;
    scale = 0.0;
  }
  CountEscalation(next);
  state_ = next;
  return scale;
}

void ForceSafety::LimitRise(Eigen::Vector3d& f, double dt_s) {
  const double allowed = last_W_N_.norm() + config_.max_rise_N_per_s * dt_s;
  const double wanted = f.norm();
  if (wanted > allowed) {
    ++counters_.rate_limited;
    f *= allowed / wanted;
  }
}

}  // namespace hapsim::bridge
