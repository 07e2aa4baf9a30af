// Meshless point-primitive elasticity (vascular paper §2.1, Müller et al.
// 2004) and the MLS surface map (§2.3), checked against analytic references:
// the affine patch test, rigid-motion invariance, forces against the
// energy's numerical derivative, the MLS map's partition of unity and linear
// reproduction, and a uniaxial tension test that recovers Young's modulus.
#include <cmath>
#include <cstdio>
#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "core/allocation_counter.h"
#include "hapsim/core/meshless/meshless_forces.h"
#include "hapsim/core/meshless/meshless_model.h"
#include "hapsim/core/meshless/mls_surface_map.h"

namespace hapsim::core {
namespace {

constexpr double kSpacing_m = 1e-3;
constexpr double kDensity_kg_per_m3 = 1000.0;

// Nodes at the centres of an nx x ny x nz block of s-cubes: each node owns
// one cube, so the volumes add up to the block's exactly.
MeshlessDef Block(int nx, int ny, int nz, double h_over_s, double E_Pa = 1e5, double nu = 0.3) {
  MeshlessDef d;
  d.x0_m.resize(3, nx * ny * nz);
  int i = 0;
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) d.x0_m.col(i++) = kSpacing_m * Eigen::Vector3d(x + 0.5, y + 0.5, z + 0.5);
  const double v = kSpacing_m * kSpacing_m * kSpacing_m;
  d.volume_m3.assign(static_cast<std::size_t>(i), v);
  d.mass_kg.assign(static_cast<std::size_t>(i), kDensity_kg_per_m3 * v);
  d.support_radius_m = h_over_s * kSpacing_m;
  d.youngs_modulus_Pa = E_Pa;
  d.poisson_ratio = nu;
  return d;
}

TEST(Meshless, AffinePatchTestGivesTheImposedGradientToRoundOff) {
  // Every node, boundary ones included (one-sided neighbourhoods): the MLS
  // gradient of an affine field is exact.
  const MeshlessModel model = BuildMeshlessModel(Block(6, 5, 7, 2.1));
  Eigen::Matrix3d G;
  G << 1.10, 0.05, -0.02, 0.03, 0.95, 0.04, -0.01, 0.02, 1.07;
  const Eigen::Vector3d t(0.3, -0.2, 0.1);
  const Eigen::Matrix3Xd x = (G * model.x0_m).colwise() + t;
  std::vector<Eigen::Matrix3d> F(static_cast<std::size_t>(model.n));
  ComputeDeformationGradients(model, x, F);
  double worst = 0.0;
  for (const auto& Fi : F) worst = std::max(worst, (Fi - G).cwiseAbs().maxCoeff());
  EXPECT_LT(worst, 1e-12);  // entries are O(1): round-off of sums of ~30 terms
}

TEST(Meshless, ARigidMotionHasZeroEnergyAndZeroForce) {
  const MeshlessModel model = BuildMeshlessModel(Block(5, 5, 5, 2.1));
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Matrix3Xd x = (R * model.x0_m).colwise() + Eigen::Vector3d(0.01, 0.02, -0.03);
  std::vector<Eigen::Matrix3d> F(static_cast<std::size_t>(model.n));
  Eigen::Matrix3Xd f(3, model.n);
  const double U = ComputeMeshlessForces(model, x, F, f);
  // Scale: 1 % uniaxial strain stores ~ ½ E e^2 V = ½ 1e5 1e-4 1.25e-7 = 6e-7 J
  // and pushes ~ E e s^2 = 1e-3 N per node.
  EXPECT_LT(std::abs(U), 1e-20);
  EXPECT_LT(f.cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Meshless, ForcesAreMinusTheGradientOfTheStrainEnergy) {
  const MeshlessModel model = BuildMeshlessModel(Block(4, 4, 4, 2.1));
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.05 * kSpacing_m);
  Eigen::Matrix3Xd x = model.x0_m;
  for (Eigen::Index c = 0; c < x.cols(); ++c)
    for (int k = 0; k < 3; ++k) x(k, c) += noise(rng);
  std::vector<Eigen::Matrix3d> F(static_cast<std::size_t>(model.n));
  Eigen::Matrix3Xd f(3, model.n), scratch(3, model.n);
  ComputeMeshlessForces(model, x, F, f);
  // Central differences of the energy (error O(delta^2) relative ~1e-8).
  const double delta = 1e-7 * kSpacing_m;
  double worst_relative = 0.0;
  for (const int node : {0, 21, 42, 63}) {
    for (int k = 0; k < 3; ++k) {
      Eigen::Matrix3Xd xp = x, xm = x;
      xp(k, node) += delta;
      xm(k, node) -= delta;
      const double dU = (ComputeMeshlessForces(model, xp, F, scratch) - ComputeMeshlessForces(model, xm, F, scratch)) /
                        (2.0 * delta);
      worst_relative = std::max(worst_relative, std::abs(-dU - f(k, node)) / f.col(node).norm());
    }
  }
  EXPECT_LT(worst_relative, 1e-5);
}

TEST(Meshless, AFlatSheetOfNodesIsRefusedNamingTheNode) {
  MeshlessDef d = Block(5, 5, 1, 2.1);  // one layer: every moment matrix is singular
  try {
    BuildMeshlessModel(d);
    FAIL() << "a coplanar neighbourhood was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("node 0 has"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("raise the support radius"), std::string::npos);
  }
}

TEST(Meshless, BadParametersAreRefused) {
  for (auto change : std::vector<void (*)(MeshlessDef&)>{
           [](MeshlessDef& d) { d.youngs_modulus_Pa = 0.0; }, [](MeshlessDef& d) { d.poisson_ratio = 0.5; },
           [](MeshlessDef& d) { d.support_radius_m = std::nan(""); }, [](MeshlessDef& d) { d.mass_kg[3] = -1.0; },
           [](MeshlessDef& d) { d.volume_m3.pop_back(); }, [](MeshlessDef& d) { d.x0_m(0, 2) = INFINITY; }}) {
    MeshlessDef d = Block(3, 3, 3, 2.1);
    change(d);
    EXPECT_THROW(BuildMeshlessModel(d), std::invalid_argument);
  }
}

TEST(MlsSurfaceMap, PartitionOfUnityAndLinearReproductionAtRandomPoints) {
  const MeshlessModel model = BuildMeshlessModel(Block(6, 6, 6, 2.1));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> inside(0.0, 6 * kSpacing_m);
  Eigen::Matrix3Xd surface(3, 200);
  for (Eigen::Index v = 0; v < surface.cols(); ++v) surface.col(v) = Eigen::Vector3d(inside(rng), inside(rng), inside(rng));
  const MlsSurfaceMap map = BuildMlsSurfaceMap(model.x0_m, surface, 2.5 * kSpacing_m);
  double worst_sum = 0.0, worst_position_m = 0.0;
  for (Eigen::Index v = 0; v < surface.cols(); ++v) {
    double sum = 0.0;
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (auto k = map.first[static_cast<std::size_t>(v)]; k < map.first[static_cast<std::size_t>(v) + 1]; ++k) {
      sum += map.phi[static_cast<std::size_t>(k)];
      x += map.phi[static_cast<std::size_t>(k)] * model.x0_m.col(map.node[static_cast<std::size_t>(k)]);
    }
    worst_sum = std::max(worst_sum, std::abs(sum - 1.0));
    worst_position_m = std::max(worst_position_m, (x - surface.col(v)).norm());
  }
  EXPECT_LT(worst_sum, 1e-12);
  EXPECT_LT(worst_position_m, 1e-15);  // 1e-12 of the 1 mm spacing
  // An affine motion of the nodes moves every surface point the same way.
  Eigen::Matrix3d G;
  G << 1.2, 0.1, 0.0, -0.05, 0.9, 0.02, 0.0, 0.03, 1.1;
  const Eigen::Vector3d t(1e-3, -2e-3, 5e-4);
  Eigen::Matrix3Xd moved(3, surface.cols());
  MapSurface(map, (G * model.x0_m).colwise() + t, moved);
  const Eigen::Matrix3Xd expected = (G * surface).colwise() + t;
  EXPECT_LT((moved - expected).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(MlsSurfaceMap, CubicSplineWeightIsTheMissionFormulaAndContinuous) {
  // Values from the formula by hand: w(0) = 2/3, w(1/2) = 2/3 - 1 + 1/2 = 1/6
  // from both pieces, w(1) = 0, w(3/4) = 4/3 - 3 + 9/4 - 9/16 = 1/48.
  EXPECT_DOUBLE_EQ(CubicSplineWeight(0.0), 2.0 / 3.0);
  EXPECT_NEAR(CubicSplineWeight(0.5), 1.0 / 6.0, 1e-15);
  EXPECT_NEAR(CubicSplineWeight(std::nextafter(0.5, 1.0)), 1.0 / 6.0, 1e-15);
  EXPECT_NEAR(CubicSplineWeight(0.75), 1.0 / 48.0, 1e-15);
  EXPECT_NEAR(CubicSplineWeight(1.0), 0.0, 1e-15);
  EXPECT_EQ(CubicSplineWeight(1.01), 0.0);
}

TEST(MlsSurfaceMap, AVertexSeeingTooFewNodesIsRefused) {
  const MeshlessModel model = BuildMeshlessModel(Block(3, 3, 3, 2.1));
  Eigen::Matrix3Xd far(3, 1);
  far.col(0) = Eigen::Vector3d(0.1, 0.1, 0.1);  // 10 cm away
  EXPECT_THROW(BuildMlsSurfaceMap(model.x0_m, far, 2e-3), std::invalid_argument);
}

TEST(Meshless, StepAllocatesNothing) {
  const MeshlessModel model = BuildMeshlessModel(Block(4, 4, 4, 2.1));
  MeshlessState state = MakeMeshlessState(model);
  state.f_ext_N.col(5) = Eigen::Vector3d(0, 0, 1e-3);
  hapsim::test::ScopedAllocationCount count;
  for (int k = 0; k < 10; ++k) StepMeshless(model, state, 1e-5);
  EXPECT_EQ(count.Count(), 0u);
}

// Uniaxial tension: a bar of 4 x 4 x 24 nodes, the first layer held in z
// only (free to contract sideways), a total force F spread evenly over the
// last layer, relaxed to rest by damped explicit steps. The strain of the
// middle half, fitted from node positions, gives E = (F / A) / strain with
// A = 4 x 4 s^2. Small strain (0.1 %), so the St. Venant-Kirchhoff law is
// linear to 1e-3. The reference is the material's E; the target tolerance
// is 10 % (checked to 2 %, below), and the figure seen is printed.
TEST(Meshless, UniaxialTensionOfABlockRecoversYoungsModulus) {
  constexpr int kNx = 4, kNy = 4, kNz = 24;
  constexpr double kE_Pa = 1e5, kNu = 0.3;
  MeshlessDef def = Block(kNx, kNy, kNz, 2.1, kE_Pa, kNu);
  const double c_m_per_s = std::sqrt(kE_Pa * (1 - kNu) / ((1 + kNu) * (1 - 2 * kNu)) / kDensity_kg_per_m3);
  const double bar_m = kNz * kSpacing_m;
  // Damping near critical for the bar's first axial mode (omega = pi c / 2L).
  def.damping_per_s = 2.0 * 3.14159265358979 * c_m_per_s / (2.0 * bar_m);
  const MeshlessModel model = BuildMeshlessModel(def);
  MeshlessState state = MakeMeshlessState(model);
  const double area_m2 = kNx * kNy * kSpacing_m * kSpacing_m;
  const double force_N = 1e-3 * kE_Pa * area_m2;  // 0.1 % strain
  const int layer = kNx * kNy;
  for (int i = model.n - layer; i < model.n; ++i) state.f_ext_N(2, i) = force_N / layer;
  const double h_s = 0.2 * kSpacing_m / c_m_per_s;
  for (int step = 0; step < 40000; ++step) {
    StepMeshless(model, state, h_s);
    for (int i = 0; i < layer; ++i) {  // first layer: z held, x and y free
      state.x_m(2, i) = model.x0_m(2, i);
      state.v_m_per_s(2, i) = 0.0;
    }
  }
  // Least-squares slope of u_z against z over the middle half of the bar.
  double sz = 0, su = 0, szz = 0, szu = 0;
  int count = 0;
  for (int i = 0; i < model.n; ++i) {
    const double z = model.x0_m(2, i);
    if (z < 0.25 * bar_m || z > 0.75 * bar_m) continue;
    const double u = state.x_m(2, i) - z;
    sz += z, su += u, szz += z * z, szu += z * u;
    ++count;
  }
  const double strain = (count * szu - sz * su) / (count * szz - sz * sz);
  const double E_measured = force_N / area_m2 / strain;
  // Lateral strain over the same nodes: slope of u_x against x.
  double sx = 0, sux = 0, sxx = 0, sxu = 0;
  for (int i = 0; i < model.n; ++i) {
    const double z = model.x0_m(2, i);
    if (z < 0.25 * bar_m || z > 0.75 * bar_m) continue;
    const double x = model.x0_m(0, i), u = state.x_m(0, i) - x;
    sx += x, sux += u, sxx += x * x, sxu += x * u;
  }
  const double lateral = (count * sxu - sx * sux) / (count * sxx - sx * sx);
  const double nu_measured = -lateral / strain;
  const double speed_left = state.v_m_per_s.cwiseAbs().maxCoeff();
  std::printf("uniaxial tension: E measured %.4g Pa for E = %.4g Pa (ratio %.4f), nu measured %.4f for %.2f, "
              "residual speed %.2e m/s\n",
              E_measured, kE_Pa, E_measured / kE_Pa, nu_measured, kNu, speed_left);
  EXPECT_LT(speed_left, 1e-6);  // at rest: the fit is of a static state
  // The target is 10 %; the model gives 0.6 % here (seen 1.0059), the
  // rest being the one-sided neighbourhoods of the bar's surface nodes, so
  // the check holds it to 2 %.
  EXPECT_NEAR(E_measured / kE_Pa, 1.0, 0.02);
  EXPECT_NEAR(nu_measured, kNu, 0.02);
}

}  // namespace
}  // namespace hapsim::core
