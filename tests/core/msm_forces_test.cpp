// MSM forces against their definition: force = -dE/dx by central finite
// differences, stiffness = -df/dx (symmetric, PSD when clamped), zero force
// at rest, and the topology hooks cutting relies on.
#include "hapsim/core/msm/msm_forces.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include "hapsim/core/msm/msm_topology.h"
#include "msm_test_models.h"

namespace hapsim::core {
namespace {

TEST(MsmForces, SpringForceIsMinusEnergyGradientByFiniteDifferences) {
  const MsmModel model = BuildMsmModel(test::IrregularNetDef());
  MsmState state = MakeMsmState(model);
  state.f_ext_N.col(3) << 0.01, -0.02, 0.03;
  state.f_residual_N.col(4) << -0.005, 0.0, 0.004;
  Eigen::Matrix3Xd f;
  ComputeForces(model, state, state.x_m, state.v_m_per_s, f);  // v = 0: no damping
  const double eps_m = 1e-7;
  for (int i = 0; i < model.num_nodes; ++i) {
    for (int a = 0; a < 3; ++a) {
      Eigen::Matrix3Xd xp = state.x_m, xm = state.x_m;
      xp(a, i) += eps_m;
      xm(a, i) -= eps_m;
      const double grad = (PotentialEnergy_J(model, state, xp) - PotentialEnergy_J(model, state, xm)) / (2 * eps_m);
      // Central difference error ~ eps^2 |E'''|: 1e-7 relative to |f| ~ 1 N.
      EXPECT_NEAR(f(a, i), -grad, 1e-6) << "node " << i << " axis " << a;
    }
  }
}

TEST(MsmForces, StiffnessIsMinusForceJacobianAndSymmetric) {
  const MsmModel model = BuildMsmModel(test::IrregularNetDef());
  const MsmState state = MakeMsmState(model);
  const Eigen::MatrixXd K = AssembleStiffness(model, state.x_m, /*clamp_compression=*/false);
  const double eps_m = 1e-7;
  for (int col = 0; col < 3 * model.num_nodes; ++col) {
    Eigen::Matrix3Xd xp = state.x_m, xm = state.x_m;
    xp(col % 3, col / 3) += eps_m;
    xm(col % 3, col / 3) -= eps_m;
    Eigen::Matrix3Xd fp, fm;
    ComputeForces(model, state, xp, state.v_m_per_s, fp);
    ComputeForces(model, state, xm, state.v_m_per_s, fm);
    const Eigen::VectorXd dfdx = (fp - fm).reshaped() / (2 * eps_m);
    // Entries ~ 100 N/m; central FD of a smooth force: ~1e-5 N/m.
    EXPECT_LT((K.col(col) + dfdx).cwiseAbs().maxCoeff(), 1e-4) << "column " << col;
  }
  EXPECT_LT((K - K.transpose()).cwiseAbs().maxCoeff(), 1e-12 * K.cwiseAbs().maxCoeff());
}

TEST(MsmForces, StiffnessIsPositiveSemiDefiniteWhenStretchedOrClamped) {
  const MsmModel model = BuildMsmModel(test::IrregularNetDef());
  const MsmState state = MakeMsmState(model);
  // The net has compressed springs: the exact Hessian is indefinite there,
  // the clamped one (what backward Euler solves with) never is.
  const Eigen::MatrixXd exact = AssembleStiffness(model, state.x_m, false);
  const Eigen::MatrixXd clamped = AssembleStiffness(model, state.x_m, true);
  const double scale = clamped.cwiseAbs().maxCoeff();
  EXPECT_LT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(exact).eigenvalues().minCoeff(), -1e-6 * scale)
      << "fixture should contain compressed springs";
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(clamped).eigenvalues().minCoeff(), -1e-12 * scale);
  // Scaled up 2x every spring is stretched: exact Hessian PSD too.
  const Eigen::Matrix3Xd stretched = 2.0 * state.x_m;
  const Eigen::MatrixXd k2 = AssembleStiffness(model, stretched, false);
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(k2).eigenvalues().minCoeff(),
            -1e-12 * k2.cwiseAbs().maxCoeff());
}

TEST(MsmForces, ZeroForceAtRestLength) {
  MsmDef d = test::IrregularNetDef();
  d.spring_rest_m.clear();  // rest = initial lengths
  d.gravity_m_per_s2.setZero();
  d.anchor_point_W_m.col(0) = d.x0_m.col(2);
  const MsmModel model = BuildMsmModel(d);
  const MsmState state = MakeMsmState(model);
  Eigen::Matrix3Xd f;
  ComputeForces(model, state, state.x_m, state.v_m_per_s, f);
  EXPECT_LT(f.cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_NEAR(PotentialEnergy_J(model, state, state.x_m), 0.0, 1e-18);
}

TEST(MsmForces, DampersOpposeRelativeVelocityAndDissipate) {
  const MsmModel model = BuildMsmModel(test::IrregularNetDef());
  MsmState state = MakeMsmState(model);
  for (int i = 0; i < model.num_nodes; ++i) state.v_m_per_s.col(i) << 0.1 * i, -0.05 * i, 0.02;
  Eigen::Matrix3Xd f_moving, f_still;
  ComputeForces(model, state, state.x_m, state.v_m_per_s, f_moving);
  ComputeForces(model, state, state.x_m, Eigen::Matrix3Xd::Zero(3, model.num_nodes), f_still);
  // Damper power sum_i (f_i(v) - f_i(0))·v_i <= 0 for any v.
  const double power_W = ((f_moving - f_still).array() * state.v_m_per_s.array()).sum();
  EXPECT_LT(power_W, 0.0);
}

TEST(MsmModelBuild, RejectsBadDefinitionsWithTheFieldName) {
  auto expect_error = [](MsmDef d, const char* field) {
    try {
      BuildMsmModel(d);
      ADD_FAILURE() << "accepted bad " << field;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  MsmDef d = test::IrregularNetDef();
  d.mass_kg[1] = 0.0;
  expect_error(d, "mass_kg");
  d = test::IrregularNetDef();
  d.springs[2] = {1, 7};
  expect_error(d, "springs");
  d = test::IrregularNetDef();
  d.spring_k_N_per_m[0] = -1.0;
  expect_error(d, "spring_k_N_per_m");
  d = test::IrregularNetDef();
  d.anchor_node = {9};
  expect_error(d, "anchor_node");
  d = test::IrregularNetDef();
  d.spring_capacity = 3;
  expect_error(d, "spring_capacity");
}

TEST(MsmTopology, RemoveAndAddSpringKeepArraysDenseAndForcesConsistent) {
  MsmModel model = BuildMsmModel(test::IrregularNetDef());
  const MsmState state = MakeMsmState(model);
  const std::int32_t s = FindSpring(model, 3, 1);
  ASSERT_GE(s, 0);
  const double rest = model.spring_rest_m[static_cast<std::size_t>(s)];
  const double k = model.spring_k_N_per_m[static_cast<std::size_t>(s)];
  Eigen::Matrix3Xd f_before, f_after;
  ComputeForces(model, state, state.x_m, state.v_m_per_s, f_before);
  RemoveSpring(model, s);
  EXPECT_EQ(model.NumSprings(), 6);
  EXPECT_EQ(FindSpring(model, 1, 3), -1);
  // Removing then re-adding the same spring restores the same forces.
  AddSpring(model, 1, 3, rest, k, 0.0);
  ComputeForces(model, state, state.x_m, state.v_m_per_s, f_after);
  EXPECT_LT((f_after - f_before).cwiseAbs().maxCoeff(), 1e-12);
  // Capacity is a hard limit (cutting must size it at build).
  AddSpring(model, 0, 3, 0.01, 1.0, 0.0);
  AddSpring(model, 2, 4, 0.01, 1.0, 0.0);
  AddSpring(model, 1, 2, 0.01, 1.0, 0.0);
  EXPECT_THROW(AddSpring(model, 0, 3, 0.01, 1.0, 0.0), std::length_error);
  EXPECT_THROW(RemoveSpring(model, 99), std::out_of_range);
  EXPECT_THROW(AddSpring(model, 2, 2, 0.01, 1.0, 0.0), std::invalid_argument);
}

TEST(MsmTopology, ResidualStressForceAddsToTheNode) {
  const MsmModel model = BuildMsmModel(test::IrregularNetDef());
  MsmState state = MakeMsmState(model);
  Eigen::Matrix3Xd f0, f1;
  ComputeForces(model, state, state.x_m, state.v_m_per_s, f0);
  const Eigen::Vector3d residual_N(0.002, -0.001, 0.0);
  SetResidualForce(state, 4, residual_N);
  ComputeForces(model, state, state.x_m, state.v_m_per_s, f1);
  EXPECT_LT((f1.col(4) - f0.col(4) - residual_N).norm(), 1e-15);
  EXPECT_THROW(SetResidualForce(state, 5, residual_N), std::out_of_range);
}

}  // namespace
}  // namespace hapsim::core
