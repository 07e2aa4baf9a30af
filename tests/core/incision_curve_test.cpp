// The incision curve: cubic Bézier segments (cutting paper eqs. 5-7) that
// pass through every committed blade point, join with a continuous tangent,
// never change once committed, and whose projection finds the closest point
// (against dense sampling).
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "hapsim/core/cutting/incision_curve.h"

namespace hapsim::core {
namespace {

TEST(IncisionCurve, PassesThroughEveryPointWithAContinuousTangent) {
  IncisionCurve c(64);
  std::vector<Eigen::Vector2d> q;
  for (int i = 0; i <= 10; ++i) q.emplace_back(0.002 * i, 0.003 * std::sin(0.4 * i));
  c.Start(q[0]);
  for (std::size_t i = 1; i < q.size(); ++i) ASSERT_TRUE(c.Extend(q[i]));
  ASSERT_EQ(c.Segments(), 10);
  for (int k = 0; k <= 10; ++k) EXPECT_LT((c.Point(k) - q[static_cast<std::size_t>(k)]).norm(), 1e-15) << k;
  for (int k = 1; k < 10; ++k) {  // C1: the same derivative either side of a joint
    const Eigen::Vector2d left = BezierDerivative(c.Controls(k - 1), 1.0), right = BezierDerivative(c.Controls(k), 0.0);
    EXPECT_LT((left - right).norm(), 1e-15 * (1.0 + left.norm())) << k;
  }
  // A straight chain is the straight line, and its length the distance.
  IncisionCurve line(8);
  line.Start({0, 0});
  line.Extend({0.01, 0});
  line.Extend({0.02, 0});
  EXPECT_NEAR(line.Length_m(), 0.02, 1e-15);
  EXPECT_LT(std::abs(line.Point(1.5).y()), 1e-18);
  EXPECT_NEAR(line.Point(1.5).x(), 0.015, 1e-15);
}

TEST(IncisionCurve, ACommittedSegmentNeverChanges) {
  IncisionCurve c(8);
  c.Start({0, 0});
  c.Extend({0.01, 0.002});
  const BezierControls before = c.Controls(0);
  c.Extend({0.015, 0.009});
  EXPECT_EQ(c.Controls(0), before);
}

TEST(IncisionCurve, ProjectionFindsTheClosestPointAndItsSide) {
  IncisionCurve c(16);
  c.Start({0, 0});
  for (int i = 1; i <= 6; ++i) c.Extend({0.003 * i, 0.004 * std::sin(0.5 * i)});
  for (int q = 0; q < 50; ++q) {
    const Eigen::Vector2d p(0.02 * (q % 10) / 10.0 - 0.001, 0.006 * ((q * 7) % 11) / 11.0 - 0.002);
    const auto proj = c.Project(p, 0, c.Segments() - 1);
    double best = 1e9;
    for (int i = 0; i <= 60000; ++i) best = std::min(best, (c.Point(6.0 * i / 60000) - p).norm());
    EXPECT_NEAR(proj.distance_m, best, 1e-9) << "point " << q;
    const Eigen::Vector2d t = c.Tangent(proj.s), r = p - proj.point;
    if (proj.distance_m > 1e-6) {
      EXPECT_EQ(proj.side, t.x() * r.y() - t.y() * r.x() > 0 ? 1 : -1);
    }
  }
}

}  // namespace
}  // namespace hapsim::core
