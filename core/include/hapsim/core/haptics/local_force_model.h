// The "intermediate representation" the physics sends to the haptic device
// (Mark et al. 1996): a small local model the device-bridge evaluates at
// 1 kHz between physics ticks, so the force stays smooth and stiff even if
// the network hiccups. World frame W, SI units.
#pragma once
#include <cstdint>

#include <Eigen/Core>

namespace hapsim::core {

enum class ContactState : std::uint8_t {
  kFree = 0,       // nothing touched: force = f_ff (normally zero)
  kContact = 1,    // pressing a surface: half-space spring-damper at anchor/normal
  kPunctured = 2,  // needle inside tissue: lateral "tunnel" spring + axial damping
  kCutting = 3,    // blade drawing an incision: contact law on the normal plus drag along the cut
};

const char* ToString(ContactState s);

struct LocalForceModel {
  ContactState state = ContactState::kFree;
  Eigen::Vector3d anchor_W_m = Eigen::Vector3d::Zero();  // contact point / tunnel entry [m]
  // kContact and kCutting: outward surface normal (unit). kPunctured:
  // needle axis, unit, pointing out of the tissue (opposite to insertion).
  Eigen::Vector3d normal_W = Eigen::Vector3d::UnitZ();
  double stiffness_N_per_m = 0.0;     // k: normal (contact) or lateral (tunnel) stiffness
  double damping_Ns_per_m = 0.0;      // b: along the normal / axis
  Eigen::Vector3d feedforward_W_N = Eigen::Vector3d::Zero();  // f_ff [N], added as is
  // kCutting only: the resistance of tissue being cut, along the incision
  // direction t (unit, in the skin plane): a smoothed Coulomb drag plus a
  // viscous part (see EvaluateLocalForce).
  Eigen::Vector3d drag_direction_W = Eigen::Vector3d::Zero();
  double drag_N = 0.0;                // Coulomb level [N] (kCutting: cutting force; kPunctured: shaft friction)
  double drag_damping_Ns_per_m = 0.0; // viscous part [N·s/m]
  // kPunctured only: stick-slip shaft friction. The shaft sticks to the
  // tissue at stick_W_m; an axial spring to it gives the friction force,
  // clamped to drag_N (beyond it the shaft slips; the server moves the
  // stick point each tick). Nonzero with the needle at rest.
  Eigen::Vector3d stick_W_m = Eigen::Vector3d::Zero();
  double stick_stiffness_N_per_m = 0.0;  // 0: no Coulomb friction (the paper's viscous law)
  // kPunctured only: the next layer under the tip, a half-space across the
  // axis at tip_anchor_W_m pushing out along the axis (0: the tip presses
  // nothing).
  Eigen::Vector3d tip_anchor_W_m = Eigen::Vector3d::Zero();
  double tip_stiffness_N_per_m = 0.0;
  // Puncture, rendered where it happens rather than a round trip later: the
  // penetration at which the pressed layer gives way (0: it never does in
  // this model). kContact: past it the skin's spring and the feed-forward
  // are gone and the needle is in a tunnel along n through the anchor
  // (lateral spring release_stiffness, axial damping release_damping) until
  // the next model says what the physics did. kPunctured: past
  // tip_release_penetration_m the next layer's push (the tip term) is gone.
  // Position-based, so the law stays a pure function of the tool's state.
  double release_penetration_m = 0.0;
  double release_stiffness_N_per_m = 0.0;
  double release_damping_Ns_per_m = 0.0;
  double tip_release_penetration_m = 0.0;
};

// Speed at which the smoothed Coulomb drag reaches tanh(1) = 76 % of drag_N
// [m/s]: smoothing keeps the drag from chattering when the blade stops.
inline constexpr double kDragSmoothingSpeed_m_per_s = 0.002;

// Force on the tool tip [N] at position x_W_m moving with v_W_m_per_s, by the
// law of model.state:
//  kFree:      F = f_ff
//  kContact:   p = (anchor - x)·n (penetration, m);
//              F = f_ff + max(0, k p - b (v·n)) n  when p > 0, else f_ff
//              (the max keeps the damper from pulling the tool into the surface);
//              punctured locally (p_r = release_penetration > 0 and p >= p_r):
//              F = -k_r d - b_r (v·n) n, d the lateral offset from the line
//              through anchor along n, k_r/b_r the release stiffness/damping
//  kPunctured: d = (x - anchor) - ((x - anchor)·n) n (lateral offset);
//              F = f_ff - k d - b (v·n) n
//                  - clamp(k_stick (x - stick)·n, ±drag_N) n   (stick-slip friction)
//                  + max(0, k_tip (tip_anchor - x)·n) n        (the next layer under the tip,
//                    0 once (tip_anchor - x)·n >= tip_release_penetration > 0: it gave way)
//  kCutting:   the kContact law on (anchor, n, k, b), plus the drag along t,
//              v_t = v·t: F_t = -(drag_N tanh(v_t / v_s) + drag_damping v_t) t
//              with v_s = kDragSmoothingSpeed_m_per_s
// Pure and allocation-free: runs inside the 1 kHz servo loop.
Eigen::Vector3d EvaluateLocalForce(const LocalForceModel& model, const Eigen::Vector3d& x_W_m,
                                   const Eigen::Vector3d& v_W_m_per_s);

}  // namespace hapsim::core
