// Every MSM integrator against its scalar definition (with m != 1, so the
// paper's dropped /m would show), per-step energy identities on the
// undamped oscillator, the stability guard and the critical time step.
#include "hapsim/core/msm/msm_step.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "allocation_counter.h"
#include "hapsim/core/msm/particle_steppers.h"
#include "hapsim/core/msm/stability.h"
#include "hapsim/core/msm/msm_forces.h"
#include "msm_test_models.h"

namespace hapsim::core {
namespace {

using test::kAllMethods;
using test::Name;

TEST(MsmIntegrators, AccelerationIsForceOverMass) {
  // One symplectic step from rest at x: v1 = -h k x / m exactly (m = 2.5 kg).
  const double m_kg = 2.5, k_N_per_m = 40.0, h_s = 0.01, x_m = 0.02;
  const MsmModel model = test::AnchoredNode(m_kg, k_N_per_m);
  MsmState state = MakeMsmState(model);
  state.x_m(0, 0) = x_m;
  MsmWorkspace ws = MakeMsmWorkspace(model);
  StepMsm(model, state, h_s, {IntegratorKind::kSymplecticEuler, 0.5}, ws);
  EXPECT_NEAR(state.v_m_per_s(0, 0), -h_s * k_N_per_m * x_m / m_kg, 1e-17);
}

TEST(MsmIntegrators, EveryMethodMatchesItsScalarDefinitionWithNonUnitMass) {
  const LinearParticle p{2.5, 40.0, 0.3};
  const MsmModel model = test::AnchoredNode(p.m_kg, p.k_N_per_m, p.c_Ns_per_m);
  const Eigen::Vector3d x0(0.01, -0.02, 0.005), v0(0.1, 0.0, -0.2);
  for (const IntegratorChoice method : kAllMethods) {
    MsmState state = MakeMsmState(model);
    state.x_m.col(0) = x0;
    state.v_m_per_s.col(0) = v0;
    MsmWorkspace ws = MakeMsmWorkspace(model);
    Eigen::Vector3d x = x0, v = v0;
    for (int k = 0; k < 20; ++k) {
      StepMsm(model, state, 0.01, method, ws);
      for (int a = 0; a < 3; ++a) StepParticle(p, method, 0.01, x[a], v[a]);
    }
    // Same arithmetic up to association (CG for backward Euler: 1e-12 rel).
    EXPECT_LT((state.x_m.col(0) - x).norm(), 1e-12 * x0.norm()) << Name(method);
    EXPECT_LT((state.v_m_per_s.col(0) - v).norm(), 1e-12 * v0.norm()) << Name(method);
  }
}

// Q = v^2 + w^2 x^2 along one axis of the undamped anchored node.
struct OscillatorRun {
  double w2;
  double h;
  std::vector<double> x, v;
};

OscillatorRun RunUndamped(IntegratorKind kind, int steps) {
  const double m_kg = 2.5, k_N_per_m = 40.0;  // w^2 = 16 /s^2
  OscillatorRun run{k_N_per_m / m_kg, 0.05, {}, {}};
  const MsmModel model = test::AnchoredNode(m_kg, k_N_per_m);
  MsmState state = MakeMsmState(model);
  state.x_m(0, 0) = 0.01;
  state.v_m_per_s(0, 0) = 0.03;
  MsmWorkspace ws = MakeMsmWorkspace(model);
  ws.cg_relative_tolerance = 1e-15;
  for (int k = 0; k <= steps; ++k) {
    run.x.push_back(state.x_m(0, 0));
    run.v.push_back(state.v_m_per_s(0, 0));
    StepMsm(model, state, run.h, {kind, 0.5}, ws);
  }
  return run;
}

// Every step multiplies the energy measure v^2 + w^2 x^2 by `factor`.
void ExpectEnergyFactorEachStep(const OscillatorRun& r, double factor) {
  for (std::size_t k = 0; k + 1 < r.x.size(); ++k) {
    const double q0 = r.v[k] * r.v[k] + r.w2 * r.x[k] * r.x[k];
    const double q1 = r.v[k + 1] * r.v[k + 1] + r.w2 * r.x[k + 1] * r.x[k + 1];
    EXPECT_NEAR(q1 / q0, factor, 1e-12) << "step " << k;
  }
}

TEST(MsmIntegrators, ExplicitEulerMultipliesOscillatorEnergyByOnePlusW2H2) {
  const OscillatorRun r = RunUndamped(IntegratorKind::kExplicitEuler, 50);
  ExpectEnergyFactorEachStep(r, 1.0 + r.w2 * r.h * r.h);
}

TEST(MsmIntegrators, BackwardEulerDividesOscillatorEnergyByOnePlusW2H2) {
  const OscillatorRun r = RunUndamped(IntegratorKind::kBackwardEuler, 50);
  ExpectEnergyFactorEachStep(r, 1.0 / (1.0 + r.w2 * r.h * r.h));
}

TEST(MsmIntegrators, SymplecticEulerConservesModifiedOscillatorEnergy) {
  const OscillatorRun r = RunUndamped(IntegratorKind::kSymplecticEuler, 2000);
  // v^2 + w^2 x^2 - h w^2 x v is exactly invariant for v-then-x Euler.
  auto modified = [&](std::size_t k) {
    return r.v[k] * r.v[k] + r.w2 * r.x[k] * r.x[k] - r.h * r.w2 * r.x[k] * r.v[k];
  };
  const double i0 = modified(0);
  double max_plain_drift = 0.0;
  for (std::size_t k = 1; k < r.x.size(); ++k) {
    EXPECT_NEAR(modified(k) / i0, 1.0, 1e-12) << "step " << k;
    const double q = r.v[k] * r.v[k] + r.w2 * r.x[k] * r.x[k];
    max_plain_drift = std::max(max_plain_drift, std::abs(q / (r.v[0] * r.v[0] + r.w2 * r.x[0] * r.x[0]) - 1.0));
  }
  // ...while the plain energy oscillates by O(h w): the invariant is not trivial.
  EXPECT_GT(max_plain_drift, 0.05);
}

TEST(MsmStabilityGuard, NonFiniteStateIsReportedAndCountedNotThrown) {
  const MsmModel model = BuildMsmModel(test::IrregularNetDef());
  for (const IntegratorChoice method : kAllMethods) {
    MsmState state = MakeMsmState(model);
    MsmWorkspace ws = MakeMsmWorkspace(model);
    state.f_ext_N(0, 3) = std::numeric_limits<double>::quiet_NaN();
    StepReport r;
    EXPECT_NO_THROW(r = StepMsm(model, state, 1e-4, method, ws));
    EXPECT_FALSE(r.ok) << Name(method);
    EXPECT_TRUE(r.non_finite) << Name(method);
    EXPECT_EQ(state.blowups, 1u);
  }
}

TEST(MsmStabilityGuard, RunawayEnergyIsReportedOnTheStepItHappens) {
  MsmDef d = test::IrregularNetDef();
  d.max_kinetic_energy_J = 1e-3;
  const MsmModel model = BuildMsmModel(d);
  MsmState state = MakeMsmState(model);
  MsmWorkspace ws = MakeMsmWorkspace(model);
  // Explicit Euler far above its critical step: energy grows every step.
  int steps = 0;
  StepReport r;
  while ((r = StepMsm(model, state, 0.02, {IntegratorKind::kExplicitEuler, 0.5}, ws)).ok && steps < 10000) ++steps;
  EXPECT_LT(steps, 10000);
  EXPECT_TRUE(r.energy_exceeded);
  EXPECT_GT(r.kinetic_energy_J, d.max_kinetic_energy_J);
  // The previous step was still within the bound (detected when crossed).
  EXPECT_EQ(state.blowups, 1u);
}

TEST(MsmCriticalStep, MatchesAnalyticLimitsOfASingleMode) {
  // Anchored node: the Gershgorin bound is exact (w^2 = k/m, g = c/m).
  const double m_kg = 2.5, k_N_per_m = 40.0, c_Ns_per_m = 1.0;
  const double w2 = k_N_per_m / m_kg, g = c_Ns_per_m / m_kg;
  const ModeBounds b = EstimateModeBounds(test::AnchoredNode(m_kg, k_N_per_m, c_Ns_per_m));
  EXPECT_DOUBLE_EQ(b.omega2_max_per_s2, w2);
  EXPECT_DOUBLE_EQ(b.gamma_max_per_s, g);
  // Symplectic Euler: stable iff h^2 w^2 + 2 h g < 4 (Jury test on its 2x2 map).
  EXPECT_NEAR(CriticalTimeStep_s(b, {IntegratorKind::kSymplecticEuler, 0.5}), (-g + std::sqrt(g * g + 4 * w2)) / w2, 1e-9);
  // Explicit Euler: |1 + h lambda| <= 1 for lambda = -g/2 +- i sqrt(w^2 - g^2/4)  <=>  h <= g / w^2.
  EXPECT_NEAR(CriticalTimeStep_s(b, {IntegratorKind::kExplicitEuler, 0.5}), g / w2, 1e-9);
  // RK4, undamped: |R(i w h)| <= 1 up to w h = 2 sqrt(2).
  const ModeBounds undamped = EstimateModeBounds(test::AnchoredNode(m_kg, k_N_per_m));
  EXPECT_NEAR(CriticalTimeStep_s(undamped, {IntegratorKind::kRk4, 0.5}), 2 * std::sqrt(2.0) / std::sqrt(w2), 1e-6);
  EXPECT_TRUE(std::isinf(CriticalTimeStep_s(b, {IntegratorKind::kBackwardEuler, 0.5})));
}

TEST(MsmCriticalStep, StepBelowTheEstimateStaysBoundedAboveItGrows) {
  const MsmModel model = test::AnchoredNode(2.5, 40.0, 0.2);
  const double h_crit = CriticalTimeStep_s(EstimateModeBounds(model), {IntegratorKind::kSymplecticEuler, 0.5});
  auto final_amplitude = [&](double h) {
    MsmState state = MakeMsmState(model);
    state.x_m(0, 0) = 0.01;
    MsmWorkspace ws = MakeMsmWorkspace(model);
    for (int k = 0; k < 3000; ++k) StepMsm(model, state, h, {IntegratorKind::kSymplecticEuler, 0.5}, ws);
    return std::abs(state.x_m(0, 0)) + std::abs(state.v_m_per_s(0, 0)) * h;
  };
  EXPECT_LT(final_amplitude(0.99 * h_crit), 0.01);
  EXPECT_FALSE(final_amplitude(1.01 * h_crit) < 1.0);  // grown past 1 (or overflowed)
}

TEST(MsmStep, SameInputsGiveBitIdenticalStateHash) {
  const MsmModel model = BuildMsmModel(test::IrregularNetDef());
  for (const IntegratorChoice method : kAllMethods) {
    auto run = [&] {
      MsmState state = MakeMsmState(model);
      MsmWorkspace ws = MakeMsmWorkspace(model);
      for (int k = 0; k < 200; ++k) {
        state.f_ext_N(2, 4) = 0.01 * std::sin(0.1 * k);
        StepMsm(model, state, 2e-4, method, ws);
      }
      return StateHash(state);
    };
    EXPECT_EQ(run(), run()) << Name(method);
  }
}

TEST(MsmStep, StepAllocatesNoMemory) {
  const MsmModel model = BuildMsmModel(test::IrregularNetDef());
  LocalRegion region = MakeLocalRegion(model);
  for (const IntegratorChoice method : kAllMethods) {
    MsmState state = MakeMsmState(model);
    MsmWorkspace ws = MakeMsmWorkspace(model);
    hapsim::test::ScopedAllocationCount allocations;
    for (int k = 0; k < 20; ++k) StepMsm(model, state, 1e-4, method, ws);
    SelectLocalRegion(model, 3, 1, region);
    for (int k = 0; k < 20; ++k) StepMsmLocal(model, state, 1e-4, method, ws, region);
    EXPECT_EQ(allocations.Count(), 0u) << Name(method);
  }
}

}  // namespace
}  // namespace hapsim::core
