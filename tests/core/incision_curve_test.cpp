// The incision curve: cubic Bézier segments (cutting paper eqs. 5-7) that
// pass through every committed blade point, join with a continuous tangent,
// never change once committed, and whose projection finds the closest point
// (against dense sampling).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

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

// de Casteljau's construction: repeated linear interpolation, an evaluation
// of eq. 5 that shares nothing with the Bernstein sums of eq. 7.
Eigen::Vector2d DeCasteljau(const BezierControls& p, double a) {
  Eigen::Vector2d q[4] = {p[0], p[1], p[2], p[3]};
  for (int level = 3; level > 0; --level)
    for (int i = 0; i < level; ++i) q[i] = (1.0 - a) * q[i] + a * q[i + 1];
  return q[0];
}

// dP/da of a cubic is 3 x the quadratic Bézier of the control differences
// (the hodograph), evaluated by de Casteljau as well.
Eigen::Vector2d HodographDeCasteljau(const BezierControls& p, double a) {
  Eigen::Vector2d q[3] = {3.0 * (p[1] - p[0]), 3.0 * (p[2] - p[1]), 3.0 * (p[3] - p[2])};
  for (int level = 2; level > 0; --level)
    for (int i = 0; i < level; ++i) q[i] = (1.0 - a) * q[i] + a * q[i + 1];
  return q[0];
}

// On a curved chain with uneven steps (so P1 - P0 and P3 - P2 differ and
// swapping B1 and B2 would move the curve), every segment's Bernstein form
// agrees with de Casteljau to rounding: 1e-16 m on a curve ~1e-2 m across
// (a few ulp of the coordinates), its derivative to 1e-16 of |P'|.
TEST(IncisionCurve, BernsteinFormAgreesWithDeCasteljauOnACurvedUnevenChain) {
  IncisionCurve c(64);
  std::vector<Eigen::Vector2d> q;
  double angle = 0.0, radius = 0.0;
  for (int i = 0; i <= 12; ++i) {
    angle += 0.15 + 0.05 * (i % 3);     // uneven turns
    radius += 0.0008 + 0.0004 * (i % 2);  // uneven steps along a spiral
    q.emplace_back(radius * std::cos(angle), radius * std::sin(angle));
  }
  c.Start(q[0]);
  for (std::size_t i = 1; i < q.size(); ++i) ASSERT_TRUE(c.Extend(q[i]));
  double worst_point_m = 0.0, worst_derivative = 0.0, asymmetry_m = 0.0;
  for (int k = 0; k < c.Segments(); ++k) {
    const BezierControls& p = c.Controls(k);
    asymmetry_m = std::max(asymmetry_m, ((p[1] - p[0]) + (p[3] - p[2])).norm());  // 0 only if B1/B2-symmetric
    for (int i = 0; i <= 100; ++i) {
      const double a = i / 100.0;
      worst_point_m = std::max(worst_point_m, (BezierPoint(p, a) - DeCasteljau(p, a)).norm());
      worst_point_m = std::max(worst_point_m, (c.Point(k + a) - DeCasteljau(p, a)).norm() * (i < 100));
      const Eigen::Vector2d d = HodographDeCasteljau(p, a);
      worst_derivative = std::max(worst_derivative, (BezierDerivative(p, a) - d).norm() / d.norm());
    }
  }
  EXPECT_GT(asymmetry_m, 1e-4);  // the chain really tells B1 from B2
  EXPECT_LT(worst_point_m, 1e-16);
  EXPECT_LT(worst_derivative, 1e-15);
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
