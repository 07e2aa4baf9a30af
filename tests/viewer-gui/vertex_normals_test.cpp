#include <cmath>

#include <gtest/gtest.h>

#include "hapsim/gui/vertex_normals.h"

namespace hapsim::gui {
namespace {

constexpr float kTol = 1e-6f;  // float rounding of unit vectors

TEST(VertexNormals, ACounterClockwiseSquareInTheXyPlaneFacesPlusZ) {
  const std::vector<float> p = {0, 0, 0, 0.01f, 0, 0, 0.01f, 0.01f, 0, 0, 0.01f, 0};
  std::vector<float> n;
  ComputeVertexNormals(p, {0, 1, 2, 0, 2, 3}, &n);
  ASSERT_EQ(n.size(), p.size());
  for (int v = 0; v < 4; ++v) {
    EXPECT_NEAR(n[3 * v], 0.0f, kTol);
    EXPECT_NEAR(n[3 * v + 1], 0.0f, kTol);
    EXPECT_NEAR(n[3 * v + 2], 1.0f, kTol);
  }
}

TEST(VertexNormals, AnOctahedronsVertexNormalsPointAwayFromItsCentre) {
  // By symmetry each corner's four faces average to the radial direction.
  const std::vector<float> p = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
  const std::vector<std::uint32_t> t = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  std::vector<float> n;
  ComputeVertexNormals(p, t, &n);
  for (int v = 0; v < 6; ++v)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(n[3 * v + k], p[3 * v + k], kTol) << "vertex " << v << " axis " << k;
}

TEST(VertexNormals, LargerFacesWeighMoreByTheirArea) {
  // Vertex 0 joins a 2 x 2 triangle facing +z (area 2) and a 1 x 1 one facing
  // -y (area 0.5): its normal is (0, -0.5, 2) normalised.
  const std::vector<float> p = {0, 0, 0, 2, 0, 0, 0, 2, 0, 1, 0, 0, 0, 0, 1};
  std::vector<float> n;
  ComputeVertexNormals(p, {0, 1, 2, 0, 3, 4}, &n);
  const float length = std::sqrt(0.25f + 4.0f);
  EXPECT_NEAR(n[0], 0.0f, kTol);
  EXPECT_NEAR(n[1], -0.5f / length, kTol);
  EXPECT_NEAR(n[2], 2.0f / length, kTol);
}

TEST(VertexNormals, AnUnusedVertexGetsZeroAndABadIndexIsSkipped) {
  const std::vector<float> p = {0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 5, 5};
  std::vector<float> n;
  ComputeVertexNormals(p, {0, 1, 2, 0, 1, 99}, &n);
  ASSERT_EQ(n.size(), 12u);
  EXPECT_NEAR(n[2], 1.0f, kTol);  // only the good triangle counted
  for (int k = 9; k < 12; ++k) EXPECT_EQ(n[k], 0.0f);
}

}  // namespace
}  // namespace hapsim::gui
