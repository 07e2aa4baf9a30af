// Force net (acupuncture paper §3.2): lattice topology, the MSM static solve
// against analytic and independent references, eq. (6) for the solved net,
// and the skin puncture force against the measured range.
#include <cmath>
#include <random>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "hapsim/core/needle/force_net.h"
#include "hapsim/core/needle/tissue_layers.h"

namespace hapsim::core {
namespace {

ForceNetDef SkinNet() { return ForceNetDefFor(PaperTissueLayers()[0]); }

TEST(HexNetTopology, RingJHoldsSixTimesJMinusOneParticlesAtSpacingL) {
  for (int w : {1, 2, 4, 8, 10}) {
    const HexNetTopology t = MakeHexNetTopology(w, 2e-3);
    EXPECT_EQ(t.NumNodes(), 1 + 3 * w * (w - 1));
    for (int j = 1; j <= w; ++j)
      EXPECT_EQ(t.ring_first_node[j] - t.ring_first_node[j - 1], j == 1 ? 1 : 6 * (j - 1));
    for (const auto& s : t.springs)
      EXPECT_NEAR((t.offset_T_m.col(s[0]) - t.offset_T_m.col(s[1])).norm(), 2e-3, 1e-15);
    // A hexagon of side w-1 on a triangular lattice: 6(w-1)² triangles.
    EXPECT_EQ(t.triangles.size(), static_cast<std::size_t>(6 * (w - 1) * (w - 1)));
    // Ring j lies at hex distance j-1: radius between (j-1)L√3/2 and (j-1)L.
    for (int i = 0; i < t.NumNodes(); ++i) {
      const double r = t.offset_T_m.col(i).norm() / 2e-3, d = t.ring_of_node[i] - 1;
      EXPECT_GE(r, d * std::sqrt(3.0) / 2 - 1e-12);
      EXPECT_LE(r, d + 1e-12);
    }
  }
}

TEST(ForceNet, TwoRingNetMatchesAnalyticFallOff) {
  // Ring-2 particle: K Z2 + k_s (Z2 - Z1) = 0 (its ring neighbours move with
  // it), so Z2 = τ/(1+τ) Z1 and F = K (1 + 6τ/(1+τ)) Z1.
  ForceNetDef d;
  d.rings_w = 2;
  d.tension_ratio = 3.0;
  const ForceNetModel m = BuildForceNet(d);
  EXPECT_NEAR(m.ring_influence[1], 0.75, 1e-12);
  EXPECT_NEAR(m.influence_sum, 1.0 + 6 * 0.75, 1e-11);
}

TEST(ForceNet, InfluenceMatchesIndependentDenseMembraneSolve) {
  // Independent reference: assemble K I + k_s (graph Laplacian) for the free
  // particles and solve with a dense LU.
  const ForceNetModel m = BuildForceNet(SkinNet());
  const auto& t = m.topology;
  const int n = t.NumNodes();
  Eigen::MatrixXd A = m.def.virtual_K_N_per_m * Eigen::MatrixXd::Identity(n, n);
  for (const auto& s : t.springs) {
    A(s[0], s[0]) += m.surface_k_N_per_m;
    A(s[1], s[1]) += m.surface_k_N_per_m;
    A(s[0], s[1]) -= m.surface_k_N_per_m;
    A(s[1], s[0]) -= m.surface_k_N_per_m;
  }
  const Eigen::VectorXd g_free = A.bottomRightCorner(n - 1, n - 1).lu().solve(-A.col(0).tail(n - 1));
  EXPECT_LT((g_free - m.influence.tail(n - 1)).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_LT(m.static_residual_N, 1e-9);
}

TEST(ForceNet, SurfaceForceEqualsPaperEquationSixForSolvedNet) {
  const ForceNetModel m = BuildForceNet(SkinNet());
  ForceNetState s = MakeForceNetState(m);
  const Eigen::Vector3d n = Eigen::Vector3d(0.2, -0.1, 1.0).normalized();
  PlaceForceNet(m, Eigen::Vector3d(0.01, 0.02, -0.003), n, s);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.5e-3, 0.5e-3);
  for (int trial = 0; trial < 20; ++trial) {
    // Oblique press: inward along the normal plus a lateral drag.
    const Eigen::Vector3d tip = s.n1_rest_W_m - 0.3e-3 * n + Eigen::Vector3d(u(rng), u(rng), u(rng)).cross(n);
    SolveForceNet(m, tip, s);
    const double f_n = NetReactionOnTip_W_N(m, s).dot(n);
    EXPECT_GT(f_n, 0.0);
    EXPECT_NEAR(f_n, PaperSurfaceForce_N(m, s.ring_Z_m), 1e-12 * f_n);
  }
}

TEST(ForceNet, ReactionOnTipEqualsSpringAndAnchorForcesOnN1) {
  // Static equilibrium of every other particle: the sum of all virtual-spring
  // pulls equals what the surface springs and N1's own anchor exert on N1.
  const ForceNetModel m = BuildForceNet(SkinNet());
  ForceNetState s = MakeForceNetState(m);
  PlaceForceNet(m, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), s);
  SolveForceNet(m, Eigen::Vector3d(0.1e-3, -0.05e-3, -0.2e-3), s);
  Eigen::Vector3d on_n1 = -m.def.virtual_K_N_per_m * (s.x_W_m.col(0) - s.rest_W_m.col(0));
  for (const auto& sp : m.topology.springs) {
    if (sp[0] == 0) on_n1 += m.surface_k_N_per_m * ((s.x_W_m.col(sp[1]) - s.x_W_m.col(0)) -
                                                   (s.rest_W_m.col(sp[1]) - s.rest_W_m.col(0)));
    if (sp[1] == 0) on_n1 += m.surface_k_N_per_m * ((s.x_W_m.col(sp[0]) - s.x_W_m.col(0)) -
                                                   (s.rest_W_m.col(sp[0]) - s.rest_W_m.col(0)));
  }
  EXPECT_LT((on_n1 - NetReactionOnTip_W_N(m, s)).norm(), 1e-10 * on_n1.norm());
}

TEST(ForceNet, SurfaceForceIsTheDerivativeOfStoredEnergyByFiniteDifferences) {
  // Elastic energy in displacement form (the edge traction balances the
  // rest tension, so no linear term): ½ K Σ|u_i|² + ½ k_s Σ_springs |u_i - u_j|².
  // With every other particle in equilibrium, dE/dZ_1 is the force the tip
  // must push with, i.e. F·n (envelope theorem).
  const ForceNetModel m = BuildForceNet(SkinNet());
  ForceNetState s = MakeForceNetState(m);
  const Eigen::Vector3d n = Eigen::Vector3d(0.1, 0.3, 1.0).normalized();
  PlaceForceNet(m, Eigen::Vector3d::Zero(), n, s);
  auto energy_J = [&](double z1_m) {
    SolveForceNet(m, -z1_m * n, s);
    const Eigen::Matrix3Xd u = s.x_W_m - s.rest_W_m;
    double e = 0.5 * m.def.virtual_K_N_per_m * u.squaredNorm();
    for (const auto& sp : m.topology.springs) e += 0.5 * m.surface_k_N_per_m * (u.col(sp[0]) - u.col(sp[1])).squaredNorm();
    return e;
  };
  const double z1 = 0.08e-3, h = 1e-7;
  const double de_dz_N = (energy_J(z1 + h) - energy_J(z1 - h)) / (2 * h);
  SolveForceNet(m, -z1 * n, s);
  const double f_n = NetReactionOnTip_W_N(m, s).dot(n);
  EXPECT_NEAR(de_dz_N, f_n, 1e-7 * f_n);
}

TEST(ForceNet, FlatProfileLimitGivesMissionStiffness) {
  // τ → ∞: every ring moves with N1, F = K (1 + 3w(w-1)) Z1 = 27.04 N/mm for skin.
  ForceNetDef d = SkinNet();
  d.tension_ratio = 1e4;
  const ForceNetModel m = BuildForceNet(d);
  EXPECT_NEAR(m.def.virtual_K_N_per_m * m.influence_sum / 1e3, 27.04, 0.05 * 27.04);
}

TEST(ForceNet, DeformationFallsOffMonotonicallyWithRing) {
  const ForceNetModel m = BuildForceNet(SkinNet());
  for (int j = 1; j < m.def.rings_w; ++j) EXPECT_LT(m.ring_influence[j], m.ring_influence[j - 1]);
  EXPECT_GT(m.ring_influence[m.def.rings_w - 1], 0.0);
}

TEST(ForceNet, SkinPeakPunctureForceIsInMeasuredRange) {
  // van Gerwen 2012: skin puncture 0.1–2 N (median 1.22 N over 24 studies).
  const ForceNetModel m = BuildForceNet(SkinNet());
  const double peak_N = m.def.virtual_K_N_per_m * m.influence_sum * m.critical_deflection_m;
  EXPECT_GT(peak_N, 0.1);
  EXPECT_LT(peak_N, 2.0);
  // At Z1* ring w is exactly at the threshold.
  EXPECT_NEAR(m.ring_influence[m.def.rings_w - 1] * m.critical_deflection_m, m.threshold_m, 1e-15);
}

TEST(ForceNet, RejectsBadParameters) {
  ForceNetDef d = SkinNet();
  d.rings_w = 1;
  EXPECT_THROW(BuildForceNet(d), std::invalid_argument);
  d = SkinNet();
  d.virtual_K_N_per_m = -1;
  EXPECT_THROW(BuildForceNet(d), std::invalid_argument);
}

TEST(ShaftDamping, AccumulatesLayerByLayerAsTableOne) {
  const auto layers = PaperTissueLayers();
  // Tip 5 mm into the fat: d_s h_s + d_f h.
  const double depth[3] = {5.8e-3, 5.0e-3, -4.2e-3};
  EXPECT_NEAR(ShaftDamping_Ns_per_m(layers, depth, 2), 3000 * 0.8e-3 + 1000 * 5e-3, 1e-12);
  EXPECT_NEAR(ShaftDamping_Ns_per_m(layers, depth, 1), 3000 * 0.8e-3, 1e-12);  // fat not yet pierced
  // Shaft friction at 5 mm/s is of order 1e-2 N per mm inserted (skin).
  EXPECT_NEAR(layers[0].damping_Ns_per_m2 * 5e-3 * 1e-3, 0.015, 1e-12);
}

}  // namespace
}  // namespace hapsim::core
