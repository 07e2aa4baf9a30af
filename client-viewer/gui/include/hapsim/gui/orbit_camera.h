// The viewer's camera: it orbits a target point at a distance, looking at
// it from a yaw (about world +z, 0 = looking along +y) and a pitch (above the
// x-y plane, + looks down). Pure math (no GL), so tests can project a known
// point to the pixel a picture must show it at. World units are metres,
// z up (the tissue's top surface is z = 0, as in the scenes).
#pragma once
#include <Eigen/Core>

namespace hapsim::gui {

struct CameraPose {
  Eigen::Vector3d target_m = Eigen::Vector3d::Zero();
  double distance_m = 0.1;
  double yaw_deg = -30.0;
  double pitch_deg = 35.0;
  double fov_y_deg = 40.0;
};

class OrbitCamera {
 public:
  CameraPose pose;

  // Frames the box [lo, hi] from the current yaw and pitch.
  void Fit(const Eigen::Vector3d& lo_m, const Eigen::Vector3d& hi_m);
  // Mouse drags in pixels of a viewport height_px high.
  void Orbit(double dx_px, double dy_px);
  void Pan(double dx_px, double dy_px, double height_px);
  void Zoom(double wheel_steps);  // + zooms in

  Eigen::Vector3d Eye_m() const;
  Eigen::Matrix4f View() const;  // for GL (float); computed in double
  Eigen::Matrix4f Projection(double aspect) const;
  Eigen::Matrix4d ViewD() const;
  Eigen::Matrix4d ProjectionD(double aspect) const;
  // Pixel (x right, y down from the top-left corner) of a world point, and
  // false when it is behind the camera or outside the depth range.
  bool ToPixel(const Eigen::Vector3d& p_m, int width_px, int height_px, Eigen::Vector2d* pixel) const;

  double Near_m() const { return pose.distance_m * 0.01; }
  double Far_m() const { return pose.distance_m * 20.0; }
};

}  // namespace hapsim::gui
