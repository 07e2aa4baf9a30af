// Time-domain passivity observer and controller (Hannaford & Ryu 2002) on
// the force rendered at the stylus.
//
// Observer, with the sign chosen so that E is the energy the virtual
// environment has absorbed from the hand:
//   E_n = E_{n-1} - F_n · v_n dt
// F the force on the stylus [N], v its velocity [m/s]. Pressing into a
// spring (F against v) raises E; the spring pushing back out lowers it by
// at most what it took. E < 0: the rendering has given the hand energy it
// never received - it is active (delay, a model that moves under the hand,
// a sampled stiff wall) and can build up to a kick or an oscillation.
//
// Controller: a tick may give the hand at most dt/kReserveFadeS of the
// reserve E (below zero: nothing, and the deficit is to be paid back). When
// this tick's force would give more, it adds damping -alpha v with
// alpha = (given - allowed)/(|v|^2 dt), which takes exactly the excess
// away. The part of alpha that only takes back the force's push along the
// motion (f.v/|v|^2, down to no push at all) removes force whatever the
// speed and needs no cap; what opposes the motion beyond it is damping,
// capped at the device's largest stable damping. So a stylus drawn back
// against a tissue that has returned all it stored feels the push fade
// over ~10 ms (a tenth of the reserve per tick), never cut in one tick —
// nor in pulses of over-damping and full force. Only when E is below zero
// already (a tick the controller did not see) does it take the whole push
// and the capped damping, so E rises every such tick until it is paid back.
// With the stylus still nothing can be done (and nothing is being done to
// the hand).
//
// The observer integrates the force actually commanded, after every later
// stage of the chain. Those only scale the force by a factor in [0, 1],
// which can only raise E on a tick where it was to fall, so E >= 0 holds
// whenever alpha was not capped, and E never falls below zero when it was.
#pragma once

#include <Eigen/Core>

namespace hapsim::bridge {

class PassivityController {
 public:
  enum class Action { kNone, kCorrected, kBounded };

  explicit PassivityController(double max_damping_Ns_per_m) : max_damping_Ns_per_m_(max_damping_Ns_per_m) {}
  // Adds the damping this tick's force needs to keep E >= 0 (in place).
  Action Control(Eigen::Vector3d& f_W_N, const Eigen::Vector3d& v_W_m_per_s, double dt_s) const;
  // Integrates the force commanded this tick.
  void Observe(const Eigen::Vector3d& commanded_W_N, const Eigen::Vector3d& v_W_m_per_s, double dt_s);
  double energy_J() const { return energy_J_; }

 private:
  // The reserve E is spent at most at E / kReserveFadeS: when it would run
  // out sooner (a tissue returning all it stored, a stale model pushing
  // along the motion), the push fades over ~this long instead of stopping
  // in one tick — a step the hand would feel.
  static constexpr double kReserveFadeS = 0.010;
  double max_damping_Ns_per_m_;
  double energy_J_ = 0.0;  // absorbed by the environment since the start [J]
};

}  // namespace hapsim::bridge
