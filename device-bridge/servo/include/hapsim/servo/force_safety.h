// Safety between the force model and the motors. The haptic device can hurt
// someone, so every commanded force passes, in order:
//  1. non-finite force -> zero (counted): nothing after it can reason
//     about NaN;
//  2. stylus velocity limit: faster than max_velocity (or a non-finite
//     velocity) -> zero, the passivity controller adding nothing either
//     (counted). A stylus moving that fast was dropped, flung or kicked:
//     any force then feeds the motion. Early, so no later stage acts on a
//     force that will not be sent;
//  3. passivity controller (passivity.h): damping added when the rendering
//     would give the hand energy it never received (and, past the damping
//     cap, the force along the motion removed). Before the clamp, so the
//     damping it adds is clamped like any other force;
//  4. magnitude clamp to the lower of max_force_N and the device's peak
//     (Omni: 3.3 N, default 2.5), rising linearly from 0 over ramp_in_s
//     after each arming (arming.h);
//  5. continuous-force derating (continuous_force_limit.h): after the clamp,
//     whose peak it averages; before the watchdog and the arm button, whose
//     zeroing it sees as cooling;
//  6. staleness watchdog on two ages of the held force model (bridge clock):
//     the stream gap (since it arrived: the stream stopped) and the physics
//     age (since the stylus was at the pose it answers: the round trip plus
//     the gap — how late the trainee feels the tissue). Each has its own
//     thresholds (safety_config.h): fresh below warn; warn (counted) from
//     warn; fade linearly from fade start to zero at disarm; disarmed (zero
//     force) beyond. The worse of the two states holds, the smaller of the
//     two factors scales the force. Disarmed lasts until a model arrives
//     whose gap is fresh and whose physics age is below its fade start.
//     No model yet: zero force. Entering warn, fading or disarmed is counted
//     as an event; a jump past a state (a stall: fresh -> disarmed) counts
//     every state the age went through;
//  7. arm button: disarmed -> zero;
//  8. rise-rate limit: the magnitude may grow by at most max_rise_N_per_s
//     per second (so re-arming, a velocity-limit release or a sudden model
//     jump never jolts the stylus); decreases pass at once — dropping force
//     is always safe. Last, so nothing after it can undo it.
// Stages 4-8 only scale the force by a factor in [0, 1]; the passivity
// observer integrates the force finally commanded.
//
// Before the chain, per model: CapModel caps its stiffnesses and dampings
// at the device's (rendering_cap.h) when the servo takes it, and Blend
// eases a model jump in over a few ticks (model_transition.h).
// Pure and allocation-free: runs in the 1 kHz servo loop.
#pragma once
#include <Eigen/Core>
#include <cstdint>

#include "hapsim/core/haptics/local_force_model.h"
#include "hapsim/servo/arming.h"
#include "hapsim/servo/continuous_force_limit.h"
#include "hapsim/servo/model_transition.h"
#include "hapsim/servo/passivity.h"
#include "hapsim/servo/safety_config.h"

namespace hapsim::bridge {

enum class WatchdogState : std::uint8_t { kNoModel, kFresh, kWarn, kFading, kDisarmed };
const char* ToString(WatchdogState s);

struct SafetyCounters {
  std::uint64_t non_finite = 0;   // ticks whose requested force was NaN/inf
  std::uint64_t clamped = 0;      // ticks cut to max_force_N
  std::uint64_t rate_limited = 0; // ticks held back by the rise limit
  std::uint64_t warnings = 0;     // times the model age crossed warn_age (entered warn or beyond)
  std::uint64_t fades = 0;        // times it crossed fade_start_age (entered fading or beyond)
  std::uint64_t disarms = 0;      // times the watchdog disarmed
  std::uint64_t delay_warnings = 0;         // times the physics age crossed delay_warn_age (felt lag)
  std::uint64_t velocity_limited = 0;       // ticks zeroed: stylus faster than max_velocity
  std::uint64_t passivity_corrected = 0;    // ticks the passivity controller damped, E back to 0
  std::uint64_t passivity_bounded = 0;      // ticks its damping hit the cap: force along the motion removed too
  std::uint64_t passivity_uncorrected = 0;  // ticks E fell below zero all the same (must stay 0)
  std::uint64_t ramp_limited = 0;           // ticks cut by the clamp while it ramped in after arming
  std::uint64_t derated = 0;                // ticks derated by the continuous-force limit
  std::uint64_t arm_toggles = 0;            // arm-button presses (each toggles armed)
  std::uint64_t models_capped = 0;          // models whose stiffness or damping was capped
  std::uint64_t model_jumps = 0;            // models blended in by the model-jump transition
  std::uint64_t jump_steps_limited = 0;     // transition ticks slowed to the just-noticeable step
};

// One tick's input to the chain.
struct SafetyInput {
  Eigen::Vector3d requested_W_N = Eigen::Vector3d::Zero();       // what the local force model asks for
  Eigen::Vector3d velocity_W_m_per_s = Eigen::Vector3d::Zero();  // the stylus's
  std::uint32_t buttons = 0;                                     // the stylus's buttons, bit per button
  double model_age_s = -1.0;    // stream gap: since the held model arrived; negative: none has
  // The gap the server promised between models (its deadband keep-alive):
  // the gap's warning and fade start that much later; zero and disarm stay
  // at disarm_age_s, whatever the promise.
  double model_gap_allowance_s = 0.0;
  double physics_age_s = -1.0;  // since the stylus was at the pose the held model answers (+inf: not one of ours);
                                // negative: not known, the gap alone decides
  double dt_s = 0.001;                                           // servo period
};

class ForceSafety {
 public:
  // Throws std::invalid_argument for a bad config or device limits.
  explicit ForceSafety(const SafetyConfig& config, const DeviceLimits& device = {});
  Eigen::Vector3d Apply(const SafetyInput& in);
  // A still stylus with no buttons pressed.
  Eigen::Vector3d Apply(const Eigen::Vector3d& requested_W_N, double model_age_s, double dt_s);

  // Per model, when the servo takes one: caps it in place (counted).
  void CapModel(core::LocalForceModel* model);
  // A taken model replaces `replaced`; new_W_N: its force at the stylus.
  void OfferModel(const core::LocalForceModel& replaced, const Eigen::Vector3d& new_W_N, const Eigen::Vector3d& x_W_m,
                  const Eigen::Vector3d& v_W_m_per_s);
  // The force to hand to Apply: model_W_N (the current model's at the
  // stylus) or, during a model jump, the blend towards it.
  Eigen::Vector3d Blend(const Eigen::Vector3d& model_W_N, const Eigen::Vector3d& x_W_m,
                        const Eigen::Vector3d& v_W_m_per_s);

  WatchdogState state() const { return state_; }
  bool armed() const { return arming_.armed(); }
  double passivity_energy_J() const { return passivity_.energy_J(); }
  double average_force_N() const { return continuous_.average_N(); }
  const EffectiveLimits& limits() const { return limits_; }
  const SafetyCounters& counters() const { return counters_; }

 private:
  // Apply's stages (in place, counted) and the watchdog's new state (counted)
  // with the factor it leaves of the force.
  void ZeroIfNonFinite(Eigen::Vector3d& f_W_N);
  bool LimitVelocity(Eigen::Vector3d& f_W_N, const Eigen::Vector3d& v_W_m_per_s);  // true: zeroed
  void ControlPassivity(Eigen::Vector3d& f_W_N, const Eigen::Vector3d& v_W_m_per_s, double dt_s);
  void ClampMagnitude(Eigen::Vector3d& f_W_N);
  void Derate(Eigen::Vector3d& f_W_N, double pass_on, double dt_s);
  double WatchdogScale(double model_age_s, double gap_allowance_s, double physics_age_s);
  void LimitRise(Eigen::Vector3d& f_W_N, double dt_s);  // against last_W_N_
  void CountEscalation(WatchdogState next);

  SafetyConfig config_;
  EffectiveLimits limits_;
  WatchdogState state_ = WatchdogState::kNoModel;
  WatchdogState physics_state_ = WatchdogState::kFresh;  // the physics age's verdict alone (counts delay warnings)
  Arming arming_;
  PassivityController passivity_;
  ContinuousForceLimit continuous_;
  ModelTransition transition_;
  Eigen::Vector3d last_W_N_ = Eigen::Vector3d::Zero();
  SafetyCounters counters_;
};

}  // namespace hapsim::bridge
