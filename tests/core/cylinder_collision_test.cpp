// The cutting paper's cylinder collision, through the uniform-grid broad
// phase, finds exactly the nodes the paper's brute-force test finds — on
// random meshes (jittered grids and point clouds) and random blade poses —
// and the test itself matches its geometric meaning.
#include <random>

#include <gtest/gtest.h>

#include "hapsim/core/cutting/cylinder_collision.h"

namespace hapsim::core {
namespace {

TEST(CylinderCollision, TheTwoAngleAndDistanceTestIsInsideTheFiniteCylinder) {
  const Cylinder c{{0, 0, 0}, {0, 0, 0.01}, 0.001};
  EXPECT_TRUE(InsideCylinder(c, {0.0009, 0, 0.005}));
  EXPECT_FALSE(InsideCylinder(c, {0.0011, 0, 0.005}));        // beyond the radius
  EXPECT_FALSE(InsideCylinder(c, {0.0, 0, -0.0001}));         // angle at p0 > 90°: below the tip
  EXPECT_FALSE(InsideCylinder(c, {0.0, 0, 0.0101}));          // angle at p1 > 90°: past the handle end
  EXPECT_TRUE(InsideCylinder(c, {0.0, 0.0005, 0.0}));         // on the tip's disc: both angles <= 90°
  EXPECT_EQ(ClosestAxisPoint(c, {0.0005, 0, 0.003}), Eigen::Vector3d(0, 0, 0.003));
  EXPECT_EQ(ClosestAxisPoint(c, {0.0005, 0, -0.003}), Eigen::Vector3d(0, 0, 0));  // clamped to the segment
}

TEST(CylinderCollision, GridBroadPhaseFindsExactlyWhatBruteForceFinds) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    // A jittered 60 x 40 skin grid (1 mm), some nodes dead, or a 3-D cloud.
    const bool cloud = trial % 4 == 3;
    Eigen::Matrix3Xd x(3, 2400);
    std::vector<std::uint8_t> live(2400, 1);
    for (int i = 0; i < 2400; ++i) {
      if (cloud) {
        x.col(i) = Eigen::Vector3d(0.03 * u(rng), 0.02 * u(rng), 0.01 * u(rng));
      } else {
        x.col(i) = Eigen::Vector3d(-0.03 + 0.001 * (i % 60), -0.02 + 0.001 * (i / 60), 0.0) +
                   Eigen::Vector3d(3e-4 * u(rng), 3e-4 * u(rng), 2e-3 * u(rng));
      }
      live[static_cast<std::size_t>(i)] = (i % 17) != 0;
    }
    UniformGrid grid(Eigen::AlignedBox3d(Eigen::Vector3d(-0.031, -0.021, -0.005), Eigen::Vector3d(0.031, 0.021, 0.005)),
                     0.002, 2400);
    grid.Build(x, live);
    Cylinder c;
    c.p0_W_m = Eigen::Vector3d(0.03 * u(rng), 0.02 * u(rng), 0.005 * u(rng));
    const Eigen::Vector3d dir = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    c.p1_W_m = c.p0_W_m + (0.002 + 0.02 * std::abs(u(rng))) * dir;
    c.radius_m = 0.0003 + 0.002 * std::abs(u(rng));
    std::vector<std::uint32_t> brute, fast;
    CollideBruteForce(c, x, live, brute);
    CollideWithGrid(c, x, grid, fast);
    ASSERT_EQ(fast, brute) << "trial " << trial;
  }
}

// The cutting scene's broad phase: a grid of the rest positions, queried
// with the largest displacement since; the same answer as brute force on
// the displaced positions, including displacements of several cells.
TEST(CylinderCollision, RestGridWithTheLargestShiftFindsExactlyWhatBruteForceFinds) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Matrix3Xd rest(3, 2400);
  std::vector<std::uint8_t> live(2400, 1);
  for (int i = 0; i < 2400; ++i) {
    rest.col(i) = Eigen::Vector3d(-0.03 + 0.001 * (i % 60), -0.02 + 0.001 * (i / 60), 0.0);
    live[static_cast<std::size_t>(i)] = (i % 13) != 0;
  }
  UniformGrid grid(Eigen::AlignedBox3d(Eigen::Vector3d(-0.031, -0.021, -0.005), Eigen::Vector3d(0.031, 0.021, 0.005)),
                   0.002, 2400);
  grid.Build(rest, live);
  int hits = 0;
  for (int trial = 0; trial < 200; ++trial) {
    // Smooth displacement field up to a few mm (a pressed or stretched skin).
    const double amp = 0.006 * std::abs(u(rng));
    const Eigen::Vector3d k(400 * u(rng), 400 * u(rng), 0.0);
    Eigen::Matrix3Xd x = rest;
    double max_shift = 0.0;
    for (int i = 0; i < 2400; ++i) {
      const double phase = k.dot(rest.col(i));
      x.col(i) += amp * Eigen::Vector3d(std::sin(phase), std::cos(1.3 * phase), 0.5 * std::sin(0.7 * phase));
      if (live[static_cast<std::size_t>(i)]) max_shift = std::max(max_shift, (x.col(i) - rest.col(i)).norm());
    }
    Cylinder c;
    c.p0_W_m = Eigen::Vector3d(0.03 * u(rng), 0.02 * u(rng), 0.003 * u(rng));
    const Eigen::Vector3d dir = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    c.p1_W_m = c.p0_W_m + (0.002 + 0.02 * std::abs(u(rng))) * dir;
    c.radius_m = 0.0003 + 0.002 * std::abs(u(rng));
    std::vector<std::uint32_t> brute, fast;
    CollideBruteForce(c, x, live, brute);
    CollideWithShiftedGrid(c, x, grid, max_shift, fast);
    ASSERT_EQ(fast, brute) << "trial " << trial;
    hits += static_cast<int>(brute.size());
  }
  EXPECT_GT(hits, 200);  // the poses do find nodes
}

TEST(UniformGrid, RadiusQueriesFindExactlyThePointsWithinTheRadius) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Matrix3Xd x(3, 1000);
  for (int i = 0; i < 1000; ++i) x.col(i) = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.01;
  x.col(7) = Eigen::Vector3d(1.0, 1.0, 1.0);  // far outside the box: clamped into a border cell, still found
  UniformGrid grid(Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-0.01), Eigen::Vector3d::Constant(0.01)), 0.002, 1000);
  grid.Build(x);
  EXPECT_EQ(grid.Points(), 1000u);
  for (int q = 0; q < 100; ++q) {
    const Eigen::Vector3d p = q == 0 ? Eigen::Vector3d(1.0, 1.0, 1.0) : Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.01;
    const double r = 0.001 + 0.003 * std::abs(u(rng));
    std::vector<std::uint32_t> found, want;
    grid.ForEachWithin(x, p, r, [&](std::uint32_t i) { found.push_back(i); });
    for (std::uint32_t i = 0; i < 1000; ++i)
      if ((x.col(i) - p).norm() <= r) want.push_back(i);
    std::sort(found.begin(), found.end());
    EXPECT_EQ(found, want) << "query " << q;
  }
  EXPECT_THROW(UniformGrid(Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()), 0.0, 10),
               std::invalid_argument);
}

}  // namespace
}  // namespace hapsim::core
