#include "hapsim/gui/orbit_camera.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace hapsim::gui {

namespace {
constexpr double kPi = 3.14159265358979323846;
double Rad(double deg) { return deg * kPi / 180.0; }
}  // namespace

Eigen::Vector3d OrbitCamera::Eye_m() const {
  const double yaw = Rad(pose.yaw_deg), pitch = Rad(pose.pitch_deg);
  // Direction from the eye to the target.
  const Eigen::Vector3d forward(std::sin(yaw) * std::cos(pitch), std::cos(yaw) * std::cos(pitch), -std::sin(pitch));
  return pose.target_m - pose.distance_m * forward;
}

Eigen::Matrix4f OrbitCamera::View() const { return ViewD().cast<float>(); }
Eigen::Matrix4f OrbitCamera::Projection(double aspect) const { return ProjectionD(aspect).cast<float>(); }

Eigen::Matrix4d OrbitCamera::ViewD() const {
  const Eigen::Vector3d eye = Eye_m();
  const Eigen::Vector3d f = (pose.target_m - eye).normalized();
  Eigen::Vector3d s = f.cross(Eigen::Vector3d::UnitZ());
  if (s.norm() < 1e-9) s = Eigen::Vector3d::UnitX();  // looking straight down
  s.normalize();
  const Eigen::Vector3d u = s.cross(f);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<1, 3>(0, 0) = s.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  m(0, 3) = -s.dot(eye);
  m(1, 3) = -u.dot(eye);
  m(2, 3) = f.dot(eye);
  return m;
}

Eigen::Matrix4d OrbitCamera::ProjectionD(double aspect) const {
  const double n = Near_m(), f = Far_m();
  const double t = 1.0 / std::tan(Rad(pose.fov_y_deg) / 2.0);
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m(0, 0) = t / aspect;
  m(1, 1) = t;
  m(2, 2) = (f + n) / (n - f);
  m(2, 3) = 2.0 * f * n / (n - f);
  m(3, 2) = -1.0;
  return m;
}

bool OrbitCamera::ToPixel(const Eigen::Vector3d& p_m, int width_px, int height_px, Eigen::Vector2d* pixel) const {
  const Eigen::Vector4d clip =
      ProjectionD(static_cast<double>(width_px) / height_px) * ViewD() * Eigen::Vector4d(p_m.x(), p_m.y(), p_m.z(), 1.0);
  if (clip.w() <= 0.0) return false;
  const Eigen::Vector3d ndc = clip.head<3>() / clip.w();
  if (ndc.z() < -1.0 || ndc.z() > 1.0) return false;
  *pixel = Eigen::Vector2d((ndc.x() + 1.0) * 0.5 * width_px, (1.0 - ndc.y()) * 0.5 * height_px);
  return true;
}

void OrbitCamera::Fit(const Eigen::Vector3d& lo_m, const Eigen::Vector3d& hi_m) {
  pose.target_m = 0.5 * (lo_m + hi_m);
  const double radius = std::max(0.5 * (hi_m - lo_m).norm(), 1e-3);
  pose.distance_m = radius / std::sin(Rad(pose.fov_y_deg) / 2.0);
}

void OrbitCamera::Orbit(double dx_px, double dy_px) {
  pose.yaw_deg = std::fmod(pose.yaw_deg + 0.3 * dx_px, 360.0);
  pose.pitch_deg = std::clamp(pose.pitch_deg + 0.3 * dy_px, -89.0, 89.0);
}

void OrbitCamera::Pan(double dx_px, double dy_px, double height_px) {
  // One pixel moves the target by the width a pixel covers at its distance.
  const double m_per_px = 2.0 * pose.distance_m * std::tan(Rad(pose.fov_y_deg) / 2.0) / std::max(height_px, 1.0);
  const Eigen::Matrix4d view = ViewD();
  const Eigen::Vector3d right = view.block<1, 3>(0, 0).transpose();
  const Eigen::Vector3d up = view.block<1, 3>(1, 0).transpose();
  pose.target_m += m_per_px * (-dx_px * right + dy_px * up);
}

void OrbitCamera::Zoom(double wheel_steps) {
  pose.distance_m = std::clamp(pose.distance_m * std::pow(0.9, wheel_steps), 1e-3, 100.0);
}

}  // namespace hapsim::gui
