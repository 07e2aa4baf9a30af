// Force net (acupuncture paper §3.2): lattice topology, the nonlinear MSM
// static solve against an independent solve of the two-ring net, the tip's
// reaction against the forces on N1, and the shape of the force-depth curve
// against the net's design targets (skin indents 2-6 mm before puncture,
// the fat's contact lasts >= 20 ticks at 10 mm/s).
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "hapsim/core/needle/force_net.h"
#include "hapsim/core/needle/tissue_layers.h"

namespace hapsim::core {
namespace {

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

// Two rings (N1 and a hexagon of six): by symmetry each ring-2 particle
// stays in its radial plane at (r, z) and the hexagon stays regular (side r).
// Its equilibrium, written out independently of the MSM code:
//   anchor K ((L, 0) - (r, z)) + spring to N1 k_s (l - L0)/l (N1 - P)
//   + both ring neighbours -k_s (r - L0) x̂ + rim traction 2 k_s (L - L0) x̂ = 0,
// solved by Newton on (r, z); the tip force is then K (d - 6 z).
TEST(ForceNet, TwoRingNetMatchesItsStaticsSolvedIndependently) {
  ForceNetDef d;
  d.rings_w = 2;
  d.spacing_L_m = 2e-3;
  d.virtual_K_N_per_m = 160.0;
  d.surface_ratio = 1.0;
  d.prestretch = 0.02;
  d.puncture_force_N = 1.0;
  const ForceNetModel m = BuildForceNet(d);
  const double K = 160.0, ks = 160.0, L = 2e-3, L0 = L / 1.02;
  ASSERT_GT(m.force_N.size(), 20u);
  for (std::size_t k = 1; k < m.force_N.size(); k += 7) {
    const double depth = static_cast<double>(k) * d.table_step_m;
    auto residual = [&](const Eigen::Vector2d& rz) {
      const Eigen::Vector2d e(-rz.x(), -depth - rz.y());  // P -> N1 in the radial plane
      const double l = e.norm();
      Eigen::Vector2d f = K * (Eigen::Vector2d(L, 0.0) - rz) + ks * (l - L0) / l * e;
      f.x() += -ks * (rz.x() - L0) + 2.0 * ks * (L - L0);
      return f;
    };
    Eigen::Vector2d rz(L, 0.0);
    for (int it = 0; it < 50; ++it) {
      Eigen::Matrix2d J;
      for (int c = 0; c < 2; ++c) {
        Eigen::Vector2d h = Eigen::Vector2d::Zero();
        h[c] = 1e-9;
        J.col(c) = (residual(rz + h) - residual(rz - h)) / 2e-9;
      }
      rz -= J.partialPivLu().solve(residual(rz));
    }
    ASSERT_LT(residual(rz).norm(), 1e-12);
    EXPECT_NEAR(m.force_N[k], K * (depth - 6.0 * rz.y()), 1e-8) << "depth " << depth;
    // The table's ring-2 particles: inward by L - r, down by -z.
    for (int i = 1; i < 7; ++i) {
      const Eigen::Vector3d rest(m.topology.offset_T_m(0, i), m.topology.offset_T_m(1, i), 0.0);
      const Eigen::Vector3d now = rest + m.displacement_T_m[k].col(i);
      EXPECT_NEAR(now.head<2>().norm(), rz.x(), 1e-10);
      EXPECT_NEAR(now.z(), rz.y(), 1e-10);
    }
  }
}

TEST(ForceNet, ReactionOnTipEqualsSpringAndAnchorForcesOnN1) {
  // Static equilibrium of every other particle: the sum of all virtual-spring
  // pulls equals what the surface springs and N1's own anchor exert on N1
  // (at a tabulated depth, where the solve is exact).
  const ForceNetModel m = BuildForceNet(ForceNetDefFor(PaperTissueLayers()[0]));
  ForceNetState s = MakeForceNetState(m);
  PlaceForceNet(m, Eigen::Vector3d::Zero(), Eigen::Vector3d(0.1, 0.3, 1.0).normalized(), s);
  const double depth = 31 * m.def.table_step_m;
  SolveForceNet(m, -depth * s.normal_W, s);
  Eigen::Vector3d on_n1 = -m.def.virtual_K_N_per_m * (s.x_W_m.col(0) - s.rest_W_m.col(0));
  for (const auto& sp : m.topology.springs) {
    if (sp[0] != 0 && sp[1] != 0) continue;
    const Eigen::Vector3d e = s.x_W_m.col(sp[0] == 0 ? sp[1] : sp[0]) - s.x_W_m.col(0);
    on_n1 += m.surface_k_N_per_m * (e.norm() - m.surface_rest_m) / e.norm() * e;
  }
  EXPECT_LT((on_n1 - NetReactionOnTip_W_N(m, s)).norm(), 1e-8);
  EXPECT_GT(on_n1.dot(s.normal_W), 0.3);
}

// Like skin: the force stiffens with depth (J-shaped), and the skin gives
// way after millimetres of indentation (target: 2-6 mm), the fat after a
// contact long enough to feel (>= 20 ticks at 10 mm/s = 0.2 mm).
TEST(ForceNet, ForceStiffensWithDepthAndTheSkinIndentsMillimetresBeforePuncture) {
  const auto layers = PaperTissueLayers();
  for (const auto& layer : layers) {
    const ForceNetModel m = BuildForceNet(ForceNetDefFor(layer));
    for (std::size_t k = 2; k < m.force_N.size(); ++k) {
      ASSERT_GT(m.force_N[k], m.force_N[k - 1]) << layer.name;
      ASSERT_GT(m.force_N[k] - m.force_N[k - 1], m.force_N[k - 1] - m.force_N[k - 2]) << layer.name << " not stiffening";
    }
    EXPECT_NEAR(NetForceAtDepth_N(m, m.puncture_depth_m), m.def.puncture_force_N, 1e-12);
  }
  const ForceNetModel skin = BuildForceNet(ForceNetDefFor(layers[0]));
  EXPECT_GE(skin.puncture_depth_m, 2e-3);
  EXPECT_LE(skin.puncture_depth_m, 6e-3);
  EXPECT_GE(BuildForceNet(ForceNetDefFor(layers[1])).puncture_depth_m, 0.2e-3);
}

TEST(ForceNet, DeformationFallsOffMonotonicallyWithRing) {
  const ForceNetModel m = BuildForceNet(ForceNetDefFor(PaperTissueLayers()[0]));
  ForceNetState s = MakeForceNetState(m);
  PlaceForceNet(m, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), s);
  SolveForceNet(m, Eigen::Vector3d(0, 0, -m.puncture_depth_m), s);
  for (int j = 1; j < m.def.rings_w; ++j) EXPECT_LE(s.ring_Z_m[j], s.ring_Z_m[j - 1]);
  EXPECT_GT(s.ring_Z_m[1], 0.1 * s.ring_Z_m[0]);  // the dimple spreads beyond N1
}

TEST(ForceNet, RejectsBadParametersAndAnUnreachablePunctureForce) {
  ForceNetDef d = ForceNetDefFor(PaperTissueLayers()[0]);
  d.rings_w = 1;
  EXPECT_THROW(BuildForceNet(d), std::invalid_argument);
  d = ForceNetDefFor(PaperTissueLayers()[0]);
  d.virtual_K_N_per_m = -1;
  EXPECT_THROW(BuildForceNet(d), std::invalid_argument);
  d = ForceNetDefFor(PaperTissueLayers()[0]);
  d.puncture_force_N = 50.0;  // beyond 20 mm of indentation
  try {
    BuildForceNet(d);
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("puncture force"), std::string::npos) << e.what();
  }
}

TEST(ShaftDamping, AccumulatesLayerByLayerAsTableOne) {
  const auto layers = PaperTissueLayers();
  // Tip 5 mm into the fat: d_s h_s + d_f h.
  const double depth[3] = {5.8e-3, 5.0e-3, -4.2e-3};
  EXPECT_NEAR(ShaftDamping_Ns_per_m(layers, depth, 2), 3000 * 0.8e-3 + 1000 * 5e-3, 1e-12);
  EXPECT_NEAR(ShaftDamping_Ns_per_m(layers, depth, 1), 3000 * 0.8e-3, 1e-12);  // fat not yet pierced
}

}  // namespace
}  // namespace hapsim::core
