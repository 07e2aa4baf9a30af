// The time-domain passivity observer and controller. E is the energy the
// virtual environment has absorbed from the hand, E_n = E_{n-1} - F_n·v_n dt.
// An active rendering (one that gives the hand energy it never received) is
// damped so that E >= 0 after every tick (to 1e-15 J, the rounding of sums
// of 1e-5 J terms) when the damping is not capped; a passive one is left
// exactly as it is.
#include "hapsim/servo/passivity.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "hapsim/servo/force_safety.h"
#include "safety_test_setup.h"

// Its own namespace: the test files are compiled in batches (unity build).
namespace hapsim::bridge::passivity_test {
namespace {

constexpr double kDt = 0.001;
constexpr double kEnergyTolJ = 1e-15;

ForceSafety PassivityOnly(double max_damping_Ns_per_m, const DeviceLimits& device = {}) {
  SafetyConfig c = test::QuietChain();
  c.passivity_control = true;
  c.max_damping_Ns_per_m = max_damping_Ns_per_m;
  return ForceSafety(c, device);
}

SafetyInput At(const Eigen::Vector3d& force_W_N, const Eigen::Vector3d& v_W_m_per_s) {
  SafetyInput in;
  in.requested_W_N = force_W_N;
  in.velocity_W_m_per_s = v_W_m_per_s;
  in.model_age_s = 0.001;
  in.dt_s = kDt;
  return in;
}

core::LocalForceModel Contact(const Eigen::Vector3d& anchor_W_m, double k_N_per_m, double b_Ns_per_m) {
  core::LocalForceModel m;
  m.state = core::ContactState::kContact;
  m.anchor_W_m = anchor_W_m;
  m.stiffness_N_per_m = k_N_per_m;
  m.damping_Ns_per_m = b_Ns_per_m;
  return m;
}

// Pressing 1 mm into a 500 N/m contact at 10 mm/s stores
// sum 0.005 n N x 0.01 m/s x 1 ms = 2.525e-4 J. Then the contact's anchor
// rides 2 mm above the tool as it rises at 10 mm/s: 1 N along the motion,
// 1e-5 J given to the hand per tick. A tick may spend a tenth of the
// reserve (1 ms of the 10 ms fade): while E >= 1e-4 J the force is
// untouched (ticks 1-16); from tick 17 (E = 9.25e-5 J) the push is E x 1e4
// N — 0.925 N, then 10 % less every tick: it fades, never steps, and E
// never goes below zero.
TEST(Passivity, AContactWhoseAnchorRidesWithTheToolIsMadePassiveAndItsPushFades) {
  ForceSafety s = PassivityOnly(1e3);
  const Eigen::Vector3d down(0, 0, -0.01), up(0, 0, 0.01);
  Eigen::Vector3d x(0, 0, 0);
  for (int n = 1; n <= 100; ++n) {
    x += down * kDt;
    const Eigen::Vector3d f = core::EvaluateLocalForce(Contact(Eigen::Vector3d::Zero(), 500.0, 0.0), x, down);
    ASSERT_EQ(s.Apply(At(f, down)), f) << "pressing, tick " << n;
  }
  EXPECT_NEAR(s.passivity_energy_J(), 2.525e-4, kEnergyTolJ);
  double previous_N = 1.0;
  for (int j = 1; j <= 100; ++j) {
    x += up * kDt;
    const Eigen::Vector3d f = core::EvaluateLocalForce(Contact(x + Eigen::Vector3d(0, 0, 0.002), 500.0, 0.0), x, up);
    ASSERT_NEAR(f.z(), 1.0, 1e-12);
    const double reserve_J = s.passivity_energy_J();
    const double expected_N = j <= 16 ? 1.0 : reserve_J * 1e4;  // (E / 10) / (v dt)
    const double rendered_N = s.Apply(At(f, up)).z();
    ASSERT_NEAR(rendered_N, expected_N, 1e-9) << "rising, tick " << j;
    ASSERT_GE(rendered_N, 0.9 * previous_N - 1e-9) << "no step: rising, tick " << j;
    ASSERT_GE(s.passivity_energy_J(), -kEnergyTolJ) << "rising, tick " << j;
    previous_N = rendered_N;
  }
  EXPECT_NEAR(previous_N, 0.925 * std::pow(0.9, 83), 1e-9);
  EXPECT_EQ(s.counters().passivity_corrected, 84u);
  EXPECT_EQ(s.counters().passivity_uncorrected, 0u);
}

// Only the part of the force along the motion does work: moving along
// (1, 0, 1)/sqrt 2 against nothing, a 1 N push along +z keeps its workless
// part (-0.5, 0, 0.5) N.
TEST(Passivity, TheControllerRemovesOnlyTheForceAlongTheMotion) {
  ForceSafety s = PassivityOnly(1e3);
  const Eigen::Vector3d v = 0.01 * Eigen::Vector3d(1, 0, 1).normalized();
  const Eigen::Vector3d f = s.Apply(At({0, 0, 1.0}, v));
  EXPECT_NEAR(f.x(), -0.5, 1e-12);
  EXPECT_NEAR(f.y(), 0.0, 1e-12);
  EXPECT_NEAR(f.z(), 0.5, 1e-12);
  EXPECT_NEAR(s.passivity_energy_J(), 0.0, kEnergyTolJ);
  EXPECT_EQ(s.counters().passivity_corrected, 1u);
}

// With nothing in reserve (E = 0), a request of 1 N along a 10 mm/s motion
// (it would give the hand 1e-5 J per tick) needs alpha = 100 N·s/m, far past
// the device's 4 N·s/m cap — but all of it only takes back the push: the
// force along the motion goes to exactly zero every tick, nothing opposes
// the motion, E stays at 0 and the sideways 0.3 N is kept. No tick lets the
// full force through (before, the capped damping over-paid for 24 ticks and
// the 25th pushed 0.96 N: a 40 Hz train of pulses).
TEST(Passivity, WithNothingInReserveThePushAlongTheMotionIsTakenBackExactlyEveryTick) {
  DeviceLimits device;
  device.max_damping_Ns_per_m = 4.0;
  ForceSafety s = PassivityOnly(5.0, device);
  const Eigen::Vector3d up(0, 0, 0.01);
  for (int j = 1; j <= 200; ++j) {
    const Eigen::Vector3d f = s.Apply(At({0.3, 0, 1.0}, up));
    ASSERT_NEAR(f.z(), 0.0, 1e-12) << "tick " << j;
    ASSERT_NEAR(f.x(), 0.3, 1e-12) << "tick " << j;
    ASSERT_NEAR(s.passivity_energy_J(), 0.0, kEnergyTolJ) << "tick " << j;
  }
  EXPECT_EQ(s.counters().passivity_corrected, 200u);
  EXPECT_EQ(s.counters().passivity_bounded, 0u);
  EXPECT_EQ(s.counters().passivity_uncorrected, 0u);
}

// E below zero already (a tick the controller did not see gave the hand
// 2.2e-6 J): a 1 N push along 10 mm/s with the damping capped at 4 N·s/m
// loses the whole push and keeps -4 x 0.01 = -0.04 N, so E rises by
// 0.04 x 0.01 x 1 ms = 4e-7 J per tick. After 5 ticks E = -2e-7 J, which
// the push and 2 N·s/m of damping pay on the 6th (-0.02 N, E = 0); on the
// 7th the push is taken back exactly.
TEST(Passivity, BelowZeroThePushAndTheCappedDampingGoUntilEIsPaidBack) {
  PassivityController pc(4.0);
  const Eigen::Vector3d up(0, 0, 0.01);
  pc.Observe(Eigen::Vector3d(0, 0, 0.22), up, kDt);  // 0.22 N x 0.01 m/s x 1 ms given: E = -2.2e-6 J
  ASSERT_NEAR(pc.energy_J(), -2.2e-6, kEnergyTolJ);
  for (int j = 1; j <= 5; ++j) {
    Eigen::Vector3d f(0.3, 0, 1.0);
    ASSERT_EQ(pc.Control(f, up, kDt), PassivityController::Action::kBounded) << "tick " << j;
    ASSERT_NEAR(f.z(), -0.04, 1e-12) << "tick " << j;
    ASSERT_NEAR(f.x(), 0.3, 1e-12) << "tick " << j;
    pc.Observe(f, up, kDt);
    ASSERT_NEAR(pc.energy_J(), -2.2e-6 + 4e-7 * j, kEnergyTolJ) << "tick " << j;
  }
  for (const double expected_z_N : {-0.02, 0.0}) {
    Eigen::Vector3d f(0.3, 0, 1.0);
    EXPECT_EQ(pc.Control(f, up, kDt), PassivityController::Action::kCorrected);
    EXPECT_NEAR(f.z(), expected_z_N, 1e-9);
    pc.Observe(f, up, kDt);
    EXPECT_NEAR(pc.energy_J(), 0.0, kEnergyTolJ);
  }
}

// The tool moving as z = -2 mm sin(2 pi 1.5 t) in and out of a 500 N/m,
// 2 N·s/m contact, velocity the backward difference of the sampled pose:
// over 3 s the controller never acts and every force is exactly the
// request; E never goes below 0.
TEST(Passivity, APassiveSpringDamperIsLeftExactlyAsItIs) {
  ForceSafety s = PassivityOnly(1e3);
  const core::LocalForceModel contact = Contact(Eigen::Vector3d::Zero(), 500.0, 2.0);
  const double w = 2.0 * 3.14159265358979323846 * 1.5;
  Eigen::Vector3d previous(0, 0, 0);
  for (int n = 1; n <= 3000; ++n) {
    const Eigen::Vector3d x(0, 0, -0.002 * std::sin(w * n * kDt));
    const Eigen::Vector3d v = (x - previous) / kDt;
    previous = x;
    const Eigen::Vector3d f = core::EvaluateLocalForce(contact, x, v);
    ASSERT_EQ(s.Apply(At(f, v)), f) << "tick " << n;
    ASSERT_GE(s.passivity_energy_J(), 0.0) << "tick " << n;
  }
  EXPECT_GT(s.passivity_energy_J(), 0.0);  // the damper dissipated
  EXPECT_EQ(s.counters().passivity_corrected, 0u);
  EXPECT_EQ(s.counters().passivity_uncorrected, 0u);
}

// A spring rendered 20 ms late (the network's round trip, if the model were
// evaluated at an old pose) pumps energy into an oscillating hand: without
// the controller E goes negative; with it E >= 0 after every tick.
std::vector<double> DelayedSpringEnergies(bool control) {
  SafetyConfig c = test::QuietChain();
  c.passivity_control = control;
  c.max_damping_Ns_per_m = 1e3;
  ForceSafety s(c);
  const double w = 2.0 * 3.14159265358979323846 * 2.0;
  const int delay_ticks = 20;
  std::vector<double> z(2001, 0.0), energies;
  for (int n = 1; n <= 2000; ++n) {
    z[n] = 0.002 * std::sin(w * n * kDt);
    const Eigen::Vector3d v(0, 0, (z[n] - z[n - 1]) / kDt);
    const double late_z = n > delay_ticks ? z[n - delay_ticks] : 0.0;
    s.Apply(At({0, 0, -500.0 * late_z}, v));
    energies.push_back(s.passivity_energy_J());
  }
  return energies;
}

TEST(Passivity, ADelayedSpringIsActiveAndTheControllerKeepsItPassive) {
  const std::vector<double> open = DelayedSpringEnergies(false);
  EXPECT_LT(*std::min_element(open.begin(), open.end()), -1e-5);  // active: it gave the hand > 10 µJ
  const std::vector<double> controlled = DelayedSpringEnergies(true);
  for (std::size_t n = 0; n < controlled.size(); ++n) ASSERT_GE(controlled[n], -kEnergyTolJ) << "tick " << n + 1;
}

}  // namespace
}  // namespace hapsim::bridge::passivity_test
