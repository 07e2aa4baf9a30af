#include "hapsim/device_link/pose_filter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

namespace hapsim::service {
namespace {

hapsim_dds_StylusPose GoodPose() {
  hapsim_dds_StylusPose p{};
  std::strcpy(p.session, "s1");
  p.pos_m[2] = 0.01;
  p.quat_wxyz[0] = 1.0;
  return p;
}

TEST(PoseFilter, AcceptsAndNormalisesAGoodPose) {
  auto p = GoodPose();
  p.quat_wxyz[0] = 1.01;  // within tolerance: normalised
  PoseRejection why;
  const auto tool = FilterPose(p, {}, &why);
  ASSERT_TRUE(tool);
  EXPECT_EQ(why, PoseRejection::kNone);
  EXPECT_TRUE(tool->valid);
  EXPECT_NEAR(tool->orientation_W.norm(), 1.0, 1e-15);
  EXPECT_DOUBLE_EQ(tool->tip_W_m.z(), 0.01);
}

TEST(PoseFilter, DropsNonFiniteValues) {
  for (int field = 0; field < 3; ++field) {
    auto p = GoodPose();
    if (field == 0) p.pos_m[1] = std::nan("");
    if (field == 1) p.vel_m_per_s[0] = std::numeric_limits<double>::infinity();
    if (field == 2) p.quat_wxyz[3] = std::nan("");
    PoseRejection why;
    EXPECT_FALSE(FilterPose(p, {}, &why));
    EXPECT_EQ(why, PoseRejection::kNotFinite);
  }
}

TEST(PoseFilter, DropsAbsurdPositionSpeedAndQuaternion) {
  PoseRejection why;
  auto p = GoodPose();
  p.pos_m[0] = 5.0;
  EXPECT_FALSE(FilterPose(p, {}, &why));
  EXPECT_EQ(why, PoseRejection::kPositionOutOfRange);
  p = GoodPose();
  p.vel_m_per_s[2] = -50.0;
  EXPECT_FALSE(FilterPose(p, {}, &why));
  EXPECT_EQ(why, PoseRejection::kSpeedOutOfRange);
  p = GoodPose();
  p.quat_wxyz[0] = 0.0;
  EXPECT_FALSE(FilterPose(p, {}, &why));
  EXPECT_EQ(why, PoseRejection::kBadQuaternion);
}

// docs/protocol.md: a pose "farther than 2 m from the origin" is dropped —
// the distance, not the largest coordinate: (1.5, 1.5, 0) m is 2.12 m away.
TEST(PoseFilter, PositionLimitIsTheDistanceFromTheOrigin) {
  PoseRejection why;
  auto p = GoodPose();
  p.pos_m[0] = 1.5;
  p.pos_m[1] = 1.5;
  p.pos_m[2] = 0.0;
  EXPECT_FALSE(FilterPose(p, {}, &why));
  EXPECT_EQ(why, PoseRejection::kPositionOutOfRange);
  // At the boundary: 2 m exactly is accepted, the next double beyond is not.
  p.pos_m[0] = 1.2;
  p.pos_m[1] = 1.6;  // |(1.2, 1.6, 0)| = 2 (to within one ulp)
  const double d = Eigen::Vector3d(1.2, 1.6, 0.0).norm();  // as the filter computes it
  PoseLimits limits;
  limits.max_distance_m = d;
  EXPECT_TRUE(FilterPose(p, limits, &why));
  limits.max_distance_m = std::nextafter(d, 0.0);
  EXPECT_FALSE(FilterPose(p, limits, &why));
  EXPECT_EQ(why, PoseRejection::kPositionOutOfRange);
}

TEST(PoseFilter, DropsSessionFieldWithoutTerminator) {
  auto p = GoodPose();
  std::memset(p.session, 'x', sizeof p.session);
  PoseRejection why;
  EXPECT_FALSE(FilterPose(p, {}, &why));
  EXPECT_EQ(why, PoseRejection::kBadSession);
  EXPECT_TRUE(SessionIdOf(p.session).empty());
}

}  // namespace
}  // namespace hapsim::service
