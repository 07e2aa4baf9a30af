// Vessel generators: the wall's node volumes add up to the tube's volume
// (Pappus for the bent ones), every node lies in the wall, the ends are
// anchored, the display surface is closed, and each shape gives a meshless
// model and an MLS surface map that build.
#include <cmath>
#include <map>

#include <gtest/gtest.h>

#include "hapsim/core/meshless/meshless_model.h"
#include "hapsim/core/meshless/mls_surface_map.h"
#include "hapsim/core/scenes/vessel/vessel_geometry.h"

namespace hapsim::core {
namespace {

constexpr double kPi = 3.14159265358979323846;

VesselGeometryDef Shape(VesselShape shape) {
  VesselGeometryDef d;
  d.shape = shape;
  if (shape != VesselShape::kStraight) {
    d.bend_radius_m = 6e-3;
    d.bend_angle_rad = kPi / 3;
  }
  return d;
}

class VesselShapes : public ::testing::TestWithParam<VesselShape> {};

TEST_P(VesselShapes, NodeVolumesAddUpToTheTubeVolume) {
  const VesselGeometryDef d = Shape(GetParam());
  const VesselGeometry g = GenerateVessel(d);
  double sum = 0.0;
  for (const double v : g.node_volume_m3) sum += v;
  const double r_out = d.lumen_radius_m + d.wall_thickness_m;
  const double expected = d.length_m * kPi * (r_out * r_out - d.lumen_radius_m * d.lumen_radius_m);
  // The ring's polygon is not the circle: the shares use the exact annulus
  // sector areas, so only round-off remains.
  EXPECT_NEAR(sum / expected, 1.0, 1e-12);
}

TEST_P(VesselShapes, EveryNodeLiesInTheWallAndOnlyTheEndsAreAnchored) {
  const VesselGeometryDef d = Shape(GetParam());
  const VesselGeometry g = GenerateVessel(d);
  const double r_out = d.lumen_radius_m + d.wall_thickness_m;
  int anchored = 0;
  for (Eigen::Index i = 0; i < g.nodes_m.cols(); ++i) {
    const int station = static_cast<int>(i / (g.layers * g.ring));
    const double r = (g.nodes_m.col(i) - g.centreline_m.col(station)).norm();
    ASSERT_GE(r, d.lumen_radius_m - 1e-12);
    ASSERT_LE(r, r_out + 1e-12);
    anchored += g.anchored[static_cast<std::size_t>(i)];
  }
  EXPECT_EQ(anchored, 2 * g.layers * g.ring);
  // Top of the tube at z = 0, centreline centred on the origin in x-y.
  EXPECT_NEAR(g.nodes_m.row(2).maxCoeff(), 0.0, 1e-12);
  const Eigen::Vector3d lo = g.centreline_m.rowwise().minCoeff(), hi = g.centreline_m.rowwise().maxCoeff();
  EXPECT_NEAR(lo.x() + hi.x(), 0.0, 1e-12);
  EXPECT_NEAR(lo.y() + hi.y(), 0.0, 1e-12);
  // Consecutive stations one spacing apart along the centreline (chord of an
  // arc is a little shorter).
  for (int k = 0; k + 1 < g.stations; ++k) {
    const double chord = (g.centreline_m.col(k + 1) - g.centreline_m.col(k)).norm();
    ASSERT_NEAR(chord, d.length_m / (g.stations - 1), 1e-3 * d.node_spacing_m);
  }
}

TEST_P(VesselShapes, TheDisplaySurfaceIsClosedAndEveryEdgeHasTwoTriangles) {
  const VesselGeometry g = GenerateVessel(Shape(GetParam()));
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const auto& t : g.triangles)
    for (int e = 0; e < 3; ++e) ++directed[{t[e], t[(e + 1) % 3]}];
  for (const auto& [edge, count] : directed) {
    ASSERT_EQ(count, 1) << "edge used twice in one direction";
    ASSERT_EQ(directed.count({edge.second, edge.first}), 1u) << "boundary edge: the surface is open";
  }
}

TEST_P(VesselShapes, MeshlessModelAndSurfaceMapBuild) {
  const VesselGeometryDef d = Shape(GetParam());
  const VesselGeometry g = GenerateVessel(d);
  MeshlessDef m;
  m.x0_m = g.nodes_m;
  m.volume_m3 = g.node_volume_m3;
  for (const double v : g.node_volume_m3) m.mass_kg.push_back(1050.0 * v);
  m.fixed = g.anchored;
  m.support_radius_m = 2.1 * d.node_spacing_m;
  m.youngs_modulus_Pa = 1e5;
  m.poisson_ratio = 0.45;
  const MeshlessModel model = BuildMeshlessModel(m);
  EXPECT_GE(model.fewest_neighbours, 8);
  const MlsSurfaceMap map = BuildMlsSurfaceMap(g.nodes_m, g.surface_m, 2.1 * d.node_spacing_m);
  Eigen::Matrix3Xd mapped(3, g.surface_m.cols());
  MapSurface(map, g.nodes_m, mapped);
  EXPECT_LT((mapped - g.surface_m).cwiseAbs().maxCoeff(), 1e-15);  // linear reproduction at rest
}

INSTANTIATE_TEST_SUITE_P(AllShapes, VesselShapes,
                         ::testing::Values(VesselShape::kStraight, VesselShape::kBent, VesselShape::kTwiceBent));

TEST(VesselGeometry, BadDefinitionsAreRefused) {
  for (auto change : std::vector<void (*)(VesselGeometryDef&)>{
           [](VesselGeometryDef& d) { d.radial_layers = 1; }, [](VesselGeometryDef& d) { d.lumen_radius_m = 0; },
           [](VesselGeometryDef& d) { d.node_spacing_m = 1e-7; },  // millions of nodes
           [](VesselGeometryDef& d) { d.bend_radius_m = 1e-3; },   // tighter than the outer radius
           [](VesselGeometryDef& d) { d.bend_angle_rad = 4.0; }, [](VesselGeometryDef& d) { d.length_m = 0.005; }}) {
    VesselGeometryDef d = Shape(VesselShape::kBent);
    change(d);
    EXPECT_THROW(GenerateVessel(d), std::invalid_argument);
  }
}

}  // namespace
}  // namespace hapsim::core
