#include "hapsim/servo/force_safety.h"

#include <algorithm>

#include "hapsim/servo/rendering_cap.h"

namespace hapsim::bridge {

namespace {
// E after a corrected tick is zero up to the rounding of sums of ~1e-5 J
// terms (seen: |E| < 3e-21 J); a real deficit is a share of a tick's work.
constexpr double kEnergyRoundingJ = 1e-15;
}  // namespace

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

namespace {
const SafetyConfig& Validated(const SafetyConfig& config, const DeviceLimits& device) {
  ValidateSafetyConfig(config);
  ValidateDeviceLimits(device);
  return config;
}

TransitionConfig TransitionOf(const SafetyConfig& c) {
  return {c.model_transition_ticks, c.jnd_fraction, c.jnd_floor_N};
}
}  // namespace

ForceSafety::ForceSafety(const SafetyConfig& config, const DeviceLimits& device)
    : config_(Validated(config, device)),
      limits_(CombineLimits(config, device)),
      arming_(config.arm_button_mask, config.ramp_in_s),
      passivity_(limits_.max_damping_Ns_per_m),
      continuous_(limits_.max_continuous_force_N, config.continuous_window_s),
      transition_(TransitionOf(config)) {}

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

// The watchdog lets force through (fully or fading).
bool Passes(WatchdogState s) {
  return s == WatchdogState::kFresh || s == WatchdogState::kWarn || s == WatchdogState::kFading;
}
}  // namespace

void ForceSafety::CountEscalation(WatchdogState next) {
  const int from = Severity(state_), to = Severity(next);
  if (from < 1 && to >= 1) ++counters_.warnings;
  if (from < 2 && to >= 2) ++counters_.fades;
  if (from < 3 && to >= 3) ++counters_.disarms;
}

// The stages in the order the header promises; each takes the previous
// stage's force. The states come first: the watchdog's and the arm
// button's decide the ramp-in of stage 4 and what stage 5 sees.
Eigen::Vector3d ForceSafety::Apply(const SafetyInput& in) {
  const double watchdog = WatchdogScale(in.model_age_s, in.model_gap_allowance_s, in.physics_age_s);
  if (arming_.Update(in.buttons, Passes(state_), in.dt_s)) ++counters_.arm_toggles;
  const double pass_on = arming_.armed() ? watchdog : 0.0;
  const Eigen::Vector3d& v = in.velocity_W_m_per_s;
  Eigen::Vector3d f = in.requested_W_N;
  ZeroIfNonFinite(f);                              // 1. garbage in -> nothing out
  const bool too_fast = LimitVelocity(f, v);       // 2. stylus too fast -> nothing out
  if (!too_fast) ControlPassivity(f, v, in.dt_s);  // 3. no energy the hand never gave
  ClampMagnitude(f);                               // 4. magnitude clamp, ramping in after arming
  Derate(f, pass_on, in.dt_s);                     // 5. continuous-force limit
  f *= watchdog;                                   // 6. watchdog
  if (!arming_.armed()) f.setZero();               // 7. arm button
  LimitRise(f, in.dt_s);                           // 8. rise-rate limit (decreases pass at once)
  const double energy_before_J = passivity_.energy_J();
  passivity_.Observe(f, v, in.dt_s);  // the observer integrates what is commanded
  // A violation left uncorrected: the rendering gave energy it never received
  // (beyond the rounding of a tick the controller brought to exactly zero).
  if (passivity_.energy_J() < -kEnergyRoundingJ && passivity_.energy_J() < energy_before_J)
    ++counters_.passivity_uncorrected;
  last_W_N_ = f;
  return f;
}

Eigen::Vector3d ForceSafety::Apply(const Eigen::Vector3d& requested, double age_s, double dt_s) {
  SafetyInput in;
  in.requested_W_N = requested;
  in.model_age_s = age_s;
  in.dt_s = dt_s;
  return Apply(in);
}

void ForceSafety::ZeroIfNonFinite(Eigen::Vector3d& f) {
  if (!f.allFinite()) {
    ++counters_.non_finite;
    f.setZero();
  }
}

bool ForceSafety::LimitVelocity(Eigen::Vector3d& f, const Eigen::Vector3d& v) {
  if (v.norm() <= limits_.max_velocity_m_per_s) return false;
  ++counters_.velocity_limited;  // a NaN velocity too: the reading is garbage
  f.setZero();
  return true;
}

void ForceSafety::ControlPassivity(Eigen::Vector3d& f, const Eigen::Vector3d& v, double dt_s) {
  if (!config_.passivity_control) return;
  switch (passivity_.Control(f, v, dt_s)) {
    case PassivityController::Action::kNone:
      break;
    case PassivityController::Action::kCorrected:
      ++counters_.passivity_corrected;
      break;
    case PassivityController::Action::kBounded:
      ++counters_.passivity_bounded;
      break;
  }
}

void ForceSafety::ClampMagnitude(Eigen::Vector3d& f) {
  const double fraction = arming_.clamp_fraction();
  const double clamp_N = limits_.max_force_N * fraction;
  const double magnitude = f.norm();
  if (magnitude > clamp_N) {
    ++(fraction < 1.0 ? counters_.ramp_limited : counters_.clamped);
    f *= clamp_N / magnitude;
  }
}

void ForceSafety::Derate(Eigen::Vector3d& f, double pass_on, double dt_s) {
  if (continuous_.Apply(f, pass_on, dt_s)) ++counters_.derated;
}

namespace {
struct AgeVerdict {
  WatchdogState state;
  double scale;  // of the force, in [0, 1]
};

// One age against its warn / fade start / disarm thresholds.
AgeVerdict JudgeAge(double age_s, double warn_s, double fade_start_s, double disarm_s) {
  if (age_s < warn_s) return {WatchdogState::kFresh, 1.0};
  if (age_s < fade_start_s) return {WatchdogState::kWarn, 1.0};
  if (age_s < disarm_s) return {WatchdogState::kFading, (disarm_s - age_s) / (disarm_s - fade_start_s)};
  return {WatchdogState::kDisarmed, 0.0};
}
}  // namespace

double ForceSafety::WatchdogScale(double age_s, double gap_allowance_s, double physics_age_s) {
  if (age_s < 0.0) {
    CountEscalation(WatchdogState::kNoModel);
    state_ = WatchdogState::kNoModel;
    return 0.0;
  }
  // A promised gap moves the warning and the fade's start, never the zero.
  const double allowance_s = std::max(0.0, gap_allowance_s);  // NaN: none
  const double fade_start_s = std::min(config_.fade_start_age_s + allowance_s, config_.disarm_age_s);
  const double warn_s = std::min(config_.warn_age_s + allowance_s, fade_start_s);
  const AgeVerdict gap = JudgeAge(age_s, warn_s, fade_start_s, config_.disarm_age_s);
  AgeVerdict physics{WatchdogState::kFresh, 1.0};
  if (physics_age_s >= 0.0) {
    physics =
        JudgeAge(physics_age_s, config_.delay_warn_age_s, config_.delay_fade_start_age_s, config_.delay_disarm_age_s);
  }
  if (Severity(physics.state) >= 1 && Severity(physics_state_) < 1) ++counters_.delay_warnings;
  physics_state_ = physics.state;
  WatchdogState next = Severity(physics.state) > Severity(gap.state) ? physics.state : gap.state;
  double scale = std::min(gap.scale, physics.scale);
  // Once disarmed, stay at zero until a model arrives that is fresh and
  // describes physics recent enough to render at full force.
  const bool rearms = gap.state == WatchdogState::kFresh && Severity(physics.state) <= 1;
  if (state_ == WatchdogState::kDisarmed && !rearms) {
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

void ForceSafety::CapModel(core::LocalForceModel* model) {
  if (CapRendering(model, limits_.max_stiffness_N_per_m, limits_.max_damping_Ns_per_m)) ++counters_.models_capped;
}

void ForceSafety::OfferModel(const core::LocalForceModel& replaced, const Eigen::Vector3d& new_W_N,
                             const Eigen::Vector3d& x, const Eigen::Vector3d& v) {
  if (transition_.Offer(replaced, new_W_N, x, v)) ++counters_.model_jumps;
}

Eigen::Vector3d ForceSafety::Blend(const Eigen::Vector3d& model_W_N, const Eigen::Vector3d& x,
                                   const Eigen::Vector3d& v) {
  bool held_back = false;
  const Eigen::Vector3d f = transition_.Step(model_W_N, x, v, &held_back);
  if (held_back) ++counters_.jump_steps_limited;
  return f;
}

}  // namespace hapsim::bridge
