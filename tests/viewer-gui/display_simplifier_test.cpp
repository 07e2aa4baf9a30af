#include <cmath>
#include <set>

#include <gtest/gtest.h>

#include "hapsim/gui/display_simplifier.h"

namespace hapsim::gui {
namespace {

// An n x n sheet of side L = 60 mm in the xy-plane (z = 0), wound
// counter-clockwise seen from +z; the left half part 0, the right half part 1.
struct Sheet {
  std::vector<float> positions_m;
  std::vector<std::uint32_t> triangles;
  std::vector<std::uint16_t> parts;
};
constexpr double kSide_m = 0.06;
Sheet MakeSheet(int n) {
  Sheet s;
  for (int iy = 0; iy < n; ++iy)
    for (int ix = 0; ix < n; ++ix)
      s.positions_m.insert(s.positions_m.end(), {static_cast<float>(kSide_m * ix / (n - 1)),
                                                 static_cast<float>(kSide_m * iy / (n - 1)), 0.0f});
  for (int iy = 0; iy + 1 < n; ++iy)
    for (int ix = 0; ix + 1 < n; ++ix) {
      const auto v = static_cast<std::uint32_t>(ix + n * iy), nu = static_cast<std::uint32_t>(n);
      s.triangles.insert(s.triangles.end(), {v, v + 1, v + nu + 1, v, v + nu + 1, v + nu});
      const std::uint16_t part = 2 * ix < n - 1 ? 0 : 1;
      s.parts.insert(s.parts.end(), {part, part});
    }
  return s;
}

// Signed area (z of the cross product / 2) of triangle t of a list.
double SignedAreaZ(const std::vector<float>& p, const std::vector<std::uint32_t>& tri, std::size_t t) {
  const std::uint32_t a = tri[3 * t], b = tri[3 * t + 1], c = tri[3 * t + 2];
  const double e1x = p[3 * b] - p[3 * a], e1y = p[3 * b + 1] - p[3 * a + 1];
  const double e2x = p[3 * c] - p[3 * a], e2y = p[3 * c + 1] - p[3 * a + 1];
  return 0.5 * (e1x * e2y - e1y * e2x);
}

TEST(DisplaySimplifier, AMeshWithinTheBudgetIsDrawnAsItIs) {
  const Sheet s = MakeSheet(11);  // 200 triangles
  const CoarseTriangles out = SimplifyToBudget(s.positions_m, s.triangles, s.parts, 200);
  EXPECT_EQ(out.cell_m, 0.0);
  EXPECT_EQ(out.vertices, s.triangles);
  EXPECT_EQ(out.parts, s.parts);
  EXPECT_EQ(SimplifyToBudget(s.positions_m, s.triangles, s.parts, 0).vertices, s.triangles);  // 0: no budget
}

TEST(DisplaySimplifier, AFineSheetFitsTheBudgetAndStillCoversItsAreaFacingTheSameWay) {
  const Sheet s = MakeSheet(151);  // 45 000 triangles, 0.4 mm apart
  const std::size_t budget = 10000;
  const CoarseTriangles out = SimplifyToBudget(s.positions_m, s.triangles, s.parts, budget);
  ASSERT_GT(out.cell_m, 0.0);
  EXPECT_LE(out.parts.size(), budget);
  EXPECT_GT(out.parts.size(), budget / 2) << "the smallest cell that fits, not a far coarser one";
  double area = 0.0;
  for (std::size_t t = 0; t < out.parts.size(); ++t) {
    const std::uint32_t a = out.vertices[3 * t], b = out.vertices[3 * t + 1], c = out.vertices[3 * t + 2];
    ASSERT_TRUE(a != b && b != c && a != c);
    ASSERT_LT(std::max({a, b, c}), s.positions_m.size() / 3);
    const double signed_area = SignedAreaZ(s.positions_m, out.vertices, t);
    EXPECT_GE(signed_area, 0.0) << "triangle " << t << " flipped";  // winding kept (0: collapsed to a sliver)
    area += signed_area;
  }
  // Each vertex moves to a vertex of its own cell, so the border retreats by
  // less than one cell diagonal in x and y (h sqrt 2) and no triangle overlaps
  // another (all face +z, none flipped): (L - 2 h sqrt 2)^2 <= area <= L^2.
  const double h = out.cell_m, inner = kSide_m - 2.0 * h * std::sqrt(2.0);
  EXPECT_GE(area, inner * inner);
  EXPECT_LE(area, kSide_m * kSide_m * (1 + 1e-6));
}

TEST(DisplaySimplifier, KeptTrianglesKeepTheirPart) {
  const Sheet s = MakeSheet(101);
  const CoarseTriangles out = SimplifyToBudget(s.positions_m, s.triangles, s.parts, 4000);
  std::set<std::uint16_t> seen(out.parts.begin(), out.parts.end());
  EXPECT_EQ(seen, (std::set<std::uint16_t>{0, 1}));
  for (std::size_t t = 0; t < out.parts.size(); ++t) {
    // The left half (part 0) ends at x = 30 mm; its coarse triangles may
    // reach at most one cell diagonal past it.
    const double limit_m = 0.03 + out.cell_m * std::sqrt(3.0);
    if (out.parts[t] != 0) continue;
    for (int k = 0; k < 3; ++k) EXPECT_LE(s.positions_m[3 * out.vertices[3 * t + k]], limit_m);
  }
}

TEST(DisplaySimplifier, ACellMergesOntoTheVertexNearestItsCentre) {
  // Three vertices in cell [0, 1)^3 (x 0.1, 0.45, 0.9) and two beyond; the
  // triangle (0, 1, 3) keeps vertex 1 (nearest the centre 0.5) and (0, 2, 4)
  // collapses onto the same vertex as (1, ...).
  const std::vector<float> p = {0.1f, 0.5f, 0.5f, 0.45f, 0.5f, 0.5f, 0.9f, 0.5f, 0.5f, 0.5f, 1.5f, 0.5f, 1.5f, 0.5f, 0.5f};
  const CoarseTriangles out = ClusterVertices(p, {0, 3, 4, 2, 3, 4, 0, 1, 2}, {0, 0, 0}, 1.0);
  ASSERT_EQ(out.parts.size(), 2u);  // the third has all three corners in one cell
  EXPECT_EQ(out.vertices, (std::vector<std::uint32_t>{1, 3, 4, 1, 3, 4}));
}

}  // namespace
}  // namespace hapsim::gui
