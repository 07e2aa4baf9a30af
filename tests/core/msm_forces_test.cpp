// MSM forces against their definition: force = -dE/dx by central finite
// differences, stiffness = -df/dx (symmetric, PSD when clamped), zero force
// at rest, and the topology hooks cutting relies on.
#include "hapsim/core/msm/msm_forces.h"

#include <cmath>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include "hapsim/core/msm/msm_step.h"
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
  EXPECT_EQ(FindSpring(model, 1, 3), kNoSpring);
  // Removing then re-adding the same spring restores the same forces.
  ASSERT_NE(AddSpring(model, 1, 3, rest, k, 0.0), kNoSpring);
  ComputeForces(model, state, state.x_m, state.v_m_per_s, f_after);
  EXPECT_LT((f_after - f_before).cwiseAbs().maxCoeff(), 1e-12);
  // Capacity is a hard limit (cutting sizes it at build): a full model
  // answers kNoSpring and is left as it was.
  EXPECT_NE(AddSpring(model, 0, 3, 0.01, 1.0, 0.0), kNoSpring);
  EXPECT_NE(AddSpring(model, 2, 4, 0.01, 1.0, 0.0), kNoSpring);
  EXPECT_NE(AddSpring(model, 1, 2, 0.01, 1.0, 0.0), kNoSpring);
  EXPECT_EQ(model.NumSprings(), 10);
  EXPECT_EQ(AddSpring(model, 0, 3, 0.01, 1.0, 0.0), kNoSpring);
  EXPECT_EQ(model.NumSprings(), 10);
}

TEST(MsmTopology, AFullNodeAdjacencyRefusesASpring) {
  MsmDef def = test::IrregularNetDef();
  def.max_node_degree = 3;  // node 0 already has 3 springs
  def.spring_capacity = 20;
  MsmModel model = BuildMsmModel(def);
  EXPECT_EQ(AddSpring(model, 0, 3, 0.01, 1.0, 0.0), kNoSpring);
  EXPECT_EQ(model.NumSprings(), 7);
  RemoveSpring(model, FindSpring(model, 0, 1));                  // node 0 down to 2 springs
  EXPECT_NE(AddSpring(model, 0, 2, 0.01, 1.0, 0.0), kNoSpring);  // node 2 had 2
}

TEST(MsmTopologyDeathTest, ProgrammingErrorsAbortWithAMessage) {
  MsmModel model = BuildMsmModel(test::IrregularNetDef());
  EXPECT_DEATH(RemoveSpring(model, 99), "RemoveSpring: no such spring");
  EXPECT_DEATH(AddSpring(model, 2, 2, 0.01, 1.0, 0.0), "nodes must be live and distinct");
  EXPECT_DEATH(AddSpring(model, 1, 2, std::nan(""), 1.0, 0.0), "finite");
}

// The per-node adjacency equals, after any sequence of edits, what a brute
// force scan of the spring arrays finds; FindSpring agrees with the scan.
TEST(MsmTopology, AdjacencyMatchesTheSpringArraysAfterRandomEdits) {
  MsmDef def = test::IrregularNetDef();
  def.spring_capacity = 10;
  MsmModel model = BuildMsmModel(def);
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> node(0, 4);
  for (int step = 0; step < 400; ++step) {
    if (model.NumSprings() > 0 && (rng() % 2 == 0 || model.NumSprings() == model.spring_capacity)) {
      RemoveSpring(model, static_cast<std::int32_t>(rng() % static_cast<unsigned>(model.NumSprings())));
    } else {
      const int a = node(rng), b = node(rng);
      if (a != b && FindSpring(model, a, b) == kNoSpring) AddSpring(model, a, b, 0.01, 100.0, 0.0);
    }
    for (std::int32_t n = 0; n < model.num_nodes; ++n) {
      std::multiset<std::int32_t> scan, listed(model.SpringsOf(n), model.SpringsOf(n) + model.DegreeOf(n));
      for (std::int32_t s = 0; s < model.NumSprings(); ++s)
        if (model.spring_i[static_cast<std::size_t>(s)] == n || model.spring_j[static_cast<std::size_t>(s)] == n) scan.insert(s);
      ASSERT_EQ(listed, scan) << "node " << n << " after edit " << step;
      for (std::int32_t m = 0; m < model.num_nodes; ++m) {
        std::int32_t expected = kNoSpring;
        for (std::int32_t s : scan)
          if (model.spring_i[static_cast<std::size_t>(s)] == m || model.spring_j[static_cast<std::size_t>(s)] == m)
            expected = s;
        if (m != n) {
          ASSERT_EQ(FindSpring(model, n, m), expected);
        }
      }
    }
  }
}

// A node activated after build behaves exactly like the same node built in
// from the start (an independent model), and deactivating it puts the
// model back to one without it.
TEST(MsmTopology, AnActivatedNodeEqualsTheSameNodeBuiltInAndDeactivationUndoesIt) {
  MsmDef without = test::IrregularNetDef();
  without.node_capacity = 6;
  MsmModel grown = BuildMsmModel(without);
  MsmState grown_state = MakeMsmState(grown);
  EXPECT_EQ(grown.num_nodes, 6);
  EXPECT_FALSE(grown.node_live[5]);

  MsmDef with = test::IrregularNetDef();  // reference: node 5 in the def
  with.x0_m.conservativeResize(3, 6);
  with.x0_m.col(5) << 0.004, -0.006, 0.002;
  with.mass_kg.conservativeResize(6);
  with.mass_kg[5] = 2e-3;
  with.node_damping_Ns_per_m.conservativeResize(6);
  with.node_damping_Ns_per_m[5] = 0.2;
  with.fixed.push_back(0);
  with.springs.push_back({5, 1});
  with.spring_rest_m.push_back(0.009);
  with.spring_k_N_per_m.push_back(140);
  with.spring_c_Ns_per_m.push_back(0.01);
  with.anchor_node.push_back(5);
  with.anchor_point_W_m.conservativeResize(3, 2);
  with.anchor_point_W_m.col(1) = with.x0_m.col(5);
  with.anchor_k_N_per_m.push_back(30.0);
  with.anchor_c_Ns_per_m = {0.0, 0.05};
  const MsmModel reference = BuildMsmModel(with);
  MsmState ref_state = MakeMsmState(reference);

  ActivateNode(grown, grown_state, 5,
               {.x_W_m = with.x0_m.col(5), .mass_kg = 2e-3, .damping_Ns_per_m = 0.2, .anchor_k_N_per_m = 30.0,
                .anchor_c_Ns_per_m = 0.05});
  ASSERT_NE(AddSpring(grown, 5, 1, 0.009, 140, 0.01), kNoSpring);
  MsmWorkspace ws_grown = MakeMsmWorkspace(grown), ws_ref = MakeMsmWorkspace(reference);
  for (int k = 0; k < 200; ++k) {
    StepMsm(grown, grown_state, 1e-4, {IntegratorKind::kSymplecticEuler, 0.5}, ws_grown);
    StepMsm(reference, ref_state, 1e-4, {IntegratorKind::kSymplecticEuler, 0.5}, ws_ref);
  }
  // Same physics; only the order of the folded anchor terms may differ.
  EXPECT_LT((grown_state.x_m - ref_state.x_m).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_GT((grown_state.x_m.col(5) - with.x0_m.col(5)).norm(), 1e-6);  // it really moved

  DeactivateNode(grown, grown_state, 5);
  EXPECT_EQ(FindSpring(grown, 5, 1), kNoSpring);
  EXPECT_EQ(grown.DegreeOf(5), 0);
  const Eigen::Vector3d parked = grown_state.x_m.col(5);
  for (int k = 0; k < 50; ++k) StepMsm(grown, grown_state, 1e-4, {IntegratorKind::kSymplecticEuler, 0.5}, ws_grown);
  EXPECT_EQ(grown_state.x_m.col(5), parked);  // a dormant node never moves
}

TEST(MsmTopologyDeathTest, ResidualStressForceAddsToTheNodeAndANodeOutOfRangeAborts) {
  const MsmModel model = BuildMsmModel(test::IrregularNetDef());
  MsmState state = MakeMsmState(model);
  Eigen::Matrix3Xd f0, f1;
  ComputeForces(model, state, state.x_m, state.v_m_per_s, f0);
  const Eigen::Vector3d residual_N(0.002, -0.001, 0.0);
  SetResidualForce(state, 4, residual_N);
  ComputeForces(model, state, state.x_m, state.v_m_per_s, f1);
  EXPECT_LT((f1.col(4) - f0.col(4) - residual_N).norm(), 1e-15);
  EXPECT_DEATH(SetResidualForce(state, 5, residual_N), "no such node");
}

}  // namespace
}  // namespace hapsim::core
