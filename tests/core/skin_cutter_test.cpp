// The three-stage cut on the skin patch: the hole is refilled exactly (rest
// area and mass unchanged), every triangle keeps a positive rest area, the
// mesh stays a consistently oriented manifold, springs join only live
// nodes, wound nodes lie on the incision curve — for straight, curved,
// diagonal and revisiting cuts, and cuts running off the patch.
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <string>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "hapsim/core/cutting/skin_cutter.h"
#include "skin_invariants.h"

namespace hapsim::core {
namespace {

using test::Violation;

SkinDef TestSkin() {
  SkinDef d;
  d.length_m = 0.03;
  d.width_m = 0.02;
  d.spacing_m = 0.001;
  d.areal_density_kg_per_m2 = 20.0;  // 20 mg per 1 mm^2 node
  return d;
}

struct Cut {
  SkinMesh skin = BuildSkinMesh(TestSkin());
  SkinCutter cutter{skin};
  IncisionCurve curve{1024};
  CutStats total;
  // Cuts through the points, one segment each.
  void Through(const std::vector<Eigen::Vector2d>& points) {
    curve.Start(points.front());
    for (std::size_t i = 1; i < points.size(); ++i) {
      if (!curve.Extend(points[i])) continue;
      total += cutter.CutAlongLastSegment(skin, curve, {});
    }
  }
};

std::vector<Eigen::Vector2d> Line(Eigen::Vector2d a, Eigen::Vector2d b, double step_m) {
  const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / step_m)));
  std::vector<Eigen::Vector2d> p;
  for (int i = 0; i <= n; ++i) p.push_back(a + (b - a) * (static_cast<double>(i) / n));
  return p;
}

TEST(SkinCutter, StraightCutRefillsTheHoleExactlyWithWoundNodesOnTheCurve) {
  Cut cut;
  const double area = 0.03 * 0.02;
  ASSERT_EQ(Violation(cut.skin, area, true), "");
  cut.Through(Line({-0.008, 0.0003}, {0.008, 0.0003}, 0.002));
  EXPECT_EQ(Violation(cut.skin, area, true), "");
  EXPECT_FALSE(cut.total.refused);
  EXPECT_EQ(cut.total.skipped_triangles, 0u);
  EXPECT_GT(cut.total.triangles_removed, 30u);
  EXPECT_GT(cut.skin.lip_nodes.size(), 16u);  // two lips along 16 mm at 1 mm spacing
  // Every wound node lies on the curve; the wound's boundary runs along it.
  for (const std::uint32_t v : cut.skin.lip_nodes) {
    const auto p = cut.curve.Project(cut.skin.model.x0_m.col(v).head<2>(), 0, cut.curve.Segments() - 1);
    EXPECT_LT(p.distance_m, 1e-12) << "lip node " << v;
  }
  EXPECT_GE(cut.skin.wound_edges.size(), 2 * 15u);
}

TEST(SkinCutter, CurvedAndDiagonalCutsKeepEveryInvariant) {
  for (const double angle_deg : {0.0, 17.0, 30.0, 45.0, 60.0, 90.0, 133.0}) {
    Cut cut;
    const double a = angle_deg * std::numbers::pi / 180.0;
    std::vector<Eigen::Vector2d> p;
    for (int i = 0; i <= 12; ++i) {  // an arc: direction turns by 40° over the cut
      const double t = i / 12.0, turn = a + 0.7 * t;
      const Eigen::Vector2d at(-0.006 * std::cos(a) + 0.012 * t * std::cos(turn),
                               -0.006 * std::sin(a) + 0.012 * t * std::sin(turn) * 0.8);
      p.push_back(at);
    }
    cut.Through(p);
    EXPECT_EQ(Violation(cut.skin, 0.03 * 0.02, true), "") << "angle " << angle_deg;
    EXPECT_FALSE(cut.total.refused) << "angle " << angle_deg;
  }
}

TEST(SkinCutter, CutsAcrossThePatchBorderAndBackOverAWoundNeverBreakTheMesh) {
  Cut across;
  across.Through(Line({-0.020, 0.002}, {0.0, 0.002}, 0.002));  // starts outside the patch
  EXPECT_EQ(Violation(across.skin, 0.0, false), "");
  Cut revisit;
  revisit.Through(Line({-0.008, 0.0}, {0.008, 0.0}, 0.002));
  revisit.curve.Clear();
  revisit.Through(Line({0.0, -0.006}, {0.0, 0.006}, 0.002));  // a second incision crossing the first
  EXPECT_EQ(Violation(revisit.skin, 0.0, false), "");
  revisit.curve.Clear();
  revisit.Through(Line({-0.008, 0.0}, {0.008, 0.0}, 0.002));  // and along the first again
  EXPECT_EQ(Violation(revisit.skin, 0.0, false), "");
}

TEST(SkinCutter, RandomWalkCutsKeepEveryInvariant) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uint32_t skipped = 0, planned = 0;
  for (int trial = 0; trial < 20; ++trial) {
    Cut cut;
    std::vector<Eigen::Vector2d> p{{0.01 * u(rng), 0.006 * u(rng)}};
    double heading = std::numbers::pi * u(rng);
    for (int i = 0; i < 10; ++i) {
      heading += 0.5 * u(rng);
      p.push_back(p.back() + 0.0015 * Eigen::Vector2d(std::cos(heading), std::sin(heading)));
    }
    cut.Through(p);
    EXPECT_EQ(Violation(cut.skin, 0.0, false), "") << "trial " << trial;
    skipped += cut.total.skipped_triangles;
    planned += cut.total.triangles_added + cut.total.skipped_triangles;
  }
  // Gaps (triangles the cutter could not place soundly, left open) are rare:
  // sharp turns within one segment only.
  EXPECT_LT(static_cast<double>(skipped), 0.02 * static_cast<double>(planned)) << skipped << " of " << planned;
}

TEST(SkinCutter, TheSameCutTwiceGivesTheSameMesh) {
  Cut a, b;
  const auto path = Line({-0.008, 0.0011}, {0.009, -0.0023}, 0.0017);
  a.Through(path);
  b.Through(path);
  EXPECT_EQ(a.skin.model.x0_m, b.skin.model.x0_m);
  EXPECT_EQ(a.skin.model.spring_i, b.skin.model.spring_i);
  EXPECT_EQ(a.skin.model.spring_j, b.skin.model.spring_j);
  EXPECT_EQ(a.skin.topology.LiveTriangleIndices(), b.skin.topology.LiveTriangleIndices());
}

}  // namespace
}  // namespace hapsim::core
