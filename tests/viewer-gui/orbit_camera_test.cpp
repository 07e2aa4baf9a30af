// The camera's projection against the pinhole model written out by hand:
// a point at depth d in front of the eye and offset (a, b) along the
// camera's right and up axes lands at
//   x = W/2 + (a / d) * (H/2) / tan(fov/2),  y = H/2 - (b / d) * (H/2) / tan(fov/2).
#include <array>
#include <cmath>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "hapsim/gui/orbit_camera.h"

namespace hapsim::gui {
namespace {

constexpr double kPi = 3.14159265358979323846;

OrbitCamera Camera() {
  OrbitCamera c;
  c.pose.target_m = Eigen::Vector3d(0.01, -0.02, 0.003);
  c.pose.distance_m = 0.09;
  c.pose.yaw_deg = -30.0;
  c.pose.pitch_deg = 35.0;
  c.pose.fov_y_deg = 40.0;
  return c;
}

TEST(OrbitCamera, TheTargetProjectsToTheImageCentre) {
  const OrbitCamera c = Camera();
  Eigen::Vector2d px;
  ASSERT_TRUE(c.ToPixel(c.pose.target_m, 800, 600, &px));
  EXPECT_NEAR(px.x(), 400.0, 1e-6);
  EXPECT_NEAR(px.y(), 300.0, 1e-6);
}

TEST(OrbitCamera, TheEyeIsAtTheDistanceAndAnglesGiven) {
  const OrbitCamera c = Camera();
  const Eigen::Vector3d d = c.pose.target_m - c.Eye_m();
  EXPECT_NEAR(d.norm(), 0.09, 1e-12);
  // Pitch 35 deg: looking down at 35 deg below the horizon.
  EXPECT_NEAR(std::asin(-d.z() / d.norm()) * 180.0 / kPi, 35.0, 1e-9);
  // Yaw -30 deg about +z from +y: the horizontal part points to (sin, cos)(-30 deg).
  EXPECT_NEAR(std::atan2(d.x(), d.y()) * 180.0 / kPi, -30.0, 1e-9);
}

TEST(OrbitCamera, OffsetPointsFollowThePinholeModel) {
  const OrbitCamera c = Camera();
  const Eigen::Vector3d eye = c.Eye_m();
  const Eigen::Vector3d forward = (c.pose.target_m - eye).normalized();
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d up = right.cross(forward);
  const int w = 800, h = 600;
  const double focal_px = (h / 2.0) / std::tan(20.0 * kPi / 180.0);
  for (const auto& [a, b, d] : {std::array<double, 3>{0.01, 0.0, 0.09}, {-0.004, 0.007, 0.05}, {0.02, -0.01, 0.2}}) {
    const Eigen::Vector3d p = eye + d * forward + a * right + b * up;
    Eigen::Vector2d px;
    ASSERT_TRUE(c.ToPixel(p, w, h, &px));
    EXPECT_NEAR(px.x(), w / 2.0 + a / d * focal_px, 1e-6 * focal_px);
    EXPECT_NEAR(px.y(), h / 2.0 - b / d * focal_px, 1e-6 * focal_px);
  }
}

TEST(OrbitCamera, PointsBehindTheEyeDoNotProject) {
  const OrbitCamera c = Camera();
  const Eigen::Vector3d behind = c.Eye_m() - 0.05 * (c.pose.target_m - c.Eye_m()).normalized();
  Eigen::Vector2d px;
  EXPECT_FALSE(c.ToPixel(behind, 800, 600, &px));
}

TEST(OrbitCamera, FitKeepsEveryCornerOfTheBoxInView) {
  OrbitCamera c = Camera();
  const Eigen::Vector3d lo(-0.03, -0.02, -0.015), hi(0.03, 0.02, 0.002);
  c.Fit(lo, hi);
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d corner((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(), (k & 4) ? hi.z() : lo.z());
    Eigen::Vector2d px;
    ASSERT_TRUE(c.ToPixel(corner, 600, 600, &px));
    EXPECT_GE(px.x(), 0.0);
    EXPECT_LE(px.x(), 600.0);
    EXPECT_GE(px.y(), 0.0);
    EXPECT_LE(px.y(), 600.0);
  }
}

TEST(OrbitCamera, PanningMovesTheTargetByThePixelsDragged) {
  OrbitCamera c = Camera();
  const Eigen::Vector3d before = c.pose.target_m;
  c.Pan(40.0, 0.0, 600.0);  // drag right by 40 px: the scene follows the mouse
  Eigen::Vector2d px;
  ASSERT_TRUE(c.ToPixel(before, 800, 600, &px));
  EXPECT_NEAR(px.x(), 440.0, 1e-6);
  EXPECT_NEAR(px.y(), 300.0, 1e-6);
}

TEST(OrbitCamera, ZoomAndOrbitStayInRange) {
  OrbitCamera c = Camera();
  c.Zoom(1.0);
  EXPECT_NEAR(c.pose.distance_m, 0.081, 1e-12);
  c.Orbit(0.0, 1e6);
  EXPECT_LE(c.pose.pitch_deg, 89.0);
  c.Zoom(-1e4);
  EXPECT_LE(c.pose.distance_m, 100.0);
}

}  // namespace
}  // namespace hapsim::gui
